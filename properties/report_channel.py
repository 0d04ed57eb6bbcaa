"""The leader's reports on their way to the follower (seed 001 §3.2, Fig. 5 iii and Fig. 6; EN 50159): every
report the follower can receive intact describes a past state of the leader, which is what the two-train proofs
assume of it (REPORT_REAR, REPORT_STOP in :mod:`atcs.properties.separation`).

Over :data:`~atcs.model.separation.REPORT_CHANNEL`, every value symbolic: the leader moving forward and never
braking harder than its highest deceleration (the two-train proofs' LEADER and LEADER_BRAKING), its position
function true (the true front within its interval, the true speed within the accuracy of the estimate: what POS-22
and the speed bounds give), each cycle's report made by the onboard unit's own
:func:`~atcs.model.t2t_message.t2t_report_step`, and a channel that delivers the report on its way any number of
cycles later, repeatedly, or never. The predicates are the assumptions' own (``report_behind``,
``report_stop_behind``), applied to the report the channel delivers rather than to an input.
"""

from __future__ import annotations

from atcs.model.separation import REPORT_CHANNEL
from atcs.model.t2t_message import report_quantities
from atcs.properties.property import Assumption, Property
from atcs.properties.separation import LEADER, LEADER_BRAKING, report_behind, report_stop_behind

LEADER_POSITION = Assumption(
    "leader_position",
    "the leader's true front is at or ahead of its min front and its true speed within the accuracy of its "
    "estimate, every cycle; its length >= 0",
    lambda o, p, s, i: o.and_(
        i.front_min_m <= s.leader_rear_m + p.leader_length_m,
        i.speed_est_mps - i.speed_accuracy_mps <= s.leader_speed_mps,
        p.leader_length_m >= o.const(0),
    ),
)


def carried_on(o, p, s, i, nxt):
    """A report carried on is the one the leader's position function gives (its min safe rear and min speed,
    rounded down: T2T-01, T2T-02) and is on its way from the next cycle; else the one on its way stays."""
    rear, speed, _ = report_quantities(
        o, i.front_min_m - p.leader_length_m, o.max(o.const(0), i.speed_est_mps - i.speed_accuracy_mps), i.clock_s
    )
    kept = o.and_(
        o.eq(nxt.on_way, s.on_way),
        o.eq(nxt.on_way_rear_m, s.on_way_rear_m),
        o.eq(nxt.on_way_speed_mps, s.on_way_speed_mps),
    )
    carried = o.and_(nxt.on_way, o.eq(nxt.on_way_rear_m, rear), o.eq(nxt.on_way_speed_mps, speed))
    return o.and_(o.implies(i.sent_on, carried), o.implies(o.not_(i.sent_on), kept))


def _on_its_way(o, p, s, i, out, nxt):
    """:func:`carried_on`, and the report on its way is the one delivered."""
    delivered = o.and_(
        o.eq(out.delivered, s.on_way),
        o.eq(out.delivered_rear_m, s.on_way_rear_m),
        o.eq(out.delivered_speed_mps, s.on_way_speed_mps),
    )
    return o.and_(delivered, carried_on(o, p, s, i, nxt))


def _property(name: str, requirement: str, text: str, holds, assumptions=(), lemmas=()) -> Property:
    return Property(
        name=f"report_channel.{name}",
        requirement=requirement,
        seed="001 §3.2 (Fig. 5 iii, Fig. 6); EN 50159",
        text=text,
        node=REPORT_CHANNEL,
        holds=holds,
        assumptions=assumptions,
        lemmas=lemmas,
    )


PROPERTIES = (
    _property(
        "leader_stop_is_earliest",
        "SEP-10",
        "The leader's speed is >= 0 and its earliest stopping point is its true rear plus its stopping distance from "
        "its true speed at its highest deceleration (as SEP-03 of the two-train node).",
        lambda o, p, s, i, out, nxt: o.and_(
            s.leader_speed_mps >= o.const(0),
            o.eq(
                o.const(2) * p.leader_max_deceleration_mps2 * (s.leader_stop_m - s.leader_rear_m),
                s.leader_speed_mps * s.leader_speed_mps,
            ),
        ),
        (LEADER, LEADER_BRAKING),
    ),
    _property(
        "delivered_rear_behind_leader",
        "SEP-07",
        "Every report the channel delivers, made by the leader's onboard unit at an earlier cycle and delivered "
        "after any delay, repeatedly or out of order, gives a min safe rear at most the leader's current rear (the "
        "two-train proofs' REPORT_REAR).",
        lambda o, p, s, i, out, nxt: o.implies(out.delivered, report_behind(o, out.delivered_rear_m, s.leader_rear_m)),
        (LEADER, LEADER_POSITION),
    ),
    _property(
        "delivered_stop_behind_leader",
        "SEP-08",
        "Every report the channel delivers gives a min speed >= 0 and an earliest stopping point at most the "
        "leader's current one (the two-train proofs' REPORT_STOP): the leader never brakes harder than its highest "
        "deceleration, so that point never moves back after the report is sent.",
        lambda o, p, s, i, out, nxt: o.implies(
            out.delivered, report_stop_behind(o, p, out.delivered_rear_m, out.delivered_speed_mps, s.leader_stop_m)
        ),
        (LEADER, LEADER_BRAKING, LEADER_POSITION),
        ("report_channel.leader_stop_is_earliest",),
    ),
    _property(
        "sent_report_on_its_way",
        "SEP-09",
        "A report the channel carries on is the leader's min safe rear (min front less its length) and min "
        "speed (the estimate less its accuracy, at least 0), rounded down to the cm and cm/s, and is delivered from "
        "the next cycle on until a later one replaces it; the channel delivers nothing else (SEP-07 and SEP-08 are "
        "about reports that do arrive).",
        _on_its_way,
    ),
)

__all__ = ["LEADER_POSITION", "PROPERTIES", "carried_on"]
