"""The bit fields packets are made of (Subset-026-7 §7.3; seed 004 §2.2-2.3 for packets 69 and 44), over
:data:`~atcs.model.bits.FIELD_CODEC`: a value of every width the formats use, and a field of each, all symbolic.

A field's bits and its value are each other's inverse: every whole value below ``2^width`` is written as bits of
0 and 1 that read back as it (PKT-01), and any ``width`` bits read as a value below ``2^width`` that writes back as
those bits (PKT-02). A packet's codec writes and reads its fields one after the other in the order of one layout
(:mod:`atcs.model.platform_packets`), so these two carry to every field of every packet.
"""

from __future__ import annotations

from atcs.model.bits import FIELD_CODEC, FIELD_WIDTHS, field_value
from atcs.properties.property import Assumption, Property


def _by_field(values: tuple) -> list[tuple]:
    fields, start = [], 0
    for width in FIELD_WIDTHS:
        fields.append(values[start : start + width])
        start += width
    return fields


def _bit(o, b):
    return o.or_(o.eq(b, o.const(0)), o.eq(b, o.const(1)))


WHOLE_VALUES_IN_RANGE = Assumption(
    "whole_values_in_range",
    "each value is a whole number in 0 .. 2^width - 1",
    lambda o, p, s, i: o.and_(
        *(
            o.and_(o.eq(o.floor(v), v), o.const(0) <= v, v < o.const(2**w))
            for v, w in zip(p.values, FIELD_WIDTHS, strict=True)
        )
    ),
)

BITS = Assumption("bits", "each bit is 0 or 1", lambda o, p, s, i: o.and_(*(_bit(o, b) for b in i.bits)))


def _written_reads_back(o, p, s, i, out, nxt):
    fields = _by_field(out.encoded)
    return o.and_(
        *(_bit(o, b) for b in out.encoded),
        *(o.eq(field_value(o, bits), v) for bits, v in zip(fields, p.values, strict=True)),
    )


def _read_writes_back(o, p, s, i, out, nxt):
    return o.and_(
        *(o.and_(o.const(0) <= v, v < o.const(2**w)) for v, w in zip(out.decoded, FIELD_WIDTHS, strict=True)),
        *(o.eq(a, b) for a, b in zip(out.reencoded, i.bits, strict=True)),
    )


PROPERTIES = (
    Property(
        name="packets.field_round_trip",
        requirement="PKT-01",
        seed="004 §2.2-2.3, Subset-026-7 §7.3",
        text=(
            "For every width a packet field has (1 to 32 bits) and every whole value below 2^width: the field is "
            "written as bits of 0 and 1, most significant first, that read back as the value."
        ),
        node=FIELD_CODEC,
        holds=_written_reads_back,
        assumptions=(WHOLE_VALUES_IN_RANGE,),
    ),
    Property(
        name="packets.bits_round_trip",
        requirement="PKT-02",
        seed="004 §2.2-2.3, Subset-026-7 §7.3",
        text=(
            "For every width a packet field has and any bits: the value read is in 0 .. 2^width - 1 (a field "
            "never reads out of its range) and is written back as the same bits."
        ),
        node=FIELD_CODEC,
        holds=_read_writes_back,
        assumptions=(BITS,),
    ),
)

__all__ = ["PROPERTIES"]
