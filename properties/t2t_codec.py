"""The T2T report's bits (seed 001 §3.2, Fig. 5 iii; EN 50159): what the receiver reads is what the sender wrote.

Over :data:`~atcs.model.t2t_message.T2T_CODEC`, every field symbolic: the fields
written by :func:`~atcs.model.t2t_message.report_bits` and read back by
:func:`~atcs.model.t2t_message.report_from_bits`, the functions ``encode_report`` and ``decode_report`` run. The
safety code around them (CRC-32) is tested, not proved (tests/model/test_t2t_message.py).
"""

from __future__ import annotations

from atcs.model.t2t_message import T2T_CODEC
from atcs.properties.property import Assumption, Property


def _whole_within(o, value, low: int, high: int):
    return o.and_(o.eq(o.floor(value), value), o.const(low) <= value, value <= o.const(high))


def _fields_in_range(o, p, s, i):
    """Each field, in its unit and rounded down, within what its bits carry (encode_report refuses the rest)."""
    return o.and_(
        _whole_within(o, i.sender_id, 0, (1 << 24) - 1),
        _whole_within(o, i.seq, 0, (1 << 32) - 1),
        _whole_within(o, o.floor(i.sent_s * o.const(1000)), 0, (1 << 32) - 1),
        _whole_within(o, o.floor(i.rear_m * o.const(100)), -(1 << 31), (1 << 31) - 1),
        _whole_within(o, o.floor(i.speed_mps * o.const(100)), 0, (1 << 16) - 1),
    )


FIELDS_IN_RANGE = Assumption(
    "fields_in_range",
    "the sender's identity and sequence number whole and within 24 and 32 bits; its time stamp in ms, rear in cm "
    "and speed in cm/s, rounded down, within 32 bits, 32 bits signed and 16 bits",
    _fields_in_range,
)


def _rounded(o, value, per_unit: int):
    return o.floor(value * o.const(per_unit)) / o.const(per_unit)


def _identity_and_number(o, p, s, i, out, nxt):
    return o.and_(o.eq(out.read_sender_id, i.sender_id), o.eq(out.read_seq, i.seq))


def _time_stamp(o, p, s, i, out, nxt):
    return o.eq(out.read_sent_s, _rounded(o, i.sent_s, 1000))


def _rear(o, p, s, i, out, nxt):
    return o.eq(out.read_rear_m, _rounded(o, i.rear_m, 100))


def _speed(o, p, s, i, out, nxt):
    return o.eq(out.read_speed_mps, _rounded(o, i.speed_mps, 100))


def _within_range(o, p, s, i, out, nxt):
    return o.and_(
        _whole_within(o, out.read_sender_id, 0, (1 << 24) - 1),
        _whole_within(o, out.read_seq, 0, (1 << 32) - 1),
        _whole_within(o, out.read_sent_s * o.const(1000), 0, (1 << 32) - 1),
        _whole_within(o, out.read_rear_m * o.const(100), -(1 << 31), (1 << 31) - 1),
        _whole_within(o, out.read_speed_mps * o.const(100), 0, (1 << 16) - 1),
    )


def _read_as_written(name: str, requirement: str, text: str, holds) -> Property:
    return Property(
        name=f"t2t_codec.{name}",
        requirement=requirement,
        seed="001 §3.2 (Fig. 5 iii); EN 50159",
        text=text,
        node=T2T_CODEC,
        holds=holds,
        assumptions=(FIELDS_IN_RANGE,),
    )


PROPERTIES = (
    _read_as_written(
        "identity_and_number_read_as_written",
        "T2T-05",
        "With every field within its range, the receiver reads from the bits the sender's identity and sequence "
        "number exactly as written.",
        _identity_and_number,
    ),
    _read_as_written(
        "time_stamp_read_as_written",
        "T2T-06",
        "With every field within its range, the receiver reads from the bits the sender's time stamp rounded down "
        "to the millisecond.",
        _time_stamp,
    ),
    _read_as_written(
        "rear_read_as_written",
        "T2T-07",
        "With every field within its range, the receiver reads from the bits the sender's rear rounded down to the "
        "centimetre, a rear behind the line's origin (in two's complement) included.",
        _rear,
    ),
    _read_as_written(
        "speed_read_as_written",
        "T2T-08",
        "With every field within its range, the receiver reads from the bits the sender's speed rounded down to the "
        "cm/s.",
        _speed,
    ),
    Property(
        name="t2t_codec.fields_within_range",
        requirement="T2T-09",
        seed="001 §3.2 (Fig. 5 iii); EN 50159",
        text="Whatever the sender's values, every field the receiver reads lies within its range: a whole identity "
        "within 24 bits, a sequence number and a time stamp within 32 bits, a rear within +-21,474,836.48 m and a "
        "speed within 655.35 m/s, each in whole units of its field.",
        node=T2T_CODEC,
        holds=_within_range,
    ),
)

__all__ = ["PROPERTIES"]
