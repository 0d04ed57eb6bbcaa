"""Braking curves: EBD, EBI, SBI, warning, permitted and indication (seed 000 §2.4, 002 §3.2, docs/design.md
reference formulas in Subset-026 §3.13 style).

A curve is handled as the *location* at which it reaches a given speed (the
inverse query of the ERA braking-curves tool): supervision compares the train's
front with the location of each curve at the train's speed, which needs no square
root and no per-metre array. The EBD is found by walking backward from the target
through the cells of (compensated gradient segment x emergency-brake speed step),
integrating ``v^2/2`` with the safe deceleration ``A_safe(v, d) = K * A_brake(v) +
A_gradient(d)``, ``K = Kdry * (Kwet + M_NVAVADH * (1 - Kwet))``. The other curves
follow from the EBD:

- ``V_bec = max(v + V_d0 + V_d1, V_target) + V_d2`` and ``D_bec = max(v + V_d0 + V_d1/2, V_target) * T_traction
  + (max(v + V_d0 + V_d1, V_target) + V_d2/2) * T_berem``, with ``V_d0 = V_ura`` (0 when inhibited),
  ``V_d1 = A_est1 * T_traction``, ``V_d2 = A_est2 * T_berem``, ``A_est1 = max(0, A_est)``,
  ``A_est2 = clamp(A_est, 0, 0.4)``, ``T_berem = max(0, T_be - T_traction)``;
- ``d_EBI(v) = d_EBD(V_bec) - D_bec``, ``d_SBI = d_EBI - v*T_bs``, warning ``= d_SBI - v*T_warning``,
  permitted ``= d_SBI - v*T_driver``, indication ``= permitted - v*T_indication``.

The end of authority at standstill also has an SBD, braking at ``A_expected = A_brake_service(V) + A_gradient``
to standstill there (Subset-026 §3.13.8.4, :func:`sbd_location_m`), and ``d_SBI1 = d_SBD(v) - v*T_bs``
(:func:`sbi1_location_m`), which Subset-026 compares with the estimated front. Both are computed and proved
(CRV-11) but not yet supervised: the SBI here is the EBD's (SBI2). So is its guidance curve (GUI, §3.13.8.5),
braking at ``A_normal_service = A_brake_normal_service(V) + A_gradient - Kn+-(V) * grad / 1000`` to standstill there
(:func:`gui_location_m`, CRV-12), which only moves the permitted speed location when the national value
Q_NVGUIPERM enables it (:func:`guided_permitted_location_m`).

A curve that never constrains speed ``v`` (the target is at or above it) is at
:data:`FAR_M`, ahead of any line.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from typing import Generic

from atcs.model.deceleration import gradient_deceleration_mps2
from atcs.model.node import Stateless, stateless_node
from atcs.model.ops import B, N, Ops
from atcs.model.ops.exact import EXACT
from atcs.model.profile import Profile, segment_ends
from atcs.model.train_data import NationalData, TrainData, TrainDataError

FAR_M = 10_000_000
"""A location ahead of (or, negated, behind) any line: where a curve that does not constrain a speed lies."""
HUGE_SPEED2 = 1_000_000
"""A squared speed ((m/s)^2) above any train's: a walk bounded by position only."""
MIN_SPAN = "0.001"
"""Guard on divisors that valid data keeps far from zero (a speed span of the ceiling offsets, m/s; a
safe deceleration, m/s^2): with data out of range the curves are meaningless but still computable,
so the backends stay comparable on any input. Proofs assume data where the guard never acts."""
A_EST2_CAP_MPS2 = "0.4"
"""Subset-026's cap on the acceleration assumed during the brake build-up."""


@dataclass(frozen=True)
class Target(Generic[N]):
    """A supervised location: the train must be at ``speed_mps`` or below from ``location_m`` on.
    The EBD ends at ``ebd_foot_mps`` there (``V_target + dV_ebi(V_target)`` for a speed decrease, the
    target speed itself for the end of authority)."""

    location_m: N
    speed_mps: N
    ebd_foot_mps: N


@dataclass(frozen=True)
class CurveLocations(Generic[N]):
    """Where each curve reaches a given speed: the train must be behind each location at that speed."""

    ebd_m: N
    ebi_m: N
    sbi_m: N
    warning_m: N
    permitted_m: N
    indication_m: N


def ceiling_offset_mps(o: Ops, speed_mps, dv_min, dv_max, v_min, v_max):
    """dV_ebi / dV_sbi / dV_warning at ``speed_mps``: ``dv_min`` up to ``v_min``, ``dv_max`` from
    ``v_max``, linear in between."""
    between = dv_min + (dv_max - dv_min) * (speed_mps - v_min) / o.max(v_max - v_min, o.const(MIN_SPAN))
    return o.ite(speed_mps <= v_min, dv_min, o.ite(speed_mps >= v_max, dv_max, between))


def adhesion_factor(o: Ops, t: TrainData, n: NationalData):
    """``K = Kdry_rst * (Kwet_rst + M_NVAVADH * (1 - Kwet_rst))``."""
    return t.kdry_rst * (t.kwet_rst + n.m_nvavadh * (o.const(1) - t.kwet_rst))


def gradient_acceleration_mps2(o: Ops, t: TrainData, gradient_permille):
    """``A_gradient`` (positive uphill: it helps braking), with M_rotating by the gradient's sign."""
    mass = o.ite(gradient_permille >= o.const(0), t.rotating_mass_uphill_percent, t.rotating_mass_downhill_percent)
    return gradient_deceleration_mps2(o, gradient_permille, mass)


def check_braking_capability(
    t: TrainData, n: NationalData, gradient_c: Profile, guidance: GuidanceData | None = None
) -> None:
    """Raise :class:`~atcs.model.train_data.TrainDataError` unless ``A_safe``, ``A_expected`` and (with
    ``guidance``) ``A_normal_service`` are positive (above :data:`MIN_SPAN`) in every cell of the EBD's, the SBD's
    and the GUI's walks: the train can stop on every gradient (concrete data)."""
    brakes = [
        ("emergency_decelerations_mps2", "A_safe", safe_brake(EXACT, t, n)),
        ("service_decelerations_mps2", "A_expected", expected_brake(EXACT, t)),
    ]
    if guidance is not None:
        brakes.append(("normal_service", "A_normal_service", normal_service_brake(EXACT, guidance)))
    for field, name, brake in brakes:
        for j, gradient in enumerate(gradient_c.values):
            for step, a_brake in enumerate(brake.decelerations_mps2):
                a = brake.factor * a_brake + gradient_acceleration_mps2(EXACT, t, gradient)
                if brake.kn_plus_mps2 is not None:
                    a = a - gradient_correction_mps2(EXACT, brake, step, gradient)
                if not a > EXACT.const(MIN_SPAN):
                    raise TrainDataError(
                        f"train data: {field}[{step}] = {float(a_brake):g} gives {name} = {float(a):.3f} m/s^2 on "
                        f"gradient_permille[{j}] = {float(gradient):g}: the train cannot stop there"
                    )


@dataclass(frozen=True)
class BrakeModel(Generic[N]):
    """The deceleration a braking walk integrates: ``factor * decelerations_mps2[k]`` from ``speeds_mps[k]`` up
    (the first step from 0), plus the gradient's acceleration."""

    speeds_mps: tuple[N, ...]
    decelerations_mps2: tuple[N, ...]
    factor: N
    kn_plus_mps2: tuple[N, ...] | None = None
    """The normal service brake's gradient correction Kn+(V) on the same speed steps (uphill), or None."""
    kn_minus_mps2: tuple[N, ...] | None = None
    """Kn-(V) (downhill), given with Kn+."""


def gradient_correction_mps2(o: Ops, brake: BrakeModel, step: int, gradient_permille):
    """``Kn+-(V) * grad / 1000`` on speed step ``step``: Kn+ on an uphill gradient, Kn- on a downhill one
    (Subset-026 §3.13.6.4.3, §3.13.2.2.9.2.4-5); subtracted from ``A_brake_normal_service + A_gradient``."""
    kn = o.ite(gradient_permille >= o.const(0), brake.kn_plus_mps2[step], brake.kn_minus_mps2[step])
    return kn * gradient_permille / o.const(1000)


def safe_brake(o: Ops, t: TrainData, n: NationalData) -> BrakeModel:
    """The EBD's: ``A_brake_safe(V) = K * A_brake_emergency(V)`` (Subset-026 §3.13.6.2.1)."""
    return BrakeModel(t.emergency_speeds_mps, t.emergency_decelerations_mps2, adhesion_factor(o, t, n))


def expected_brake(o: Ops, t: TrainData) -> BrakeModel:
    """The SBD's: ``A_brake_service(V)`` without correction factors (``A_expected``, §3.13.6.3.1.3)."""
    return BrakeModel(t.service_speeds_mps, t.service_decelerations_mps2, o.const(1))


def braking_cells(
    o: Ops, t: TrainData, brake: BrakeModel, gradient_c: Profile, target_m, target_speed2, stop_m, stop_speed2
):
    """Walk backward from ``(target_m, target_speed2)`` along a braking curve (``brake`` plus the gradient's
    acceleration) until the position reaches ``stop_m`` or the squared speed reaches ``stop_speed2``: returns
    ``(cells, (position, squared speed))``, ``cells`` giving for each cell visited the position, the squared speed
    and the deceleration (brake and gradient) as the walk enters it.

    Cells are visited from the target backward, speed steps upward in each
    gradient segment (the speed only rises going backward). The first gradient
    segment extends behind the profile's start. Needs a positive deceleration in every cell.
    """
    speeds, decels, k = brake.speeds_mps, brake.decelerations_mps2, brake.factor
    position, speed2 = target_m, target_speed2
    starts = gradient_c.starts_m
    cells = []
    for j in reversed(range(len(starts))):
        low = stop_m if j == 0 else o.max(starts[j], stop_m)
        a_gradient = gradient_acceleration_mps2(o, t, gradient_c.values[j])
        for step, a_brake in enumerate(decels):
            a_safe = k * a_brake + a_gradient
            if brake.kn_plus_mps2 is not None:
                a_safe = a_safe - gradient_correction_mps2(o, brake, step, gradient_c.values[j])
            cells.append((position, speed2, a_safe))
            top2 = stop_speed2 if step + 1 == len(decels) else o.min(speeds[step + 1] * speeds[step + 1], stop_speed2)
            needed_m = (top2 - speed2) / (o.const(2) * o.max(a_safe, o.const(MIN_SPAN)))
            moved_m = o.max(o.const(0), o.min(needed_m, position - low))
            position = position - moved_m
            speed2 = speed2 + o.const(2) * a_safe * moved_m
    return cells, (position, speed2)


def braking_walk(
    o: Ops, t: TrainData, brake: BrakeModel, gradient_c: Profile, target_m, target_speed2, stop_m, stop_speed2
):
    """:func:`braking_cells`' end: ``(position, squared speed)`` where the walk stops."""
    return braking_cells(o, t, brake, gradient_c, target_m, target_speed2, stop_m, stop_speed2)[1]


def braking_walk_ahead(o: Ops, t: TrainData, brake: BrakeModel, gradient_c: Profile, from_m, from_speed2, stop_speed2):
    """Walk forward from ``(from_m, from_speed2)`` along a braking curve, braking until the squared speed falls
    to ``stop_speed2``: returns ``(position, squared speed)``.

    Cells are visited from ``from_m`` ahead, speed steps downward in each gradient segment (the speed only falls
    going ahead); the last gradient segment extends past the profile's end. Needs a positive deceleration in
    every cell.
    """
    speeds, decels, k = brake.speeds_mps, brake.decelerations_mps2, brake.factor
    position, speed2 = from_m, from_speed2
    ends = segment_ends(gradient_c)
    for j, gradient in enumerate(gradient_c.values):
        high = o.const(FAR_M) if j + 1 == len(ends) else ends[j]
        a_gradient = gradient_acceleration_mps2(o, t, gradient)
        for step in reversed(range(len(decels))):
            a_safe = k * decels[step] + a_gradient
            floor2 = o.max(speeds[step] * speeds[step], stop_speed2)
            needed_m = (speed2 - floor2) / (o.const(2) * o.max(a_safe, o.const(MIN_SPAN)))
            moved_m = o.max(o.const(0), o.min(needed_m, high - position))
            position = position + moved_m
            speed2 = speed2 - o.const(2) * a_safe * moved_m
    return position, speed2


def ebd_location_m(o: Ops, t, n, gradient_c: Profile, target: Target, speed_mps):
    """Where the EBD reaches ``speed_mps`` (FAR_M if it never exceeds it)."""
    foot2 = target.ebd_foot_mps * target.ebd_foot_mps
    position, _ = braking_walk(
        o, t, safe_brake(o, t, n), gradient_c, target.location_m, foot2, o.const(-FAR_M), speed_mps * speed_mps
    )
    return above_foot(o, target, speed_mps, position)


def above_foot(o: Ops, target: Target, speed_mps, location_m):
    """``location_m``, where the EBD reaches ``speed_mps``, if the speed is above the curve's foot; FAR_M if not
    (the EBD never exceeds its foot speed)."""
    return o.ite(speed_mps <= target.ebd_foot_mps, o.const(FAR_M), location_m)


def ebd_speed2_at(o: Ops, t, n, gradient_c: Profile, target: Target, x_m):
    """The EBD's squared speed at ``x_m`` (the foot speed squared at and past the target)."""
    foot2 = target.ebd_foot_mps * target.ebd_foot_mps
    _, speed2 = braking_walk(o, t, safe_brake(o, t, n), gradient_c, target.location_m, foot2, x_m, o.const(HUGE_SPEED2))
    return speed2


def ebd_reference_location_m(o: Ops, t, n, gradient_c: Profile, target: Target, speed_mps):
    """Where the EBD reaches ``speed_mps`` at any speed (the ERA braking-curves tool's EBD, Subset-026 §3.13.8.3.1):
    behind the target above the foot speed (:func:`ebd_location_m`); below it, beyond the target, the curve
    continuing from the foot speed at the target down to standstill. Supervision never needs the part beyond the
    target (a target is supervised until the train reaches it); the reference values do."""
    foot2 = target.ebd_foot_mps * target.ebd_foot_mps
    beyond_m, _ = braking_walk_ahead(
        o, t, safe_brake(o, t, n), gradient_c, target.location_m, foot2, speed_mps * speed_mps
    )
    return o.ite(speed_mps <= target.ebd_foot_mps, beyond_m, ebd_location_m(o, t, n, gradient_c, target, speed_mps))


def sbd_location_m(o: Ops, t: TrainData, gradient_c: Profile, eoa_m, speed_mps):
    """Where the SBD of the end of authority ``eoa_m`` reaches ``speed_mps``: braking at ``A_expected(V, d) =
    A_brake_service(V) + A_gradient(d)`` to standstill at the EoA (Subset-026 §3.13.8.4.1); FAR_M at standstill."""
    position, _ = braking_walk(
        o, t, expected_brake(o, t), gradient_c, eoa_m, o.const(0), o.const(-FAR_M), speed_mps * speed_mps
    )
    return o.ite(speed_mps <= o.const(0), o.const(FAR_M), position)


def sbi1_location_m(o: Ops, t: TrainData, gradient_c: Profile, eoa_m, speed_mps):
    """The end of authority's SBI1 at ``speed_mps``: ``d_SBD(v) - v * T_bs1`` (Subset-026 §3.13.9.3.3.1; T_bs1 is
    T_bs2, which the train data's ``t_bs_s`` gives, §3.13.9.3.3.3 to 5)."""
    return sbd_location_m(o, t, gradient_c, eoa_m, speed_mps) - speed_mps * t.t_bs_s


@dataclass(frozen=True)
class GuidanceData(Generic[N]):
    """The normal service brake for the guidance curve (Subset-026 §3.13.6.4): the model
    A_brake_normal_service(V) the train's brake position and A_brake_service(V=0) select (§3.13.2.2.3.1.9-10), and
    the gradient corrections Kn+(V), Kn-(V) (§3.13.2.2.9.2), all on the same speed steps."""

    normal_service_speeds_mps: tuple[N, ...]
    normal_service_decelerations_mps2: tuple[N, ...]
    kn_plus_mps2: tuple[N, ...]
    kn_minus_mps2: tuple[N, ...]


def normal_service_brake(o: Ops, g: GuidanceData) -> BrakeModel:
    """The GUI's: ``A_normal_service = A_brake_normal_service(V) + A_gradient - Kn+-(V) * grad / 1000``, no worst
    case conditions (§3.13.6.4.1, .3)."""
    return BrakeModel(
        g.normal_service_speeds_mps, g.normal_service_decelerations_mps2, o.const(1), g.kn_plus_mps2, g.kn_minus_mps2
    )


def gui_location_m(o: Ops, t: TrainData, g: GuidanceData, gradient_c: Profile, target_m, speed_mps):
    """Where the guidance curve of an end of authority (or SvL) at ``target_m`` reaches ``speed_mps``: braking at
    ``A_normal_service(V, d)`` to standstill there, its foot at the target (§3.13.8.5.2 a); FAR_M at standstill."""
    position, _ = braking_walk(
        o, t, normal_service_brake(o, g), gradient_c, target_m, o.const(0), o.const(-FAR_M), speed_mps * speed_mps
    )
    return o.ite(speed_mps <= o.const(0), o.const(FAR_M), position)


def curve_speed2_at(o: Ops, t: TrainData, brake: BrakeModel, gradient_c: Profile, target_m, foot_speed2, x_m):
    """The forward query: the squared speed at ``x_m`` of the braking curve of ``brake`` whose foot is
    ``foot_speed2`` at ``target_m`` (the foot speed at and past the target)."""
    _, speed2 = braking_walk(o, t, brake, gradient_c, target_m, foot_speed2, x_m, o.const(HUGE_SPEED2))
    return speed2


def guided_permitted_location_m(
    o: Ops, t: TrainData, n: NationalData, g: GuidanceData, gradient_c: Profile, eoa_m, speed_mps
):
    """The end of authority's permitted speed location with the guidance curve enabled (Q_NVGUIPERM):
    ``d_P(v) = min(d_SBI1(v) - v * T_driver, d_GUI(v))`` (§3.13.9.3.5.4)."""
    return o.min(
        sbi1_location_m(o, t, gradient_c, eoa_m, speed_mps) - speed_mps * n.t_driver_s,
        gui_location_m(o, t, g, gradient_c, eoa_m, speed_mps),
    )


def bec_speed_deltas_mps(o: Ops, t: TrainData, n: NationalData, a_est_mps2):
    """``(V_delta0, V_delta1)`` of ``V_bec``: the speed inaccuracy (0 where inhibited) and the acceleration over
    the traction cut-off time (Subset-026 §3.13.9.3.2, the EBI)."""
    zero = o.const(0)
    return o.ite(n.inhibit_speed_inaccuracy, zero, t.v_ura_mps), o.max(zero, a_est_mps2) * t.t_traction_s


def bec_speed_and_distance(o: Ops, t: TrainData, n: NationalData, target: Target, speed_mps, a_est_mps2):
    """``(V_bec, D_bec)``: the worst-case speed and distance until the emergency brake is effective."""
    zero = o.const(0)
    t_berem = o.max(zero, t.t_be_s - t.t_traction_s)
    a_est2 = o.min(o.max(zero, a_est_mps2), o.const(A_EST2_CAP_MPS2))
    v_d0, v_d1 = bec_speed_deltas_mps(o, t, n, a_est_mps2)
    v_d2 = a_est2 * t_berem
    v_cut = o.max(speed_mps + v_d0 + v_d1, target.speed_mps)
    v_bec = v_cut + v_d2
    d_bec = (
        o.max(speed_mps + v_d0 + v_d1 / o.const(2), target.speed_mps) * t.t_traction_s
        + (v_cut + v_d2 / o.const(2)) * t_berem
    )
    return v_bec, d_bec


def bec_train_speed_mps(o: Ops, t: TrainData, n: NationalData, speed_mps, a_est_mps2):
    """The least of the train's speeds :func:`bec_speed_and_distance` weighs against the target speed
    (``V + V_delta0 + V_delta1 / 2``, the same terms): every target whose speed is at or below it has the same
    ``(V_bec, D_bec)``."""
    v_d0, v_d1 = bec_speed_deltas_mps(o, t, n, a_est_mps2)
    return o.min(speed_mps + v_d0 + v_d1, speed_mps + v_d0 + v_d1 / o.const(2))


def curve_locations(
    o: Ops, t: TrainData, n: NationalData, gradient_c: Profile, target: Target, speed_mps, a_est_mps2
) -> CurveLocations:
    """Where each curve of ``target`` reaches ``speed_mps`` with estimated acceleration ``a_est_mps2``."""
    return curves_from_ebd(
        o, t, n, target, speed_mps, a_est_mps2, lambda v: ebd_location_m(o, t, n, gradient_c, target, v)
    )


def curves_from_ebd(
    o: Ops, t: TrainData, n: NationalData, target: Target, speed_mps, a_est_mps2, ebd_at: Callable
) -> CurveLocations:
    """:func:`curve_locations` from ``ebd_at(speed)``, where the target's EBD reaches a speed (walked directly, or
    looked up in the target's preprocessed table, :mod:`atcs.model.prepared_curves`)."""
    v_bec, d_bec = bec_speed_and_distance(o, t, n, target, speed_mps, a_est_mps2)
    return curves_from_ebd_and_ebi(o, t, n, lambda: ebd_at(speed_mps), ebd_at(v_bec) - d_bec, speed_mps)


def curves_from_ebd_and_ebi(o: Ops, t: TrainData, n: NationalData, ebd_m: Callable, ebi_m, speed_mps) -> CurveLocations:
    """The curves' locations from the EBI's and ``ebd_m()``, the EBD's: the SBI, warning, permitted and indication
    fixed distances at ``speed_mps`` before the EBI (Subset-026 §3.13.9.3). The EBD is asked for where the
    symbolic terms have always been built (z3's search follows the terms' order)."""
    sbi = ebi_m - speed_mps * t.t_bs_s
    permitted = sbi - speed_mps * n.t_driver_s
    return CurveLocations(
        ebd_m=ebd_m(),
        ebi_m=ebi_m,
        sbi_m=sbi,
        warning_m=sbi - speed_mps * n.t_warning_s,
        permitted_m=permitted,
        indication_m=permitted - speed_mps * n.t_indication_s,
    )


def reference_curve_locations(
    o: Ops, t: TrainData, n: NationalData, gradient_c: Profile, target: Target, speed_mps, a_est_mps2
) -> CurveLocations:
    """:func:`curve_locations` with the EBD at every speed (:func:`ebd_reference_location_m`), as the ERA
    braking-curves tool defines the curves of a target down to standstill. At a given speed the SBI, warning,
    permitted and indication lie fixed distances before the EBI (:func:`curve_locations`), so they move with it
    (exact backends: the supervision's EBI may be :data:`FAR_M`-based)."""
    curve = curve_locations(o, t, n, gradient_c, target, speed_mps, a_est_mps2)
    v_bec, d_bec = bec_speed_and_distance(o, t, n, target, speed_mps, a_est_mps2)
    shift = ebd_reference_location_m(o, t, n, gradient_c, target, v_bec) - d_bec - curve.ebi_m
    return CurveLocations(
        ebd_m=ebd_reference_location_m(o, t, n, gradient_c, target, speed_mps),
        **{
            name: getattr(curve, name) + shift
            for name in ("ebi_m", "sbi_m", "warning_m", "permitted_m", "indication_m")
        },
    )


# --- the node the proofs quantify over ------------------------------------------------------------


@dataclass(frozen=True)
class CurveParams(TrainData[N, B], NationalData[N, B]):
    gradient_starts_m: tuple[N, ...]
    """The compensated gradient profile ahead (per mille), as :func:`~atcs.model.psl.extend_by_train_length`
    gives it."""
    gradient_permille: tuple[N, ...]
    line_end_m: N
    target_m: N
    target_speed_mps: N
    target_ebd_foot_mps: N


@dataclass(frozen=True)
class CurveQuery(Generic[N, B]):
    speed_mps: N
    """The estimated (measured) speed."""
    a_est_mps2: N
    """The estimated acceleration."""
    front_m: N
    """The train's front (properties only)."""
    true_speed_mps: N
    """The true speed, within V_ura of the estimate (properties only)."""


@dataclass(frozen=True)
class CurveOutputs(CurveLocations[N], Generic[N, B]):
    sbd_m: N
    """Where the SBD of an end of authority at the target's location reaches the speed (:func:`sbd_location_m`)."""
    sbi1_m: N
    """That end of authority's SBI1: ``d_SBD(v) - v * T_bs`` (Subset-026 §3.13.9.3.3.1)."""


def curve_target(p: CurveParams) -> Target:
    return Target(p.target_m, p.target_speed_mps, p.target_ebd_foot_mps)


def curve_gradient(p: CurveParams) -> Profile:
    return Profile(p.gradient_starts_m, p.gradient_permille, p.line_end_m)


def curves_step(o: Ops, p: CurveParams, s: Stateless, i: CurveQuery):
    locations = curve_locations(o, p, p, curve_gradient(p), curve_target(p), i.speed_mps, i.a_est_mps2)
    return s, CurveOutputs(
        **{name: getattr(locations, name) for name in CurveLocations.__dataclass_fields__},
        sbd_m=sbd_location_m(o, p, curve_gradient(p), p.target_m, i.speed_mps),
        sbi1_m=sbi1_location_m(o, p, curve_gradient(p), p.target_m, i.speed_mps),
    )


DESIGN_CASE_SIZES = {
    "gradient_starts_m": 2,
    "gradient_permille": 2,
    "emergency_speeds_mps": 1,
    "emergency_decelerations_mps2": 1,
    "service_speeds_mps": 1,
    "service_decelerations_mps2": 1,
}
"""The array sizes of the proofs' design case: 2 compensated-gradient segments (the design pair), one-step brake
tables; the curves, closed-loop and two-train nodes share them."""


CURVES = stateless_node(
    name="curves",
    params=CurveParams,
    inputs=CurveQuery,
    outputs=CurveOutputs,
    step=curves_step,
    seed="000 §2.4, 002 §3.2",
    sizes=DESIGN_CASE_SIZES,
)
"""The braking curves of one target as a node for proofs: 2 compensated-gradient segments, the target
and the query speed and acceleration symbolic; train and national data as each property fixes them."""


@dataclass(frozen=True)
class GuidanceCurveParams(CurveParams[N, B], GuidanceData[N]):
    """:class:`CurveParams` with the normal service brake of the guidance curve."""


@dataclass(frozen=True)
class GuidanceCurveOutputs(Generic[N, B]):
    gui_m: N
    """Where the guidance curve of an end of authority at the target's location reaches the speed
    (:func:`gui_location_m`)."""
    guided_permitted_m: N
    """That end of authority's permitted speed location with the guidance curve enabled
    (:func:`guided_permitted_location_m`)."""


def guidance_curves_step(o: Ops, p: GuidanceCurveParams, s: Stateless, i: CurveQuery):
    gradient = curve_gradient(p)
    return s, GuidanceCurveOutputs(
        gui_m=gui_location_m(o, p, p, gradient, p.target_m, i.speed_mps),
        guided_permitted_m=guided_permitted_location_m(o, p, p, p, gradient, p.target_m, i.speed_mps),
    )


GUIDANCE_CURVES = stateless_node(
    name="guidance_curves",
    params=GuidanceCurveParams,
    inputs=CurveQuery,
    outputs=GuidanceCurveOutputs,
    step=guidance_curves_step,
    seed="000 §2.4 (Subset-026 3.13.8.5)",
    sizes={
        **DESIGN_CASE_SIZES,
        "normal_service_speeds_mps": 2,
        "normal_service_decelerations_mps2": 2,
        "kn_plus_mps2": 2,
        "kn_minus_mps2": 2,
    },
)
"""The guidance curve and the permitted speed it adjusts for an end of authority, as a node for proofs: the
design case's gradients, a normal service brake of two speed steps with Kn+ and Kn- on them."""

STEPPED_CURVES = dataclasses.replace(
    CURVES, name="curves_stepped", sizes={**CURVES.sizes, "emergency_speeds_mps": 3, "emergency_decelerations_mps2": 3}
)
""":data:`CURVES` (the same step) for a train whose emergency brake has three speed steps: the walk's cells over
speed, which the presets' one-step brakes never enter, are proved about too."""

CONVERTED_CURVES = dataclasses.replace(
    CURVES,
    name="curves_converted",
    sizes={
        **CURVES.sizes,
        **{
            f"{brake}_{table}": 4
            for brake in ("emergency", "service")
            for table in ("speeds_mps", "decelerations_mps2")
        },
    },
)
""":data:`CURVES` (the same step) for a Lambda train whose emergency and service brakes the conversion model of
Subset-026 §3.13.3 gives in four speed steps: AD_0 up to V_lim, then the steps of V_lim's range and above it (a
brake percentage from about 98 to 165 %, V_lim between 120 and 150 km/h)."""


# --- dV as a sub-function node: the speed-dependent ceiling offset on its own ---------------------------------


@dataclass(frozen=True)
class CeilingOffsetParams(Generic[N, B]):
    """One of dV_ebi, dV_sbi, dV_warning (Subset-026 3.13.9.3): its two offsets and the speeds between which it
    is interpolated."""

    dv_min_mps: N
    dv_max_mps: N
    v_min_mps: N
    v_max_mps: N


@dataclass(frozen=True)
class CeilingOffsetQuery(Generic[N, B]):
    speed_mps: N
    """The MRSP (or target speed) the offset is added to."""


@dataclass(frozen=True)
class CeilingOffsetOutputs(Generic[N, B]):
    offset_mps: N


def ceiling_offset_step(o: Ops, p: CeilingOffsetParams, s: Stateless, i: CeilingOffsetQuery):
    return s, CeilingOffsetOutputs(
        ceiling_offset_mps(o, i.speed_mps, p.dv_min_mps, p.dv_max_mps, p.v_min_mps, p.v_max_mps)
    )


CEILING_OFFSET = stateless_node(
    name="ceiling_offset",
    params=CeilingOffsetParams,
    inputs=CeilingOffsetQuery,
    outputs=CeilingOffsetOutputs,
    step=ceiling_offset_step,
    seed="000 §2.4.2, 002 §3.2",
)
""":func:`ceiling_offset_mps` as a sub-function of its own (seed 001 §3.4: each sub-function tested alone), all
four national values symbolic."""


# --- the adhesion factor as a sub-function node -----------------------------------------------------------------


@dataclass(frozen=True)
class AdhesionParams(Generic[N, B]):
    kdry_rst: N
    """The train's brake-performance correction on a dry rail (train data)."""
    kwet_rst: N
    """The train's correction on a wet rail (train data)."""
    m_nvavadh: N
    """The weighting between wet and dry rail (national value: 0 wet, 1 dry)."""


@dataclass(frozen=True)
class AdhesionQuery(Generic[N, B]):
    pass


@dataclass(frozen=True)
class AdhesionOutputs(Generic[N, B]):
    k: N
    """K, the factor on the emergency deceleration the EBD is computed with."""


def adhesion_step(o: Ops, p: AdhesionParams, s: Stateless, i: AdhesionQuery):
    return s, AdhesionOutputs(adhesion_factor(o, p, p))


ADHESION = stateless_node(
    name="adhesion",
    params=AdhesionParams,
    inputs=AdhesionQuery,
    outputs=AdhesionOutputs,
    step=adhesion_step,
    seed="000 §2.4.1 (Subset-026 3.13.6.2)",
)
""":func:`adhesion_factor` as a sub-function of its own."""


# --- the gradient's share of the safe deceleration as a sub-function node ---------------------------------------


@dataclass(frozen=True)
class GradientAccelerationParams(Generic[N, B]):
    rotating_mass_uphill_percent: N
    """M_rotating the train data gives for an uphill gradient (train data)."""
    rotating_mass_downhill_percent: N
    """M_rotating for a downhill gradient."""


@dataclass(frozen=True)
class GradientAccelerationQuery(Generic[N, B]):
    gradient_permille: N
    """A compensated gradient, positive uphill."""


@dataclass(frozen=True)
class GradientAccelerationOutputs(Generic[N, B]):
    a_gradient_mps2: N
    """A_gradient, the gradient's share of A_safe (positive uphill: it helps braking)."""


def gradient_acceleration_step(o: Ops, p: GradientAccelerationParams, s: Stateless, i: GradientAccelerationQuery):
    return s, GradientAccelerationOutputs(gradient_acceleration_mps2(o, p, i.gradient_permille))


GRADIENT_ACCELERATION = stateless_node(
    name="gradient_acceleration",
    params=GradientAccelerationParams,
    inputs=GradientAccelerationQuery,
    outputs=GradientAccelerationOutputs,
    step=gradient_acceleration_step,
    seed="000 §2.3 (equation 2), Subset-026 3.13.4.3",
)
""":func:`gradient_acceleration_mps2` as a sub-function of its own, the gradient and both rotating masses
symbolic (the curve proofs fix them to the presets' data and the design gradients)."""
