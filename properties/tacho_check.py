"""The tachometer's plausibility check (seed 001 §3.2, 002 §3.1), tested on its own (seed 001 §3.4).

The node runs :data:`~atcs.model.position.TACHO_CHECK`, the very function the position node calls, with all
its data symbolic.
"""

from __future__ import annotations

from atcs.model.position import TACHO_CHECK
from atcs.properties.property import Assumption, Property


def _sensors(o, p, s, i):
    dt2, e = p.cycle_s * p.cycle_s, p.tacho_error
    change = i.distance_m - i.last_distance_m

    def within(true_m, tacho_m):
        return o.and_(tacho_m >= o.const(0), true_m - tacho_m <= e * tacho_m, tacho_m - true_m <= e * tacho_m)

    return o.and_(
        o.const(0) <= e,
        e < o.const(1),
        p.cycle_s > o.const(0),
        within(i.distance_m, i.tacho_m),
        within(i.last_distance_m, i.last_tacho_m),
        change <= p.max_acceleration_mps2 * dt2,
        -change <= p.max_deceleration_mps2 * dt2,
    )


SENSORS = Assumption(
    "sensors",
    "0 <= tachometer error < 1, cycle > 0; both cycles' tachometer distances >= 0 and within the error of the "
    "true distances; the true distance changes by at most max_acceleration * dt^2 (max_deceleration * dt^2 down)",
    _sensors,
)


PROPERTIES = (
    Property(
        name="tacho_check.plausible_within_bounds",
        requirement="POS-17",
        seed="001 §3.2, 002 §3.1",
        text="No false alarm: tachometer distances within their error of true distances that change within the "
        "acceleration bounds are never found implausible.",
        node=TACHO_CHECK,
        holds=lambda o, p, s, i, out, nxt: o.not_(out.implausible_tacho),
        assumptions=(SENSORS,),
    ),
    Property(
        name="tacho_check.negative_is_implausible",
        requirement="POS-18",
        seed="001 §3.2",
        text="A negative tachometer distance (the train rolling back, or a fault) is always implausible.",
        node=TACHO_CHECK,
        holds=lambda o, p, s, i, out, nxt: o.implies(i.tacho_m < o.const(0), out.implausible_tacho),
    ),
)
