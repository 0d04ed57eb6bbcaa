"""Properties of the braking curves (seed 000 §2.4, 002 §3.2; docs/design.md reference formulas).

Proved over the node :data:`~atcs.model.curves.CURVES` with the target, the query
speed and acceleration, the front, the true speed and the breakpoints of a
2-segment compensated gradient profile symbolic; train and national data fixed
to the seed presets (``fixed_params``), one property per preset, and the gradient
values fixed to a design case, 40 per mille downhill then 40 uphill
(:data:`~atcs.model.train_data.DESIGN_GRADIENTS_PERMILLE`). A third preset, ``stepped``, is the seed 000
train with a three-step emergency brake (:data:`STEPPED_EMERGENCY_BRAKE`, over the
node :data:`~atcs.model.curves.STEPPED_CURVES`), so the walk's cells over speed are
proved about too. With symbolic gradient values the walk
divides by a symbolic deceleration and z3 answers unknown.
"""

from __future__ import annotations

import dataclasses
from fractions import Fraction

from atcs.model.braking_data import curve_national_data, curve_train_data
from atcs.model.curves import (
    A_EST2_CAP_MPS2,
    CONVERTED_CURVES,
    CURVES,
    FAR_M,
    GUIDANCE_CURVES,
    STEPPED_CURVES,
    CurveLocations,
    Target,
    bec_speed_and_distance,
    bec_train_speed_mps,
    curve_gradient,
    curve_locations,
    curve_target,
    ebd_location_m,
    gui_location_m,
    sbd_location_m,
)
from atcs.model.node import as_dict
from atcs.model.prepared_curves import (
    PREPARED_CONVERTED_CURVES,
    PREPARED_CURVES,
    PREPARED_STEPPED_CURVES,
    TABLE_ORDER,
    TABLE_ORDER_CONVERTED,
    TABLE_ORDER_STEPPED,
    braking_table,
)
from atcs.model.profile import KMH_PER_MPS, MAX_SPEED_KMH, is_well_formed
from atcs.model.train_data import (
    DESIGN_GRADIENTS_PERMILLE,
    seed000_train,
    seed002_national,
    seed002_train,
    subset026_national,
)
from atcs.model.train_files import load_train, shipped_trains
from atcs.properties.property import Assumption, Property

MAX_GRADIENT_PERMILLE = 40
"""Gradients covered by the curve proofs: [-40, 40] per mille (steeper than any metro line)."""

MAX_LINE_M = 1_000_000
"""Longest line covered (m)."""

"""The compensated gradient values the curve proofs fix: steepest downhill, then steepest uphill."""

STEPPED_EMERGENCY_BRAKE = {
    "emergency_speeds_mps": tuple(Fraction(v) / KMH_PER_MPS for v in (0, 50, 90)),
    "emergency_decelerations_mps2": tuple(Fraction(a) / KMH_PER_MPS for a in (4, Fraction(7, 2), 3)),
}
"""A design case of the speed-step braking model (seed 000 §2.3 ``Dec(v)``, Subset-026 3.13.2.2.4): the seed 000
train's emergency brake at 4.0 km/h/s up to 50 km/h, 3.5 km/h/s up to 90 km/h and 3.0 km/h/s above (the presets
have one step; three steps give the walk a middle step, with a step on either side)."""

DESIGN_NORMAL_SERVICE = {
    "normal_service_speeds_mps": (Fraction(0), Fraction(60) / KMH_PER_MPS),
    "normal_service_decelerations_mps2": (Fraction("0.6"), Fraction("0.5")),
    "kn_plus_mps2": (Fraction(3), Fraction(2)),
    "kn_minus_mps2": (Fraction(5), Fraction(4)),
}
"""A design case of the normal service brake (Subset-026 §3.13.2.2.3.1.9, §3.13.2.2.9.2): A_brake_normal_service
0.6 m/s^2 up to 60 km/h and 0.5 above, Kn+ 3 then 2 m/s^2, Kn- 5 then 4 (two steps each, distinct, so a swapped
or dropped correction shows on either gradient)."""

GUIDANCE_PRESETS = ("seed000", "gamma")
"""The presets whose guidance curve is proved (with :data:`DESIGN_NORMAL_SERVICE`; the node has one-step brakes)."""

_DESIGN_TRACK = {"gradient_permille": tuple(Fraction(g) for g in DESIGN_GRADIENTS_PERMILLE)}
PRESETS = {
    "seed000": {**as_dict(seed000_train()), **as_dict(subset026_national()), **_DESIGN_TRACK},
    "seed002": {**as_dict(seed002_train()), **as_dict(seed002_national()), **_DESIGN_TRACK},
    "stepped": {
        **as_dict(seed000_train()),
        **as_dict(subset026_national()),
        **_DESIGN_TRACK,
        **STEPPED_EMERGENCY_BRAKE,
    },
}
"""The fixed parameters of each preset's curve proofs: the seeds' trains, the seed 000 train with a
three-step emergency brake, and the Gamma and Lambda trains of the ERA tool's reference frames from their train
data files (``model/trains``), derived as Subset-026 states it (:func:`~atcs.model.braking_data.curve_train_data`:
the correction factors in the deceleration steps, the Lambda train's through the conversion model; T_bs2 and
T_indication by the interface rules), for a target at standstill."""


def _subset026_preset(name: str) -> dict:
    train, national = load_train(shipped_trains()[name]), subset026_national()
    return {
        **as_dict(curve_train_data(train, national, 0)),
        **as_dict(curve_national_data(train, national, 0)),
        **_DESIGN_TRACK,
    }


PRESETS["gamma"] = _subset026_preset("gamma_passenger_P")
PRESETS["lambda"] = _subset026_preset("lambda_passenger_P_100")


def _track_and_target(o, p, s, i):
    g = curve_gradient(p)
    bound = o.const(MAX_GRADIENT_PERMILLE)
    return o.and_(
        is_well_formed(o, g),
        *(o.and_(-bound <= v, v <= bound) for v in g.values),
        o.const(0) <= p.target_m,
        p.target_m <= p.line_end_m,
        p.line_end_m <= o.const(MAX_LINE_M),
        o.const(0) <= p.target_speed_mps,
        p.target_speed_mps <= p.target_ebd_foot_mps,
    )


TRACK_AND_TARGET = Assumption(
    "track_and_target",
    f"the compensated gradient profile starts at 0 with increasing breakpoints up to the line end (at most "
    f"{MAX_LINE_M} m), gradients within +-{MAX_GRADIENT_PERMILLE} per mille; the target lies on the line, "
    "its speed >= 0 and at most the EBD's foot speed",
    _track_and_target,
)

QUERY = Assumption(
    "query",
    "speed >= 0, estimated acceleration within [-A_max, A_max]",
    lambda o, p, s, i: o.and_(
        i.speed_mps >= o.const(0),
        -p.max_acceleration_mps2 <= i.a_est_mps2,
        i.a_est_mps2 <= p.max_acceleration_mps2,
    ),
)


SPEED_PAIR = Assumption(
    "speed_pair",
    "both speeds >= 0",
    lambda o, p, s, i: o.and_(i.slower_mps >= o.const(0), i.faster_mps >= o.const(0)),
)


def _ordered(o, p, s, i, out, nxt):
    return o.and_(
        out.indication_m <= out.permitted_m,
        out.permitted_m <= out.warning_m,
        out.warning_m <= out.sbi_m,
        out.sbi_m <= out.ebi_m,
        out.ebi_m <= out.ebd_m,
    )


def _spaced(o, p, s, i, out, nxt):
    v = i.speed_mps
    return o.and_(
        o.eq(out.ebi_m - out.sbi_m, v * p.t_bs_s),
        o.eq(out.sbi_m - out.warning_m, v * p.t_warning_s),
        o.eq(out.sbi_m - out.permitted_m, v * p.t_driver_s),
        o.eq(out.permitted_m - out.indication_m, v * p.t_indication_s),
    )


def _ebi_protects_ebd(o, p, s, i, out, nxt):
    """At or behind the EBI, the worst case until the brake is effective stays behind the EBD."""
    zero = o.const(0)
    accuracy = o.ite(p.inhibit_speed_inaccuracy, zero, p.v_ura_mps)
    t_rem = o.max(zero, p.t_be_s - p.t_traction_s)
    a_traction = o.max(zero, i.a_est_mps2)
    a_build_up = o.min(a_traction, o.const("0.4"))
    v_cut = i.true_speed_mps + a_traction * p.t_traction_s  # speed when traction is cut
    v_brake = v_cut + a_build_up * t_rem  # speed when the brake is effective
    distance = (i.true_speed_mps + v_cut) / o.const(2) * p.t_traction_s + (v_cut + v_brake) / o.const(2) * t_rem
    measured = o.and_(
        i.true_speed_mps >= zero, i.true_speed_mps - i.speed_mps <= accuracy, i.speed_mps - i.true_speed_mps <= accuracy
    )
    ebd = ebd_location_m(o, p, p, curve_gradient(p), curve_target(p), v_brake)
    return o.implies(o.and_(measured, i.front_m <= out.ebi_m), i.front_m + distance <= ebd)


def seed_gradient_acceleration_mps2(o, p, g):
    """``g * gradient / (1000 + 10 * M_rotating)``, the mass by the gradient's sign, stated from the seed."""
    mass = o.ite(g > o.const(0), p.rotating_mass_uphill_percent, p.rotating_mass_downhill_percent)
    return o.const("9.81") * g / (o.const(1000) + o.const(10) * mass)


def _energy_by_speed_step(o, p, v, foot, location, speeds, decelerations, factor, kn=None):
    """Speed step by speed step of a brake model (``[V_b, V_b+1)``, the last one unbounded): between the curve's
    locations at the step's two ends (clamped to [foot speed, v]), ``hi^2 - lo^2 = 2 * sum over the gradient
    segments of (factor * A_brake(b) + A_gradient) times the length of the segment between them``, A_gradient
    stated from the seed. The first segment extends behind the profile's start, the last beyond the line's end.
    With ``kn = (Kn+, Kn-)`` (the normal service brake), ``Kn+(b) * grad / 1000`` is taken from each uphill
    segment's deceleration and ``Kn-(b) * grad / 1000`` from each downhill one's (Subset-026 §3.13.6.4.3)."""
    starts = p.gradient_starts_m

    def work(b, a_brake, behind, ahead):
        total = o.const(0)
        for j, g in enumerate(p.gradient_permille):
            low = behind if j == 0 else o.max(behind, starts[j])
            high = ahead if j + 1 == len(starts) else o.min(ahead, starts[j + 1])
            a = factor * a_brake + seed_gradient_acceleration_mps2(o, p, g)
            if kn is not None:
                a = a - o.ite(g > o.const(0), kn[0][b], kn[1][b]) * g / o.const(1000)
            total = total + a * o.max(o.const(0), high - low)
        return total

    energy = []
    for b, a_brake in enumerate(decelerations):

        def clamp(speed, b=b):
            speed = o.max(speed, speeds[b])
            return speed if b + 1 == len(speeds) else o.min(speed, speeds[b + 1])

        lo, hi = clamp(foot), clamp(v)
        energy.append(o.eq(hi * hi - lo * lo, o.const(2) * work(b, a_brake, location(hi), location(lo))))
    return energy


def _ebd_is_braking_curve(o, p, s, i, out, nxt):
    """The EBD is the braking curve at ``A_safe = K * A_brake_emergency + A_gradient`` from its foot speed at the
    target (:func:`_energy_by_speed_step`); a speed at or below the foot speed is reached at the target."""
    v, foot, target = i.speed_mps, p.target_ebd_foot_mps, p.target_m
    k = p.kdry_rst * (p.kwet_rst + p.m_nvavadh * (o.const(1) - p.kwet_rst))
    gradient, aim = curve_gradient(p), curve_target(p)

    def location(speed):
        return o.ite(speed <= foot, target, ebd_location_m(o, p, p, gradient, aim, speed))

    energy = _energy_by_speed_step(o, p, v, foot, location, p.emergency_speeds_mps, p.emergency_decelerations_mps2, k)
    top = o.const(MAX_SPEED_KMH) / o.const(KMH_PER_MPS)
    return o.and_(
        o.implies(v <= foot, o.eq(out.ebd_m, o.const(FAR_M))),
        o.implies(o.and_(foot < v, v <= top), o.and_(o.eq(out.ebd_m, location(v)), *energy)),
    )


def _sbd_is_service_braking_curve(o, p, s, i, out, nxt):
    """The SBD of an end of authority at the target is the braking curve at ``A_expected = A_brake_service +
    A_gradient``, no correction factor, to standstill at the target (:func:`_energy_by_speed_step`), and SBI1 lies
    ``v * T_bs`` before it."""
    v, zero, target = i.speed_mps, o.const(0), p.target_m

    def location(speed):
        return o.ite(speed <= zero, target, sbd_location_m(o, p, curve_gradient(p), target, speed))

    energy = _energy_by_speed_step(
        o, p, v, zero, location, p.service_speeds_mps, p.service_decelerations_mps2, o.const(1)
    )
    top = o.const(MAX_SPEED_KMH) / o.const(KMH_PER_MPS)
    return o.and_(
        o.implies(v <= zero, o.eq(out.sbd_m, o.const(FAR_M))),
        o.implies(o.and_(zero < v, v <= top), o.and_(o.eq(out.sbd_m, location(v)), *energy)),
        o.eq(out.sbi1_m, out.sbd_m - v * p.t_bs_s),
    )


def _gui_is_normal_service_curve(o, p, s, i, out, nxt):
    """The guidance curve of an end of authority at the target is the braking curve at ``A_normal_service =
    A_brake_normal_service + A_gradient - Kn+-(V) * grad / 1000`` to standstill at the target
    (:func:`_energy_by_speed_step`); the permitted speed location is the nearer of ``d_SBI1(v) - v * T_driver`` and
    the guidance curve's."""
    v, zero, target = i.speed_mps, o.const(0), p.target_m

    def location(speed):
        return o.ite(speed <= zero, target, gui_location_m(o, p, p, curve_gradient(p), target, speed))

    energy = _energy_by_speed_step(
        o,
        p,
        v,
        zero,
        location,
        p.normal_service_speeds_mps,
        p.normal_service_decelerations_mps2,
        o.const(1),
        kn=(p.kn_plus_mps2, p.kn_minus_mps2),
    )
    top = o.const(MAX_SPEED_KMH) / o.const(KMH_PER_MPS)
    sbi1 = sbd_location_m(o, p, curve_gradient(p), target, v) - v * p.t_bs_s
    return o.and_(
        o.implies(v <= zero, o.eq(out.gui_m, o.const(FAR_M))),
        o.implies(o.and_(zero < v, v <= top), o.and_(o.eq(out.gui_m, location(v)), *energy)),
        o.eq(out.guided_permitted_m, o.min(sbi1 - v * p.t_driver_s, out.gui_m)),
    )


def _ebi_from_brake_build_up(o, p, s, i, out, nxt):
    """EBI = d_EBD(V_bec) - D_bec with V_bec and D_bec as Subset-026 3.13.9.3.3 states them."""
    zero, v, v_target = o.const(0), i.speed_mps, p.target_speed_mps
    t_traction, t_berem = p.t_traction_s, o.max(zero, p.t_be_s - p.t_traction_s)
    v_d0 = o.ite(p.inhibit_speed_inaccuracy, zero, p.v_ura_mps)
    v_d1 = o.max(zero, i.a_est_mps2) * t_traction
    v_d2 = o.min(o.max(zero, i.a_est_mps2), o.const(A_EST2_CAP_MPS2)) * t_berem
    v_bec = o.max(v + v_d0 + v_d1, v_target) + v_d2
    d_bec = (
        o.max(v + v_d0 + v_d1 / o.const(2), v_target) * t_traction
        + (o.max(v + v_d0 + v_d1, v_target) + v_d2 / o.const(2)) * t_berem
    )
    return o.eq(out.ebi_m, ebd_location_m(o, p, p, curve_gradient(p), curve_target(p), v_bec) - d_bec)


def _prepared_equals_direct(o, p, s, i, out, nxt):
    direct = curve_locations(o, p, p, curve_gradient(p), curve_target(p), i.speed_mps, i.a_est_mps2)
    top = o.const(MAX_SPEED_KMH) / o.const(KMH_PER_MPS)
    same = (o.eq(getattr(out, name), getattr(direct, name)) for name in CurveLocations.__dataclass_fields__)
    return o.implies(o.and_(i.speed_mps <= top, p.target_speed_mps <= top), o.and_(*same))


def _table_ascending(o, p, s, i, out, nxt):
    keys = braking_table(o, p, p, curve_gradient(p), curve_target(p)).exit_speed2
    return o.and_(*(keys[c] <= keys[c + 1] for c in range(len(keys) - 1)))


def _bec_alike(o, p, s, i, out, nxt):
    target = curve_target(p)
    standstill = Target(target.location_m, o.const(0), target.ebd_foot_mps)
    own = bec_speed_and_distance(o, p, p, target, i.speed_mps, i.a_est_mps2)
    alike = bec_speed_and_distance(o, p, p, standstill, i.speed_mps, i.a_est_mps2)
    slow = p.target_speed_mps <= bec_train_speed_mps(o, p, p, i.speed_mps, i.a_est_mps2)
    return o.implies(slow, o.and_(*(o.eq(a, b) for a, b in zip(own, alike, strict=True))))


def _table_order(o, p, s, i, out, nxt):
    return o.implies(i.slower_mps <= i.faster_mps, out.faster_ebd_m <= out.slower_ebd_m)


def sized_node(node, fixed: dict):
    """``node`` with the array sizes of ``fixed`` (itself if they are its own; one node per shape, so a property
    and its lemmas share it)."""
    sizes = {key: len(fixed[key]) for key in node.sizes if key in fixed}
    if {**node.sizes, **sizes} == node.sizes:
        return node
    name = f"{node.name}_" + "_".join(str(sizes.get(key, node.sizes[key])) for key in sorted(node.sizes))
    if name not in _SIZED:
        _SIZED[name] = dataclasses.replace(node, name=name, sizes={**node.sizes, **sizes})
    return _SIZED[name]


_SIZED: dict = {}


def prepared_node(fixed: dict, variants=(PREPARED_CURVES, PREPARED_STEPPED_CURVES, PREPARED_CONVERTED_CURVES)):
    """The prepared-curves node (or another of ``variants``) whose brake tables have the sizes of ``fixed``'s
    (as :func:`curve_node`)."""
    sizes = {key: len(fixed[key]) for key in variants[0].sizes if key in fixed}
    for node in variants:
        if {**node.sizes, **sizes} == node.sizes:
            return node
    return sized_node(variants[0], fixed)


def curve_node(fixed: dict):
    """The curves node whose brake tables have the sizes of ``fixed``'s: a registered one, or :data:`CURVES` with
    those sizes (and its gradient profile's, when ``fixed`` gives the breakpoints)."""
    sizes = {key: len(fixed[key]) for key in CURVES.sizes if key in fixed}
    for node in (CURVES, STEPPED_CURVES, CONVERTED_CURVES):
        if {**node.sizes, **sizes} == node.sizes:
            return node
    return sized_node(CURVES, fixed)


def _properties(preset: str):
    guidance = DESIGN_NORMAL_SERVICE if preset in GUIDANCE_PRESETS else None
    return curve_properties(preset, PRESETS[preset], guidance) + table_properties(preset, PRESETS[preset])


def curve_properties(preset: str, fixed: dict, guidance: dict | None = None) -> tuple[Property, ...]:
    """The curve properties (CRV-01, 02, 06, 08, 10, 11, and with a normal service brake ``guidance``, the fields of
    :class:`~atcs.model.curves.GuidanceData`, CRV-12) for one set of fixed data,
    named ``curves.<kind>_<preset>``."""
    node = curve_node(fixed)
    return (
        Property(
            name=f"curves.order_{preset}",
            requirement="CRV-01",
            seed="000 §2.4, 002 §3.2",
            text=(
                f"With the {preset} train and national data and the design gradients, at every speed the curves "
                "are ordered: indication "
                "<= permitted <= warning <= SBI <= EBI <= EBD (locations where each reaches that speed)."
            ),
            node=node,
            holds=_ordered,
            assumptions=(TRACK_AND_TARGET, QUERY),
            fixed_params=fixed,
        ),
        Property(
            name=f"curves.ebi_protects_ebd_{preset}",
            requirement="CRV-02",
            seed="000 §2.4.2",
            text=(
                f"With the {preset} data and the design gradients: a train at or behind the EBI for its measured "
                "speed, whose true speed "
                "is within V_ura and which accelerates at most A_est while traction is cut (at most min(A_est, "
                "0.4) during the rest of the brake build-up), is still behind the EBD for its speed when the "
                "emergency brake becomes effective."
            ),
            node=node,
            holds=_ebi_protects_ebd,
            assumptions=(TRACK_AND_TARGET, QUERY),
            fixed_params=fixed,
        ),
        Property(
            name=f"curves.ebd_is_braking_curve_{preset}",
            requirement="CRV-08",
            seed="000 §2.4.1 (Subset-026 3.13.8.3)",
            text=(
                f"With the {preset} data and the design gradients: the EBD reaches a speed v above its foot speed "
                "(up to the highest line speed) where braking at A_safe, stated from the seed, takes v down to the "
                "foot speed exactly at the target: v^2 - V_foot^2 = 2 * sum of A_safe over the distance to the "
                "target, segment by segment; at or below the foot speed it never constrains (FAR_M)."
            ),
            node=node,
            holds=_ebd_is_braking_curve,
            assumptions=(TRACK_AND_TARGET, QUERY),
            fixed_params=fixed,
        ),
        Property(
            name=f"curves.sbd_is_service_braking_curve_{preset}",
            requirement="CRV-11",
            seed="000 §2.4.1 (Subset-026 3.13.8.4, 3.13.9.3.3.1)",
            text=(
                f"With the {preset} data and the design gradients: the SBD of an end of authority reaches a speed v "
                "above 0 (up to the highest line speed) where braking at A_expected = A_brake_service + A_gradient, "
                "stated from the seed without correction factors, takes v to standstill exactly at the EoA, speed "
                "step by speed step of the service brake; at standstill it never constrains (FAR_M); SBI1 lies "
                "v * T_bs before it."
            ),
            node=node,
            holds=_sbd_is_service_braking_curve,
            assumptions=(TRACK_AND_TARGET, QUERY),
            fixed_params=fixed,
        ),
        *(
            ()
            if guidance is None
            else (
                Property(
                    name=f"curves.gui_is_normal_service_curve_{preset}",
                    requirement="CRV-12",
                    seed="000 §2.4.1 (Subset-026 3.13.6.4, 3.13.8.5, 3.13.9.3.5.4)",
                    text=(
                        f"With the {preset} data, the design gradients and a design normal service brake: the "
                        "guidance curve of an end of authority reaches a speed v above 0 (up to the highest line "
                        "speed) where braking at A_normal_service = A_brake_normal_service + A_gradient - "
                        "Kn+(V) * grad / 1000 uphill (Kn-(V) downhill), stated from Subset-026, takes v to "
                        "standstill exactly at the EoA, speed step by speed step; at standstill it never constrains "
                        "(FAR_M); with the guidance curve enabled the permitted speed location is the nearer of "
                        "d_SBI1(v) - v * T_driver and d_GUI(v)."
                    ),
                    node=sized_node(GUIDANCE_CURVES, {**fixed, **guidance}),
                    holds=_gui_is_normal_service_curve,
                    assumptions=(TRACK_AND_TARGET, QUERY),
                    fixed_params={**fixed, **guidance},
                ),
            )
        ),
        Property(
            name=f"curves.ebi_from_brake_build_up_{preset}",
            requirement="CRV-10",
            seed="000 §2.4.2 (Subset-026 3.13.9.3.3)",
            text=(
                f"With the {preset} data: the EBI lies D_bec before the EBD's location for V_bec, with V_bec = "
                "max(v + V_d0 + V_d1, V_target) + V_d2 and D_bec = max(v + V_d0 + V_d1/2, V_target) * T_traction + "
                "(max(v + V_d0 + V_d1, V_target) + V_d2/2) * T_berem stated from Subset-026 (neither longer nor "
                "shorter a build-up than stated)."
            ),
            node=node,
            holds=_ebi_from_brake_build_up,
            assumptions=(TRACK_AND_TARGET, QUERY),
            fixed_params=fixed,
        ),
        Property(
            name=f"curves.spacing_{preset}",
            requirement="CRV-06",
            seed="000 §2.4.2, 002 §3.2 (Subset-026 3.13.9.3)",
            text=(
                f"With the {preset} data: SBI is the speed times T_bs before EBI, the warning T_warning and the "
                "permitted speed T_driver before SBI, the indication T_indication before the permitted speed (so "
                "each curve leaves the driver its stated time, not more and not less)."
            ),
            node=node,
            holds=_spaced,
            assumptions=(TRACK_AND_TARGET, QUERY),
            fixed_params=fixed,
        ),
    )


def table_properties(preset: str, fixed: dict) -> tuple[Property, ...]:
    """The properties of the curves preprocessed per authority (CRV-13, 14, 16, 17) for one set of fixed data, named
    ``curves.<kind>_<preset>``: proved for the presets; a configuration's trains and the envelopes do not prove
    them yet."""
    return (
        Property(
            name=f"curves.prepared_equals_direct_{preset}",
            requirement="CRV-13",
            seed="002 §3.2 (preprocessing), 000 §2.4",
            text=(
                f"With the {preset} data and the design gradients, a target and a speed up to the highest line "
                "speed: every curve's location, looked up in the target's EBD table walked once per authority, "
                "equals the direct walk's, for every gradient breakpoints and estimated acceleration."
            ),
            node=prepared_node(fixed),
            holds=_prepared_equals_direct,
            assumptions=(TRACK_AND_TARGET, QUERY),
            fixed_params=fixed,
        ),
        Property(
            name=f"curves.table_ascending_{preset}",
            requirement="CRV-14",
            seed="002 §3.2 (preprocessing)",
            text=(
                f"With the {preset} data and the design gradients: the squared speeds at which the EBD's walk "
                "leaves its cells never fall, so the concrete backends' bisection finds the cell the symbolic "
                "lookup's chain does."
            ),
            node=prepared_node(fixed),
            holds=_table_ascending,
            assumptions=(TRACK_AND_TARGET,),
            fixed_params=fixed,
        ),
        Property(
            name=f"curves.table_order_{preset}",
            requirement="CRV-16",
            seed="002 §3.2 (preprocessing), 000 §2.4",
            text=(
                f"With the {preset} data and the design gradients: the tabled EBD reaches a faster speed no "
                "nearer the target than a slower one (at or below the foot, FAR_M): what lets an envelope drop, "
                "speed band by speed band, the targets that cannot be the nearest."
            ),
            node=prepared_node(fixed, (TABLE_ORDER, TABLE_ORDER_STEPPED, TABLE_ORDER_CONVERTED)),
            holds=_table_order,
            assumptions=(TRACK_AND_TARGET, SPEED_PAIR),
            fixed_params=fixed,
        ),
        Property(
            name=f"curves.bec_alike_below_train_speed_{preset}",
            requirement="CRV-17",
            seed="000 §2.4.2 (Subset-026 3.13.9.3.3)",
            text=(
                f"With the {preset} data: every target whose speed is at or below the train's own term of V_bec "
                "(v + V_d0 + V_d1/2, the lesser of the two) has the V_bec and D_bec of a target at standstill: "
                "what lets supervision locate the EBI of all of them in one envelope."
            ),
            node=prepared_node(fixed),
            holds=_bec_alike,
            assumptions=(TRACK_AND_TARGET, QUERY),
            fixed_params=fixed,
        ),
    )


PROPERTIES = tuple(prop for preset in PRESETS for prop in _properties(preset))

__all__ = ["PROPERTIES"]
