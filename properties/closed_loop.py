"""The closed-loop theorem (seed 000 §2.4, §2.5; docs/design.md, the closed-loop argument in discrete time).

Over :data:`~atcs.model.closed_loop.CLOSED_LOOP`: for any driver or ATO command
(any motion the plant admits), any measurement within its error bounds, any end of
authority, MRSP ceiling, odometry error and 2-segment compensated gradient profile
(breakpoints symbolic, values fixed to the design case -40 / +40 per mille), with the
train, national and plant data of a seed preset, the true front never passes the EoA
and the true speed never exceeds the MRSP + dV_ebi by more than the EBI's own margin.

Proved by k-induction with a braking invariant (``closed_loop.braking_invariant``,
proved first and then assumed): with ``c`` cycles of EB command so far, the train's
worst-case state when the brake becomes effective (full traction until the cut-off,
then coasting downhill) is behind the EBD for its speed; once the brake is effective,
the true speed is under the EBD at the true front. One case per value of ``c``, so
every case is polynomial of degree 2 in the state.
"""

from __future__ import annotations

from fractions import Fraction

from atcs.model.closed_loop import (
    CLOSED_LOOP,
    DECREASE_LOOP,
    closed_loop_admits,
    decrease_loop_admits,
    whole_cycles,
    worst_acceleration_mps2,
    worst_case_at_brake,
)
from atcs.model.curves import (
    A_EST2_CAP_MPS2,
    Target,
    adhesion_factor,
    ceiling_offset_mps,
    curve_locations,
    ebd_location_m,
    ebd_speed2_at,
)
from atcs.model.dynamic_profile import ceilings, ebd_foot_mps
from atcs.model.plant import PLANT_PAIR, max_gradient_acceleration_mps2, plant_gradient
from atcs.model.profile import KMH_PER_MPS, MAX_SPEED_KMH, is_well_formed
from atcs.model.train_data import PRESETS as TRAIN_PRESETS
from atcs.model.train_data import preset_data
from atcs.properties.curves import MAX_LINE_M, sized_node
from atcs.properties.property import Assumption, Property

PRESETS = {name: preset_data(train(), national()) for name, (train, national) in TRAIN_PRESETS.items()}
"""The fixed data of each preset's closed-loop properties."""


def _setting(o, p, s, i):
    g = plant_gradient(p)
    zero = o.const(0)
    return o.and_(
        is_well_formed(o, g),
        zero <= p.eoa_m,
        p.eoa_m <= p.line_end_m,
        p.line_end_m <= o.const(MAX_LINE_M),
        zero <= p.mrsp_mps,
        p.mrsp_mps <= o.const(Fraction(MAX_SPEED_KMH) / KMH_PER_MPS),
        p.position_error_m >= zero,
    )


SETTING = Assumption(
    "setting",
    f"the compensated gradient profile is well formed, the EoA lies on a line of at most {MAX_LINE_M} m, the MRSP "
    f"is within [0, {MAX_SPEED_KMH}] km/h, the odometry error bound is >= 0",
    _setting,
)


def _timing(o, p, s, i):
    dt = p.cycle_s
    return o.and_(
        dt > o.const(0),
        o.const(0) <= p.traction_cut_cycles,
        p.traction_cut_cycles <= p.brake_build_up_cycles,
        (p.traction_cut_cycles + o.const(1)) * dt <= p.t_traction_s,
        (p.brake_build_up_cycles + o.const(1)) * dt <= p.t_be_s,
        p.guaranteed_deceleration_mps2 >= adhesion_factor(o, p, p) * p.emergency_decelerations_mps2[0],
        max_gradient_acceleration_mps2(o, p) <= o.const(A_EST2_CAP_MPS2),
    )


TIMING = Assumption(
    "timing",
    "the plant cuts traction and makes the brake effective within T_traction and T_be of the last passing check "
    "(one cycle before the command), brakes at least K * A_brake_emergency, and accelerates downhill by at most "
    "Subset-026's A_est2 cap (0.4 m/s^2: gradients down to about -41 per mille)",
    _timing,
)


def _measurement(o, p, s, i):
    return o.and_(
        i.measured_front_m - s.front_m <= p.position_error_m,
        s.front_m - i.measured_front_m <= p.position_error_m,
        i.measured_speed_mps >= o.const(0),
        i.measured_speed_mps - s.speed_mps <= p.v_ura_mps,
        s.speed_mps - i.measured_speed_mps <= p.v_ura_mps,
        o.implies(i.standstill, o.eq(s.speed_mps, o.const(0))),
    )


MEASUREMENT = Assumption(
    "measurement",
    "the measured front is within the odometry bound of the true front, the measured speed (>= 0) within V_ura "
    "of the true speed; standstill is reported only at standstill",
    _measurement,
)

PLANT = Assumption(
    "plant",
    "each cycle's motion is within the plant's bounds (model/plant.py) under the ATP's emergency-brake command",
    closed_loop_admits,
)

ASSUMPTIONS = (SETTING, TIMING, MEASUREMENT, PLANT)


def ceiling_margin_mps(o, p, cycles: int, traction_cycles: int):
    """How far the true speed can be over the EBI ceiling after ``cycles`` cycles of EB command: V_ura and
    the acceleration since the last passing check."""
    dt = p.cycle_s
    return (
        p.v_ura_mps
        + worst_acceleration_mps2(o, p) * dt * o.const(min(cycles, traction_cycles) + 1)
        + max_gradient_acceleration_mps2(o, p) * dt * o.const(max(0, cycles - traction_cycles))
    )


def ebi_ceiling_mps(o, p):
    return ceilings(o, p, p.mrsp_mps).ebi_mps


def braking_invariant(o, p, s, eoa_m, n_t: int, n_be: int):
    """CL-00's invariant for the end of authority ``eoa_m`` (module docstring)."""
    zero = o.const(0)
    target = Target(eoa_m, zero, zero)
    gradient = plant_gradient(p)
    cases = []
    for c in range(n_be):
        front, speed = worst_case_at_brake(o, p, s.front_m, s.speed_mps, c, n_t, n_be)
        cases.append(
            o.and_(
                o.eq(s.brake_cycles, o.const(c)),
                front <= eoa_m,
                front <= ebd_location_m(o, p, p, gradient, target, speed),
                s.speed_mps <= ebi_ceiling_mps(o, p) + ceiling_margin_mps(o, p, c, n_t),
            )
        )
    braking = o.and_(
        o.eq(s.brake_cycles, o.const(n_be)),
        s.eb_latched,
        s.front_m <= eoa_m,
        s.speed_mps * s.speed_mps <= ebd_speed2_at(o, p, p, gradient, target, s.front_m),
        s.speed_mps <= ebi_ceiling_mps(o, p) + ceiling_margin_mps(o, p, n_be, n_t),
    )
    return o.and_(s.speed_mps >= zero, o.or_(*cases, braking))


def brake_cycle_cases(n_be: int):
    """``Property.cases``: one inductive-step case per value of the EB-command counter."""

    def by_brake_cycles(o, p, s):
        return tuple(o.eq(s.brake_cycles, o.const(c)) for c in range(n_be + 1))

    return by_brake_cycles


CERTIFICATE_SPEED_BOUND_MPS = Fraction(MAX_SPEED_KMH + 50) / KMH_PER_MPS
"""The speed bound of each :func:`speed_bounded_brake_cycle_cases` case: above any speed the braking invariant
allows (the EBI ceiling at the top MRSP is 15 km/h over it, the build-up margin a few km/h more)."""


def speed_bounded_brake_cycle_cases(n_be: int):
    """``Property.certificate_cases``: :func:`brake_cycle_cases`, each case at a speed within
    :data:`CERTIFICATE_SPEED_BOUND_MPS`; the faster states fall in the rest case, which the invariant refutes at
    once. The explicit bound is what cvc5's non-linear reasoning lacked (case 1 of
    ``separation.no_collision_rbd_seed000`` has no answer without it, docs/certificates.md). The engine splits on
    it only for relative braking's no-collision, where z3 lacked it too; elsewhere it stalled z3 on the
    coarse-cycle variant, hence a split for the certificate only (docs/certificates.md)."""
    by_brake_cycles = brake_cycle_cases(n_be)

    def by_brake_cycles_within_bound(o, p, s):
        bounded = s.speed_mps <= o.const(CERTIFICATE_SPEED_BOUND_MPS)
        return tuple(o.and_(case, bounded) for case in by_brake_cycles(o, p, s))

    return by_brake_cycles_within_bound


def brake_cycle_splits(n_be: int) -> dict:
    """The ``cases`` and ``certificate_cases`` of a closed-loop or separation property."""
    return dict(cases=brake_cycle_cases(n_be), certificate_cases=speed_bounded_brake_cycle_cases(n_be))


def closed_loop_properties(preset: str, fixed: dict) -> tuple[Property, ...]:
    """The closed-loop properties for one set of fixed data (:func:`preset_data`), named ``*_<preset>``."""
    n_t, n_be = whole_cycles(preset, fixed)

    common = dict(node=CLOSED_LOOP, assumptions=ASSUMPTIONS, fixed_params=fixed, **brake_cycle_splits(n_be))
    invariant = f"closed_loop.braking_invariant_{preset}"
    return (
        Property(
            name=invariant,
            requirement="CL-00",
            seed="000 §2.4; docs/design.md closed loop",
            text=(
                f"{preset}: with c cycles of EB command so far (c < the build-up), the worst-case state when the "
                "brake becomes effective is behind the EoA and behind the EBD for its speed, and the speed is "
                "within the ceiling margin for c; with the brake effective, the true speed is under the EBD "
                "at the true front."
            ),
            holds=lambda o, p, s, i, out, nxt: braking_invariant(o, p, s, p.eoa_m, n_t, n_be),
            **common,
        ),
        Property(
            name=f"closed_loop.no_overrun_{preset}",
            requirement="CL-01",
            seed="000 §2.4, §2.5",
            text=(
                f"{preset}: whatever the driver or ATO commands, the true front never passes the end of "
                "authority (measured speed within V_ura, measured front within the odometry bound)."
            ),
            holds=lambda o, p, s, i, out, nxt: s.front_m <= p.eoa_m,
            lemmas=(invariant,),
            **common,
        ),
        Property(
            name=f"closed_loop.under_ceiling_{preset}",
            requirement="CL-02",
            seed="000 §2.4.2, 002 §3.2",
            text=(
                f"{preset}: the true speed never exceeds MRSP + dV_ebi by more than V_ura + A_est1 * T_traction "
                "+ A_est2 * (T_be - T_traction) (the EBI's own margin, with the worst-case acceleration)."
            ),
            holds=lambda o, p, s, i, out, nxt: (
                s.speed_mps <= ebi_ceiling_mps(o, p) + ceiling_margin_mps(o, p, n_be, n_t)
            ),
            lemmas=(invariant,),
            **common,
        ),
        Property(
            name=f"closed_loop.eb_at_ebi_{preset}",
            requirement="CL-03",
            seed="000 §2.4.3",
            text=(
                f"{preset}: supervision composed with the curves commands EB in the cycle the max safe front "
                "is beyond the EBI for the measured speed (the measured speed crosses the EBI)."
            ),
            holds=lambda o, p, s, i, out, nxt: o.implies(
                i.measured_front_m + p.position_error_m > out.ebi_m, out.emergency_brake
            ),
            **common,
        ),
        Property(
            name=f"closed_loop.no_spurious_eb_{preset}",
            requirement="CL-04",
            seed="000 §2.4.3, 001 §3.2",
            text=(
                f"{preset}: with a valid position (the closed loop's measurement assumption), EB is commanded only "
                "when the max safe front is beyond the EBI for the measured speed, the measured speed is above "
                "MRSP + dV_ebi, or EB is latched and not released at standstill."
            ),
            holds=_no_spurious_eb,
            node=CLOSED_LOOP,
            assumptions=ASSUMPTIONS,
            fixed_params=fixed,
        ),
        Property(
            name=f"closed_loop.supervises_eoa_and_ceilings_{preset}",
            requirement="CL-06",
            seed="000 §2.4.2-2.4.3, Subset-026 3.13.9.3, 3.13.10",
            text=(
                f"{preset}: the commands are the seed's supervision of the end of authority (a target of speed 0) "
                "and of the MRSP's ceilings: with the max safe front and the measured speed, the curves of the EoA "
                "with the plant's worst acceleration as A_est and each ceiling MRSP + its dV, EB over the EBI or "
                "latched and not released at standstill, SB over the SBI or latched and over the permitted speed, "
                "the warning over the warning limit, traction cut with either brake, and the EBI reported is the "
                "EoA's."
            ),
            holds=_supervises_eoa_and_ceilings,
            node=CLOSED_LOOP,
            assumptions=ASSUMPTIONS,
            fixed_params=fixed,
        ),
        Property(
            name=f"closed_loop.state_follows_plant_and_atp_{preset}",
            requirement="CL-05",
            seed="000 §2.5; docs/design.md closed loop",
            text=(
                f"{preset}: each cycle the true front advances by the distance run and the true speed becomes "
                "the cycle's end speed, the brake counter counts the cycles of EB command up to the build-up "
                "(0 without it), and the latches record this cycle's EB and SB commands."
            ),
            holds=follows_plant_and_atp,
            node=CLOSED_LOOP,
            assumptions=ASSUMPTIONS,
            fixed_params=fixed,
        ),
    )


def follows_plant_and_atp(o, p, s, i, out, nxt):
    """CL-05: the true front advances by the distance run, the true speed becomes the end speed, the brake counter
    counts the cycles of EB command up to the build-up (0 without it), the latches record the commands."""
    counted = o.min(s.brake_cycles + o.const(1), p.brake_build_up_cycles)
    return o.and_(
        o.eq(nxt.front_m, s.front_m + i.distance_m),
        o.eq(nxt.speed_mps, i.next_speed_mps),
        o.eq(nxt.brake_cycles, o.ite(out.emergency_brake, counted, o.const(0))),
        o.eq(nxt.eb_latched, out.emergency_brake),
        o.eq(nxt.sb_latched, out.service_brake),
    )


def _supervises_eoa_and_ceilings(o, p, s, i, out, nxt):
    """The commands are the seed's supervision of the end of authority (a target of speed 0, EBD foot 0) and of
    the MRSP's ceilings: the curves at the measured speed with the plant's worst acceleration (A_max plus the
    steepest downhill's, from the plant's own gradient physics) as A_est, each ceiling MRSP + its dV
    (:func:`ceiling_offset_mps`, CRV-03..05), a limit exceeded when the max safe front is beyond its curve or
    the measured speed above its ceiling; EB over the EBI or latched and not released at standstill, SB (the
    presets have a service brake) over the SBI or latched and over the permitted speed, the warning over the
    warning limit."""
    zero, mrsp, speed = o.const(0), p.mrsp_mps, i.measured_speed_mps
    front = i.measured_front_m + p.position_error_m
    a_est = p.max_acceleration_mps2 + max_gradient_acceleration_mps2(o, p)
    curve = curve_locations(o, p, p, plant_gradient(p), Target(p.eoa_m, zero, zero), speed, a_est)

    def over(location_m, dv_min, dv_max, v_min, v_max):
        ceiling = mrsp if dv_min is None else mrsp + ceiling_offset_mps(o, mrsp, dv_min, dv_max, v_min, v_max)
        return o.or_(front > location_m, speed > ceiling)

    over_ebi = over(curve.ebi_m, p.dv_ebi_min_mps, p.dv_ebi_max_mps, p.v_ebi_min_mps, p.v_ebi_max_mps)
    over_sbi = over(curve.sbi_m, p.dv_sbi_min_mps, p.dv_sbi_max_mps, p.v_sbi_min_mps, p.v_sbi_max_mps)
    over_warning = over(
        curve.warning_m, p.dv_warning_min_mps, p.dv_warning_max_mps, p.v_warning_min_mps, p.v_warning_max_mps
    )
    over_permitted = over(curve.permitted_m, None, None, None, None)
    eb = o.or_(over_ebi, o.and_(s.eb_latched, o.not_(o.and_(i.standstill, i.eb_release))))
    sb = o.or_(over_sbi, o.and_(s.sb_latched, over_permitted))
    return o.and_(
        o.eq(out.ebi_m, curve.ebi_m),
        o.eq(out.emergency_brake, eb),
        o.eq(out.service_brake, sb),
        o.eq(out.warning, over_warning),
        o.eq(out.traction_cut, o.or_(eb, sb)),
    )


def _no_spurious_eb(o, p, s, i, out, nxt):
    released = o.and_(i.standstill, i.eb_release)
    return o.implies(
        out.emergency_brake,
        o.or_(
            i.measured_front_m + p.position_error_m > out.ebi_m,
            i.measured_speed_mps > ebi_ceiling_mps(o, p),
            o.and_(s.eb_latched, o.not_(released)),
        ),
    )


# --- one speed decrease of the MRSP as a target --------------------------------------------------------------------


def _decrease_setting(o, p, s, i):
    zero = o.const(0)
    return o.and_(
        is_well_formed(o, plant_gradient(p)),
        zero <= p.decrease_m,
        p.decrease_m <= p.line_end_m,
        p.line_end_m <= o.const(MAX_LINE_M),
        zero <= p.mrsp_after_mps,
        p.mrsp_after_mps <= p.mrsp_mps,
        p.mrsp_mps <= o.const(Fraction(MAX_SPEED_KMH) / KMH_PER_MPS),
        p.position_error_m >= zero,
    )


DECREASE_SETTING = Assumption(
    "setting",
    f"the compensated gradient profile is well formed, the decrease lies on a line of at most {MAX_LINE_M} m, the "
    f"MRSP decreases there and is within [0, {MAX_SPEED_KMH}] km/h, the odometry error bound is >= 0",
    _decrease_setting,
)

DECREASE_ASSUMPTIONS = (
    DECREASE_SETTING,
    TIMING,
    MEASUREMENT,
    Assumption(
        "plant",
        "each cycle's motion is within the plant's bounds (model/plant.py) under the ATP's emergency-brake command",
        decrease_loop_admits,
    ),
)


def decrease_target(o, p) -> Target:
    """The decrease as the ATP supervises it: the lower speed, the EBD ending at ``V_target + dV_ebi(V_target)``."""
    return Target(p.decrease_m, p.mrsp_after_mps, ebd_foot_mps(o, p, p.mrsp_after_mps))


def decrease_invariant(o, p, s, n_t: int, n_be: int):
    """CL-08's invariant: :func:`braking_invariant` for the decrease's target, or the true speed already within the
    closed loop's margin of the EBD's foot (the lower MRSP's EBI ceiling), which the ceiling keeps once the max safe
    front is past the decrease; and under the higher MRSP's EBI ceiling with the margin."""
    target = decrease_target(o, p)
    foot = target.ebd_foot_mps
    gradient = plant_gradient(p)
    top = ebi_ceiling_mps(o, p)
    cases = []
    for c in range(n_be):
        front, speed = worst_case_at_brake(o, p, s.front_m, s.speed_mps, c, n_t, n_be)
        margin = ceiling_margin_mps(o, p, c, n_t)
        cases.append(
            o.and_(
                o.eq(s.brake_cycles, o.const(c)),
                o.or_(front <= ebd_location_m(o, p, p, gradient, target, speed), s.speed_mps <= foot + margin),
                s.speed_mps <= top + margin,
            )
        )
    margin = ceiling_margin_mps(o, p, n_be, n_t)
    braking = o.and_(
        o.eq(s.brake_cycles, o.const(n_be)),
        s.eb_latched,
        o.or_(
            s.speed_mps * s.speed_mps <= ebd_speed2_at(o, p, p, gradient, target, s.front_m),
            s.speed_mps <= foot + margin,
        ),
        s.speed_mps <= top + margin,
    )
    return o.and_(s.speed_mps >= o.const(0), o.or_(*cases, braking))


def decrease_properties(tag: str, fixed: dict, target: str = "decrease") -> tuple[Property, ...]:
    """The theorems of one speed decrease of the MRSP for one set of fixed data, named
    ``closed_loop.<target>_invariant_<tag>`` and ``closed_loop.under_<target>_<tag>`` (``target`` ``loa`` for a limit
    of authority, which the ATP supervises as a speed decrease)."""
    n_t, n_be = whole_cycles(tag, fixed)
    common = dict(node=DECREASE_LOOP, assumptions=DECREASE_ASSUMPTIONS, fixed_params=fixed, **brake_cycle_splits(n_be))
    invariant = f"closed_loop.{target}_invariant_{tag}"
    return (
        Property(
            name=invariant,
            requirement="CL-08",
            seed="000 §2.4.2; Subset-026 3.13.8.3.1, 3.13.10.3",
            text=(
                f"{tag}: with c cycles of EB command so far (c < the build-up), the worst-case state when the brake "
                "becomes effective is behind the decrease's EBD for its speed, or the true speed is within the "
                "ceiling margin for c of the lower MRSP's EBI ceiling; with the brake effective, the true speed is "
                "under the EBD at the true front or within that margin; always within the margin of the higher "
                "MRSP's EBI ceiling."
            ),
            holds=lambda o, p, s, i, out, nxt: decrease_invariant(o, p, s, n_t, n_be),
            **common,
        ),
        Property(
            name=f"closed_loop.under_{target}_{tag}",
            requirement="CL-09",
            seed="000 §2.4.2, 002 §3.2; Subset-026 3.13.10.3",
            text=(
                f"{tag}: whatever the driver or ATO commands, once the true front is at or past the speed decrease "
                "the true speed is at most the lower MRSP + dV_ebi plus V_ura + A_est1 * T_traction + A_est2 * "
                "(T_be - T_traction) (the EBI's own margin, with the worst-case acceleration)."
            ),
            holds=lambda o, p, s, i, out, nxt: o.implies(
                s.front_m >= p.decrease_m,
                s.speed_mps <= ebd_foot_mps(o, p, p.mrsp_after_mps) + ceiling_margin_mps(o, p, n_be, n_t),
            ),
            lemmas=(invariant,),
            **common,
        ),
    )


# --- the side condition of the line's windows: more braking commanded admits fewer motions ------------------------


def _brake_histories(o, p, s, i):
    zero = o.const(0)
    return o.and_(
        is_well_formed(o, plant_gradient(p)),
        p.cycle_s > zero,
        p.max_acceleration_mps2 >= zero,
        p.guaranteed_deceleration_mps2 >= zero,
        i.speed_mps >= zero,
        o.implies(i.other_emergency_brake, i.emergency_brake),
        zero <= i.other_brake_cycles,
        i.other_brake_cycles <= i.brake_cycles,
        i.brake_cycles <= p.brake_build_up_cycles,
    )


BRAKE_HISTORIES = Assumption(
    "brake_histories",
    "the other command brakes only when the first does, its counter is between 0 and the first's, the first's at "
    "most the build-up; the profile is well formed, the cycle positive, A_max and the guaranteed deceleration >= 0",
    _brake_histories,
)


def braking_order_property(name: str, fixed: dict) -> Property:
    """CL-10: a motion the plant admits under an emergency-brake command and counter is admitted under any command
    given only when that one is and any counter not above it, and the counters stay so ordered: a closed loop whose
    ATP brakes at least whenever another's does runs only motions the other's plant admits."""
    plant_fixed = {key: value for key, value in fixed.items() if key in PLANT_PAIR.sorts("params")}

    def holds(o, p, s, i, out, nxt):
        return o.implies(
            out.admissible,
            o.and_(out.other_admissible, out.other_next_brake_cycles <= out.next_brake_cycles),
        )

    return Property(
        name=name,
        requirement="CL-10",
        seed="000 §2.5; docs/configuration.md windows",
        text=(
            "a motion admitted under an EB command and brake counter is admitted under any command given only when "
            "that one is and any counter not above it, and the next counters keep that order"
        ),
        node=sized_node(PLANT_PAIR, plant_fixed),
        holds=holds,
        assumptions=(BRAKE_HISTORIES,),
        fixed_params=plant_fixed,
        max_k=0,
    )


PROPERTIES = tuple(p for name, fixed in PRESETS.items() for p in closed_loop_properties(name, fixed))

__all__ = ["PROPERTIES"]
