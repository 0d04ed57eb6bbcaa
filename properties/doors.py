"""Properties of door-opening protection (seed 004 §2.1): the door enable, the DCU and the traction interlock.

The enable properties quantify over every front in the position interval and every
door (the ``probe_front_m`` and ``probe_door_m`` inputs), so "a platform covers the
train's doors" is claimed door by door, not in the form the node computes it. The
door geometry and the platform table (3 entries, each on either side or none) are
symbolic: every train and every table up to that capacity.
"""

from __future__ import annotations

from atcs.model.doors import DCU, DOOR_ENABLE, DOOR_LOOP
from atcs.properties.property import Assumption, Property

DOOR_GEOMETRY = Assumption(
    name="door_geometry",
    text="0 <= first_door <= last_door (the doors lie behind the front)",
    holds=lambda o, p, s, i: o.and_(o.const(0) <= p.first_door_m, p.first_door_m <= p.last_door_m),
)

PROBES = Assumption(
    name="probes",
    text="front_min <= probe_front <= front_max and first_door <= probe_door <= last_door",
    holds=lambda o, p, s, i: o.and_(
        i.front_min_m <= i.probe_front_m,
        i.probe_front_m <= i.front_max_m,
        p.first_door_m <= i.probe_door_m,
        i.probe_door_m <= p.last_door_m,
    ),
)

SPEED_NON_NEGATIVE = Assumption(
    name="speed_non_negative",
    text="the measured speed is never negative",
    holds=lambda o, p, s, i: i.speed_mps >= o.const(0),
)

ENABLE_ASSUMPTIONS = (DOOR_GEOMETRY, PROBES, SPEED_NON_NEGATIVE)
SINGLE_LOOP_FAULT = Assumption(
    "single_loop_fault",
    "at most one of the two door detection loops lies (reports closed whatever the doors)",
    lambda o, p, s, i: o.not_(o.and_(i.loop_a_stuck_closed, i.loop_b_stuck_closed)),
)


def safe_to_open(o, p, i, side: str):
    """Seed 004 §2.1's four conditions for one side, for the probed front and door: zero speed, immobilised, the
    front within the stopping tolerance, and the door on a platform on that side."""
    on_side = getattr(i, f"platform_{side}")
    door_at_m = i.probe_front_m - i.probe_door_m
    return o.and_(
        i.standstill,
        o.eq(i.speed_mps, o.const(0)),
        i.immobilised,
        i.position_valid,
        i.stopping_point_m - i.stop_tolerance_m <= i.probe_front_m,
        i.probe_front_m <= i.stopping_point_m + i.stop_tolerance_m,
        o.or_(
            *(
                o.and_(on_side[j], i.platform_start_m[j] <= door_at_m, door_at_m <= i.platform_end_m[j])
                for j in range(len(on_side))
            )
        ),
    )


def conditions_met(o, p, i, side: str):
    """Seed 004 §2.1's conditions met for the whole position interval on one side: requested, zero speed,
    immobilised, every front within the stopping tolerance, and one platform on that side spanning every door of
    every front."""
    on_side = getattr(i, f"platform_{side}")
    return o.and_(
        getattr(i, f"request_{side}"),
        i.standstill,
        o.eq(i.speed_mps, o.const(0)),
        i.immobilised,
        i.position_valid,
        i.stopping_point_m - i.stop_tolerance_m <= i.front_min_m,
        i.front_max_m <= i.stopping_point_m + i.stop_tolerance_m,
        o.or_(
            *(
                o.and_(
                    on_side[j],
                    i.platform_start_m[j] <= i.front_min_m - p.last_door_m,
                    i.front_max_m - p.first_door_m <= i.platform_end_m[j],
                )
                for j in range(len(on_side))
            )
        ),
    )


def _opens(o, s, nxt, side: str):
    return o.and_(o.not_(getattr(s, f"door_open_{side}")), getattr(nxt, f"door_open_{side}"))


PROPERTIES = (
    Property(
        name="doors.enable_left_only_at_platform_stop",
        requirement="DOOR-01",
        seed="004 §2.1",
        text=(
            "The left doors are enabled only at zero speed, immobilised, with every front of the position interval "
            "within the stopping tolerance and every door on a platform on the left."
        ),
        node=DOOR_ENABLE,
        holds=lambda o, p, s, i, out, nxt: o.implies(out.enable_left, safe_to_open(o, p, i, "left")),
        assumptions=ENABLE_ASSUMPTIONS,
    ),
    Property(
        name="doors.enable_right_only_at_platform_stop",
        requirement="DOOR-02",
        seed="004 §2.1",
        text=(
            "The right doors are enabled only at zero speed, immobilised, with every front of the position interval "
            "within the stopping tolerance and every door on a platform on the right."
        ),
        node=DOOR_ENABLE,
        holds=lambda o, p, s, i, out, nxt: o.implies(out.enable_right, safe_to_open(o, p, i, "right")),
        assumptions=ENABLE_ASSUMPTIONS,
    ),
    Property(
        name="doors.traction_cut_while_unlocked",
        requirement="DOOR-03",
        seed="004 §2.3.3, Fig. 1",
        text=(
            "While any door is not closed and locked, traction is cut and the train is not driven by its own power, "
            "even with one of the two detection loops lying (stuck at closed)."
        ),
        node=DOOR_LOOP,
        holds=lambda o, p, s, i, out, nxt: o.implies(
            o.or_(s.door_open_left, s.door_open_right),
            o.and_(out.traction_cut, o.not_(out.traction_applied)),
        ),
        assumptions=(SINGLE_LOOP_FAULT,),
    ),
    Property(
        name="doors.open_only_with_enable_and_command",
        requirement="DOOR-04",
        seed="004 §2.1, Fig. 1",
        text="A closed door opens only in a cycle with both the ATP's enable and the ATO's or driver's open command.",
        node=DCU,
        holds=lambda o, p, s, i, out, nxt: o.and_(
            o.implies(_opens(o, s, nxt, "left"), o.and_(i.enable_left, i.open_left)),
            o.implies(_opens(o, s, nxt, "right"), o.and_(i.enable_right, i.open_right)),
        ),
    ),
    Property(
        name="doors.close_when_enable_drops",
        requirement="DOOR-05",
        seed="004 §2.1",
        text="A side's doors are closed in the cycle after its enable drops, unless an obstacle holds them open.",
        node=DCU,
        holds=lambda o, p, s, i, out, nxt: o.and_(
            o.implies(o.not_(o.or_(i.enable_left, i.obstructed_left)), o.not_(nxt.door_open_left)),
            o.implies(o.not_(o.or_(i.enable_right, i.obstructed_right)), o.not_(nxt.door_open_right)),
        ),
    ),
    Property(
        name="doors.open_only_at_platform_stop",
        requirement="DOOR-06",
        seed="004 §2.1, Fig. 1",
        text=(
            "ATP and DCU together: a door opens only at zero speed, immobilised, within the stopping tolerance and "
            "onto a platform on its side."
        ),
        node=DOOR_LOOP,
        holds=lambda o, p, s, i, out, nxt: o.and_(
            o.implies(_opens(o, s, nxt, "left"), safe_to_open(o, p, i, "left")),
            o.implies(_opens(o, s, nxt, "right"), safe_to_open(o, p, i, "right")),
        ),
        assumptions=ENABLE_ASSUMPTIONS,
    ),
    Property(
        name="doors.enable_at_platform_stop",
        requirement="DOOR-07",
        seed="004 §2.1",
        text=(
            "No false refusal: a side's doors are enabled when requested at zero speed, immobilised, with the whole "
            "position interval within the stopping tolerance and one platform on that side spanning every door."
        ),
        node=DOOR_ENABLE,
        holds=lambda o, p, s, i, out, nxt: o.and_(
            o.implies(conditions_met(o, p, i, "left"), out.enable_left),
            o.implies(conditions_met(o, p, i, "right"), out.enable_right),
        ),
        assumptions=ENABLE_ASSUMPTIONS,
    ),
    Property(
        name="doors.dcu_follows_commands",
        requirement="DOOR-08",
        seed="004 §2.1, Fig. 1",
        text=(
            "The DCU obeys: a side enabled and commanded open is open in the next cycle, and an open side stays open "
            "while it is enabled and no close command is given."
        ),
        node=DCU,
        holds=lambda o, p, s, i, out, nxt: o.and_(
            *(
                o.and_(
                    o.implies(
                        o.and_(getattr(i, f"enable_{side}"), getattr(i, f"open_{side}")),
                        getattr(nxt, f"door_open_{side}"),
                    ),
                    o.implies(
                        o.and_(getattr(s, f"door_open_{side}"), getattr(i, f"enable_{side}"), o.not_(i.close)),
                        getattr(nxt, f"door_open_{side}"),
                    ),
                )
                for side in ("left", "right")
            )
        ),
    ),
    Property(
        name="doors.traction_as_requested_unless_cut",
        requirement="DOOR-09",
        seed="004 §2.1, Fig. 1",
        text=(
            "ATP and DCU together: traction is applied exactly when the ATO requests it and it is not cut; the doors "
            "are taken as closed and locked exactly when no door is open, or a door is open and both loops are stuck "
            "reporting closed: one loop's fault hides no open door, and closed doors cause no false cut-off."
        ),
        node=DOOR_LOOP,
        holds=lambda o, p, s, i, out, nxt: o.and_(
            o.eq(out.traction_applied, o.and_(i.traction_request, o.not_(out.traction_cut))),
            o.eq(
                out.closed_locked,
                o.or_(
                    o.not_(o.or_(s.door_open_left, s.door_open_right)),
                    o.and_(i.loop_a_stuck_closed, i.loop_b_stuck_closed),
                ),
            ),
        ),
    ),
)
