"""Two trains never collide (seed 001 §3.2 Fig. 6, seed 000 §2.2 and §2.5).

Over :data:`~atcs.model.separation.TWO_TRAINS`: the follower's ATP supervising the end
of authority its authority node computes (route of 2 resources held or not, switches
reported or not, protection zone, end of line, MAX_MA and the leader's reports: all
symbolic inputs), its plant (the closed loop's bounds), the leader moving forward in
any way (relative braking: never braking harder than its highest deceleration), and
T2T reports delivered after any delay, out of order, or lost. With the follower's
train, national and plant data of a seed preset (the closed loop's), any MRSP ceiling,
odometry error, safety margin, report timeout and 2-segment compensated gradient
profile (breakpoints symbolic, values the design case -40 / +40 per mille).

Brick wall: the proof is the closed loop's (CL-00) with the end of authority replaced
by the leader's true rear less the margin, a target that never moves back and is never
ahead of the end of authority the ATP supervises (SEP-00).

Relative braking, in two steps. SEP-01: the follower's own best reported stopping point
less the margin never moves back and its end of authority never lies beyond it, so
CL-00's invariant holds for it; this needs nothing of the leader. SEP-02: that point is
behind the leader's true earliest stopping point (SEP-00), and the gap between the
follower's worst case and the leader's fastest stop closes by at most what one cycle
allows, so with a margin at least that large the follower never reaches the leader's
rear (assumptions *fleet* and *margin*).
"""

from __future__ import annotations

from dataclasses import fields

from atcs.model.authority import AuthorityInputs, AuthorityState, authority_step
from atcs.model.curves import MIN_SPAN
from atcs.model.plant import gradient_braking_mps2, plant_gradient
from atcs.model.profile import KMH_PER_MPS, MAX_SPEED_KMH, is_well_formed
from atcs.model.separation import TWO_TRAINS, earliest_stop_m, follower_authority, two_train_admits
from atcs.properties.closed_loop import (
    MEASUREMENT,
    PRESETS,
    TIMING,
    brake_cycle_splits,
    braking_invariant,
    follows_plant_and_atp,
    speed_bounded_brake_cycle_cases,
    whole_cycles,
)
from atcs.properties.curves import MAX_LINE_M
from atcs.properties.property import Assumption, Property


def _setting(o, p, s, i):
    zero = o.const(0)
    eoa = follower_authority(o, p, s, i)[1].eoa_m
    return o.and_(
        is_well_formed(o, plant_gradient(p)),
        p.line_end_m <= o.const(MAX_LINE_M),
        zero <= p.safety_margin_m,
        p.position_error_m >= zero,
        zero <= p.mrsp_mps,
        p.mrsp_mps <= o.const(MAX_SPEED_KMH) / o.const(KMH_PER_MPS),
        p.leader_max_deceleration_mps2 >= o.const(MIN_SPAN),
        zero <= eoa,
        eoa <= p.line_end_m,
        s.leader_rear_m + i.leader_distance_m <= p.line_end_m,
    )


SETTING = Assumption(
    "setting",
    f"the compensated gradient profile is well formed on a line of at most {MAX_LINE_M} m that the leader does not "
    f"leave, the follower's end of authority is on the line, MRSP within [0, {MAX_SPEED_KMH}] km/h, odometry error "
    f"and safety margin >= 0, the leader's highest deceleration >= {MIN_SPAN} m/s^2",
    _setting,
)

LEADER = Assumption(
    "leader",
    "the leader never moves backward (any other motion, including stopping dead)",
    lambda o, p, s, i: o.and_(i.leader_distance_m >= o.const(0), i.leader_next_speed_mps >= o.const(0)),
)


def report_behind(o, rear_m, leader_rear_m):
    """A report's min safe rear is at most the leader's current rear."""
    return rear_m <= leader_rear_m


def report_stop_behind(o, p, rear_m, speed_mps, leader_stop_m):
    """A report's min speed is >= 0 and the earliest stopping point it gives at most the leader's current one."""
    return o.and_(speed_mps >= o.const(0), earliest_stop_m(o, p, rear_m, speed_mps) <= leader_stop_m)


REPORT_REAR = Assumption(
    "report_rear",
    "an intact report describes a past state of the leader: its min safe rear is at most the leader's current rear "
    "(reports may arrive after any delay, out of order, repeated, or not at all; one whose safety code fails may "
    "say anything); proved of the reports the leader sends, SEP-07",
    lambda o, p, s, i: o.implies(
        o.and_(i.report_delivered, i.report_intact), report_behind(o, i.report_rear_m, s.leader_rear_m)
    ),
)


def _leader_braking(o, p, s, i):
    d, dt, v, v_next, x = (
        p.leader_max_deceleration_mps2,
        p.cycle_s,
        s.leader_speed_mps,
        i.leader_next_speed_mps,
        i.leader_distance_m,
    )
    two = o.const(2)
    return o.and_(
        d >= o.const(MIN_SPAN),
        v_next * v_next >= v * v - two * d * x,
        v_next >= v - d * dt,
        o.or_(two * d * x >= v * v, o.and_(v >= d * dt, x >= v * dt - d * dt * dt / two)),
    )


LEADER_BRAKING = Assumption(
    "leader_braking",
    "the leader never decelerates harder than leader_max_deceleration_mps2: over a cycle its speed falls by at "
    "most that deceleration times the cycle, its squared speed by at most twice that deceleration times the "
    "distance, and it runs at least the distance of braking that hard (for the whole cycle, or to a stop if it "
    "is slow enough to stop within the cycle)",
    _leader_braking,
)


REPORT_STOP = Assumption(
    "report_stop",
    "an intact report's min speed is >= 0 and the earliest stopping point it gives is at most the leader's current "
    "one (true of a past state: that point never moves back, SEP-04); proved of the reports the leader sends, SEP-08",
    lambda o, p, s, i: o.implies(
        o.and_(i.report_delivered, i.report_intact),
        report_stop_behind(o, p, i.report_rear_m, i.report_speed_mps, s.leader_stop_m),
    ),
)


def _fleet(o, p, s, i):
    uphill = o.max(o.const(0), *(gradient_braking_mps2(o, p, g) for g in p.gradient_permille))
    return p.guaranteed_deceleration_mps2 + uphill <= p.leader_max_deceleration_mps2


FLEET = Assumption(
    "fleet",
    "the follower's guaranteed deceleration, with the steepest uphill's help, is at most the leader's highest "
    "deceleration (otherwise a follower braking harder than the leader could close in on it mid-way)",
    _fleet,
)

FOLLOWER_PLANT = Assumption(
    "plant",
    "each cycle's motion of the follower is within the plant's bounds (model/plant.py) under its ATP's command",
    two_train_admits,
)


def one_cycle_closing_m(o, p):
    """How far a follower can gain on a leader at the same speed in one cycle: the plant bounds a braking
    cycle's distance by ``v * dt`` (its end points only), while the leader may brake at its highest
    deceleration for the whole cycle."""
    return p.leader_max_deceleration_mps2 * p.cycle_s * p.cycle_s / o.const(2)


MARGIN = Assumption(
    "margin",
    "the safety margin is at least leader_max_deceleration_mps2 * cycle^2 / 2 (1.5 cm at 3 m/s^2 and 100 ms), "
    "what a follower can gain on a leader at the same speed within one cycle, since the plant bounds a cycle's "
    "motion by its end points only",
    lambda o, p, s, i: p.safety_margin_m >= one_cycle_closing_m(o, p),
)


def _authority_on_safe_position(o, p, s, i, out, nxt):
    """The end of authority is the authority node's for the follower's max safe front (measured front + odometry
    bound) and min safe rear (measured front - bound - train length), the other inputs as delivered."""
    position = {
        "front_max_m": i.measured_front_m + p.position_error_m,
        "rear_min_m": i.measured_front_m - p.position_error_m - p.train_length_m,
        "rear_confirmed": o.const_bool(True),
    }
    inputs = AuthorityInputs(
        **{f.name: position[f.name] if f.name in position else getattr(i, f.name) for f in fields(AuthorityInputs)}
    )
    reports, authority = authority_step(o, p, s, inputs)
    return o.and_(
        o.eq(out.eoa_m, authority.eoa_m),
        *(o.eq(getattr(nxt, f.name), getattr(reports, f.name)) for f in fields(AuthorityState)),
    )


def _state_follows(o, p, s, i, out, nxt):
    """The follower's plant and latches as in the closed loop (CL-05); the leader moves by its input, and its
    earliest stopping point is its physics' (:func:`earliest_stop_m`) from its new rear and speed."""
    leader_rear = s.leader_rear_m + i.leader_distance_m
    return o.and_(
        follows_plant_and_atp(o, p, s, i, out, nxt),
        o.eq(nxt.leader_rear_m, leader_rear),
        o.eq(nxt.leader_speed_mps, i.leader_next_speed_mps),
        o.eq(nxt.leader_stop_m, earliest_stop_m(o, p, leader_rear, i.leader_next_speed_mps)),
    )


FOLLOWER = (SETTING, TIMING, MEASUREMENT, FOLLOWER_PLANT)
"""What relative braking's invariant (SEP-01) assumes: the follower's own closed loop, nothing of the leader."""
BRICK_WALL = (*FOLLOWER, LEADER, REPORT_REAR)
RELATIVE = (*BRICK_WALL, REPORT_STOP, LEADER_BRAKING, FLEET)


def separation_properties(preset: str, fixed: dict, mode: str) -> tuple[Property, ...]:
    """The separation properties for one preset and mode (``bw``: brick wall, ``rbd``: relative braking
    distance), named ``*_<mode>_<preset>``."""
    if mode not in ("bw", "rbd"):
        raise ValueError(f"separation mode must be 'bw' or 'rbd', got {mode!r}")
    n_t, n_be = whole_cycles(preset, fixed)
    fixed = {k: v for k, v in fixed.items() if k != "eoa_m"}
    fixed = {**fixed, "brick_wall": mode == "bw", "leader_max_deceleration_mps2": fixed["max_deceleration_mps2"]}
    assumptions = BRICK_WALL if mode == "bw" else RELATIVE
    common = dict(node=TWO_TRAINS, fixed_params=fixed)
    reports = f"separation.reports_behind_leader_{mode}_{preset}"
    invariant = f"separation.braking_invariant_{mode}_{preset}"
    earliest = f"separation.leader_stop_is_earliest_{preset}"
    never_recedes = f"separation.leader_stop_never_recedes_{preset}"
    name = {"bw": "brick-wall", "rbd": "relative braking"}[mode]
    authority = Property(
        name=f"separation.authority_on_safe_position_{mode}_{preset}",
        requirement="SEP-05",
        seed="001 §3.2 (Fig. 5), 000 §2.2",
        text=(
            f"{preset}, {name}: the follower's end of authority and the report bounds it keeps are its authority "
            "node's for its max safe front (measured front plus the odometry bound) and min safe rear (less the "
            "bound and the train length)."
        ),
        holds=_authority_on_safe_position,
        assumptions=assumptions,
        **common,
    )
    state_follows = Property(
        name=f"separation.state_follows_{mode}_{preset}",
        requirement="SEP-06",
        seed="000 §2.5; docs/design.md closed loop",
        text=(
            f"{preset}, {name}: each cycle the follower's front, speed, brake counter and latches follow its plant "
            "and ATP as in the closed loop (CL-05), the leader's rear advances by its distance run, its speed "
            "becomes its end speed, and its earliest stopping point is its physics' from those."
        ),
        holds=_state_follows,
        assumptions=assumptions,
        **common,
    )
    reports_behind = Property(
        name=reports,
        requirement="SEP-00",
        seed="001 §3.2",
        text=(
            f"{preset}, {name}: the best leader rear and earliest stopping point reported to the follower are "
            "never ahead of the leader's true ones."
        ),
        holds=(lambda o, p, s, i, out, nxt: o.and_(s.leader_known, s.best_rear_m <= s.leader_rear_m))
        if mode == "bw"
        else (
            lambda o, p, s, i, out, nxt: o.and_(
                s.leader_known, s.best_rear_m <= s.leader_rear_m, s.best_stop_m <= s.leader_stop_m
            )
        ),
        assumptions=assumptions,
        **common,
    )
    if mode == "bw":
        return (
            authority,
            state_follows,
            reports_behind,
            Property(
                name=invariant,
                requirement="SEP-01",
                seed="001 §3.2 (Fig. 6), 000 §2.4",
                text=(
                    f"{preset}, brick wall: the closed loop's braking invariant (CL-00) holds for the leader's "
                    "true rear less the safety margin as the end of authority."
                ),
                holds=lambda o, p, s, i, out, nxt: braking_invariant(
                    o, p, s, s.leader_rear_m - p.safety_margin_m, n_t, n_be
                ),
                assumptions=assumptions,
                lemmas=(reports,),
                **brake_cycle_splits(n_be),
                **common,
            ),
            Property(
                name=f"separation.no_collision_bw_{preset}",
                requirement="SEP-02",
                seed="001 §3.2, 000 §2.5",
                text=(
                    f"{preset}, brick wall: whatever the leader does (within its assumptions) and whatever the "
                    "follower's driver or ATO commands, the follower's true front stays at least the safety "
                    "margin behind the leader's true rear, with reports delayed, reordered or lost."
                ),
                holds=lambda o, p, s, i, out, nxt: s.front_m + p.safety_margin_m <= s.leader_rear_m,
                assumptions=assumptions,
                lemmas=(invariant,),
                **common,
            ),
        )
    return (
        Property(
            name=earliest,
            requirement="SEP-03",
            seed="001 §3.2 (Fig. 6)",
            text=(
                f"{preset}: the leader's speed is >= 0 and its earliest stopping point is its true rear plus its "
                "stopping distance from its true speed at its highest deceleration."
            ),
            holds=lambda o, p, s, i, out, nxt: o.and_(
                s.leader_speed_mps >= o.const(0),
                o.eq(
                    o.const(2) * p.leader_max_deceleration_mps2 * (s.leader_stop_m - s.leader_rear_m),
                    s.leader_speed_mps * s.leader_speed_mps,
                ),
            ),
            assumptions=assumptions,
            **common,
        ),
        Property(
            name=never_recedes,
            requirement="SEP-04",
            seed="001 §3.2 (Fig. 6)",
            text=(
                f"{preset}: the leader's earliest stopping point never moves back (it never brakes harder than its "
                "highest deceleration), so every report's stopping point bounds every later one from below."
            ),
            holds=lambda o, p, s, i, out, nxt: nxt.leader_stop_m >= s.leader_stop_m,
            assumptions=assumptions,
            lemmas=(earliest,),
            **common,
        ),
        authority,
        state_follows,
        reports_behind,
        Property(
            name=invariant,
            requirement="SEP-01",
            seed="001 §3.2 (Fig. 6), 000 §2.4",
            text=(
                f"{preset}, relative braking: once the leader has reported, the rear bound kept is never ahead "
                "of the stopping-point bound, and the closed loop's braking invariant (CL-00) holds for the "
                "best reported stopping point less the safety margin (never ahead of the leader's true one, "
                "SEP-00) as the end of authority; nothing about the leader is assumed."
            ),
            holds=lambda o, p, s, i, out, nxt: o.and_(
                s.leader_known,
                s.best_rear_m <= s.best_stop_m,
                braking_invariant(o, p, s, s.best_stop_m - p.safety_margin_m, n_t, n_be),
            ),
            assumptions=FOLLOWER,
            **brake_cycle_splits(n_be),
            **common,
        ),
        Property(
            name=f"separation.no_collision_rbd_{preset}",
            requirement="SEP-02",
            seed="001 §3.2, 000 §2.5",
            text=(
                f"{preset}, relative braking: whatever the leader does (never braking harder than its highest "
                "deceleration) and whatever the follower's driver or ATO commands, the follower's true front "
                "stays behind the leader's true rear, with reports delayed, reordered or lost."
            ),
            holds=lambda o, p, s, i, out, nxt: s.front_m < s.leader_rear_m,
            assumptions=(*assumptions, MARGIN),
            lemmas=(invariant, reports, earliest),
            cases=speed_bounded_brake_cycle_cases(n_be),
            certificate_cases=speed_bounded_brake_cycle_cases(n_be),
            **common,
        ),
    )


PROPERTIES = tuple(
    p for name, fixed in PRESETS.items() for mode in ("bw", "rbd") for p in separation_properties(name, fixed, mode)
)

__all__ = [
    "BRICK_WALL",
    "FOLLOWER",
    "LEADER",
    "LEADER_BRAKING",
    "MARGIN",
    "PROPERTIES",
    "RELATIVE",
    "report_behind",
    "report_stop_behind",
    "separation_properties",
]
