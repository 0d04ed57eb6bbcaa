"""Two trains never collide (seed 001 §3.2 Fig. 6, seed 000 §2.2 and §2.5): brick-wall mode.

Over :data:`~atcs.model.separation.TWO_TRAINS`: the follower's ATP, its plant (the
closed loop's bounds), the leader moving forward in any way, and T2T reports of the
leader's min safe rear delivered after any delay, or lost. With the follower's
train, national and plant data of a seed preset (the closed loop's), any MRSP
ceiling, odometry error, safety margin and 2-segment compensated gradient profile
(breakpoints symbolic, values the design case -40 / +40 per mille), the follower's
true front stays at least the safety margin behind the leader's true rear.

The proof is the closed loop's (CL-00) with the end of authority replaced by the
leader's true rear less the margin, a target that only moves forward; the follower's
ATP supervises the best reported rear less the margin, which is never ahead of it
(SEP-00).
"""

from __future__ import annotations

from atcs.model.plant import plant_gradient
from atcs.model.profile import KMH_PER_MPS, MAX_SPEED_KMH, is_well_formed
from atcs.model.separation import TWO_TRAINS, two_train_admits
from atcs.properties.closed_loop import (
    MEASUREMENT,
    PRESETS,
    TIMING,
    brake_cycle_cases,
    braking_invariant,
    whole_cycles,
)
from atcs.properties.curves import MAX_LINE_M
from atcs.properties.property import Assumption, Property


def _setting(o, p, s, i):
    zero = o.const(0)
    return o.and_(
        is_well_formed(o, plant_gradient(p)),
        p.line_end_m <= o.const(MAX_LINE_M), zero <= p.safety_margin_m, p.position_error_m >= zero,
        zero <= p.mrsp_mps, p.mrsp_mps <= o.const(MAX_SPEED_KMH) / o.const(KMH_PER_MPS),
        zero <= s.best_rear_m - p.safety_margin_m, s.leader_rear_m + i.leader_distance_m <= p.line_end_m,
    )


SETTING = Assumption(
    "setting",
    f"the compensated gradient profile is well formed on a line of at most {MAX_LINE_M} m that the leader does not "
    f"leave, the follower's end of authority is on the line, MRSP within [0, {MAX_SPEED_KMH}] km/h, odometry error "
    "and safety margin >= 0",
    _setting,
)

LEADER = Assumption(
    "leader",
    "the leader never moves backward (any other motion, including stopping dead)",
    lambda o, p, s, i: o.and_(i.leader_distance_m >= o.const(0), i.leader_next_speed_mps >= o.const(0)),
)

REPORT = Assumption(
    "report",
    "a report describes a past state of the leader: its min safe rear is at most the leader's current true rear "
    "(reports may arrive after any delay, out of order, or not at all)",
    lambda o, p, s, i: o.implies(i.report_delivered, i.report_rear_m <= s.leader_rear_m),
)

FOLLOWER_PLANT = Assumption(
    "plant",
    "each cycle's motion of the follower is within the plant's bounds (model/plant.py) under its ATP's command",
    two_train_admits,
)

ASSUMPTIONS = (SETTING, TIMING, MEASUREMENT, FOLLOWER_PLANT, LEADER, REPORT)


def separation_properties(preset: str, fixed: dict) -> tuple[Property, ...]:
    """The brick-wall separation properties for one preset, named ``*_<preset>``."""
    n_t, n_be = whole_cycles(preset, fixed)
    fixed = {k: v for k, v in fixed.items() if k != "eoa_m"}
    common = dict(node=TWO_TRAINS, assumptions=ASSUMPTIONS, fixed_params=fixed)
    reports = f"separation.report_behind_leader_{preset}"
    invariant = f"separation.braking_invariant_bw_{preset}"
    return (
        Property(
            name=reports, requirement="SEP-00", seed="001 §3.2",
            text=f"{preset}: the best leader rear reported to the follower is never ahead of the leader's true rear.",
            holds=lambda o, p, s, i, out, nxt: s.best_rear_m <= s.leader_rear_m,
            **common,
        ),
        Property(
            name=invariant, requirement="SEP-01", seed="001 §3.2 (Fig. 6), 000 §2.4",
            text=(f"{preset}: the closed loop's braking invariant (CL-00) holds for the leader's true rear less the "
                  "safety margin as the end of authority."),
            holds=lambda o, p, s, i, out, nxt: braking_invariant(
                o, p, s, s.leader_rear_m - p.safety_margin_m, n_t, n_be),
            lemmas=(reports,), cases=brake_cycle_cases(n_be),
            **common,
        ),
        Property(
            name=f"separation.no_collision_bw_{preset}", requirement="SEP-02", seed="001 §3.2, 000 §2.5",
            text=(f"{preset}, brick-wall mode: whatever the leader does (moving forward) and whatever the follower's "
                  "driver or ATO commands, the follower's true front stays at least the safety margin behind the "
                  "leader's true rear, with reports delayed, reordered or lost."),
            holds=lambda o, p, s, i, out, nxt: s.front_m + p.safety_margin_m <= s.leader_rear_m,
            lemmas=(invariant,),
            **common,
        ),
    )


PROPERTIES = tuple(p for name, fixed in PRESETS.items() for p in separation_properties(name, fixed))

__all__ = ["ASSUMPTIONS", "PROPERTIES", "separation_properties"]
