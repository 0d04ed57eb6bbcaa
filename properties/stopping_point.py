"""The leader's earliest stopping point (seed 000 §2.2, 002 §4.2), tested on its own (seed 001 §3.4).

The node runs :data:`~atcs.model.authority.STOPPING_POINT`, the very function the authority calls, with
all its data symbolic.
"""

from __future__ import annotations

from atcs.model.authority import STOPPING_POINT
from atcs.model.curves import MIN_SPAN
from atcs.properties.property import Assumption, Property

LEADER_REPORT = Assumption(
    "leader_report",
    f"the reported speed is >= 0 and the leader's highest deceleration at least {MIN_SPAN} m/s^2 (below any "
    "brake's: the guard in stopping_point_m is for invalid data only)",
    lambda o, p, s, i: o.and_(i.speed_mps >= o.const(0), p.leader_max_deceleration_mps2 >= o.const(MIN_SPAN)),
)


def _stop_ahead_of_rear(o, p, s, i, out, nxt):
    return o.and_(out.stop_m >= i.rear_m, o.implies(o.eq(i.speed_mps, o.const(0)), o.eq(out.stop_m, i.rear_m)))


def _stop_reachable(o, p, s, i, out, nxt):
    """v^2 = 2 * d * (stop - rear): braking at d from the reported speed ends exactly at the stopping point."""
    two = o.const(2)
    return o.eq(i.speed_mps * i.speed_mps, two * p.leader_max_deceleration_mps2 * (out.stop_m - i.rear_m))


PROPERTIES = (
    Property(
        name="stopping_point.ahead_of_rear",
        requirement="AUT-12",
        seed="000 §2.2, 002 §4.2",
        text="The leader's earliest stopping point is never behind its reported rear, and is the rear itself at "
        "standstill.",
        node=STOPPING_POINT,
        holds=_stop_ahead_of_rear,
        assumptions=(LEADER_REPORT,),
    ),
    Property(
        name="stopping_point.reached_at_max_deceleration",
        requirement="AUT-13",
        seed="000 §2.2, 002 §4.2",
        text="Braking at its highest deceleration from the reported speed, the leader's rear stops exactly at the "
        "stopping point (v^2 = 2 * d * (stop - rear)): no earlier stop is possible.",
        node=STOPPING_POINT,
        holds=_stop_reachable,
        assumptions=(LEADER_REPORT,),
    ),
)
