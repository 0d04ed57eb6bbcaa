"""What a T2T report says of its sender (seed 001 §3.2, Fig. 5 iii and Fig. 6; EN 50159): never more than is true.

Over :data:`~atcs.model.t2t_message.T2T_REPORT`, every value symbolic: the sender's min safe rear (its position
function's min front less its length) and min speed (the estimate less its accuracy, at least 0), each rounded
down to the unit its field carries, and the time stamp, rounded down to the millisecond. With the sender's
position true (the true front within its interval, the true speed within the accuracy of the estimate: what
POS-22 and the speed bounds give), the rear and speed reported are at most the true ones: what the two-train
proofs assume of an intact report (REPORT_REAR, REPORT_STOP) holds of it when it is sent, and the leader's rear
and earliest stopping point never move back afterwards (SEP-04).
"""

from __future__ import annotations

from atcs.model.t2t_message import T2T_REPORT
from atcs.properties.property import Assumption, Property

SENDER_POSITION = Assumption(
    "sender_position",
    "the sender's true front is at or ahead of its min front, its true speed (>= 0) within the accuracy of its "
    "estimate, and its length >= 0",
    lambda o, p, s, i: o.and_(
        i.front_min_m <= i.true_front_m,
        i.true_speed_mps >= o.const(0),
        i.speed_est_mps - i.speed_accuracy_mps <= i.true_speed_mps,
        p.train_length_m >= o.const(0),
    ),
)


def _rear(o, p, s, i, out, nxt):
    min_rear = i.front_min_m - p.train_length_m
    return o.and_(
        out.report_rear_m <= i.true_front_m - p.train_length_m,
        out.report_rear_m <= min_rear,
        min_rear - o.const("1/100") < out.report_rear_m,
    )


def _speed(o, p, s, i, out, nxt):
    min_speed = o.max(o.const(0), i.speed_est_mps - i.speed_accuracy_mps)
    return o.and_(
        o.const(0) <= out.report_speed_mps,
        out.report_speed_mps <= i.true_speed_mps,
        min_speed - o.const("1/100") < out.report_speed_mps,
    )


def _time_stamp(o, p, s, i, out, nxt):
    return o.and_(out.report_sent_s <= i.clock_s, i.clock_s - o.const("1/1000") < out.report_sent_s)


def _whole_units(o, p, s, i, out, nxt):
    def whole(value, per_unit):
        scaled = value * o.const(per_unit)
        return o.eq(o.floor(scaled), scaled)

    return o.and_(whole(out.report_rear_m, 100), whole(out.report_speed_mps, 100), whole(out.report_sent_s, 1000))


def _property(name, requirement, seed, text, holds, assumptions=(SENDER_POSITION,)):
    return Property(
        name=name, requirement=requirement, seed=seed, text=text, node=T2T_REPORT, holds=holds, assumptions=assumptions
    )


PROPERTIES = (
    _property(
        "t2t_report.rear_at_most_the_true_rear",
        "T2T-01",
        "001 §3.2 (Fig. 6)",
        "The rear a report carries is at most the sender's true rear: its min safe rear rounded down to the "
        "centimetre (less than 1 cm below it).",
        _rear,
    ),
    _property(
        "t2t_report.speed_at_most_the_true_speed",
        "T2T-02",
        "001 §3.2 (Fig. 6), 000 §2.2",
        "The speed a report carries is at least 0 and at most the sender's true speed: its estimate less the "
        "accuracy (at least 0) rounded down to the cm/s (less than 1 cm/s below it), so the earliest stopping "
        "point it gives is never beyond the sender's own.",
        _speed,
    ),
    _property(
        "t2t_report.time_stamp_not_ahead",
        "T2T-03",
        "EN 50159 (time stamp)",
        "The time stamp a report carries is the sender's clock rounded down to the millisecond: never ahead of it, "
        "less than 1 ms behind.",
        _time_stamp,
        assumptions=(),
    ),
    _property(
        "t2t_report.whole_units",
        "T2T-04",
        "001 §3.2 (Fig. 5 iii)",
        "A report carries its rear in whole centimetres, its speed in whole cm/s and its time stamp in whole "
        "milliseconds, the units of its fields (D_REAR, V_MIN, T_SENT): the bytes carry exactly the values T2T-01 "
        "to T2T-03 are about.",
        _whole_units,
        assumptions=(),
    ),
)
