"""User packet 44's bits (seed 004 §2.3, Table 2): what the receiver reads is what the sender wrote, for every code
of every field and every N_ITER up to the format's 31.

Over :data:`~atcs.model.platform_packets.PACKET44_CODEC`, as :mod:`atcs.properties.packet69_codec` over packet 69:
the fields written by :func:`~atcs.model.platform_packets.packet44_bits`, filled to the format's 31 elements, and
read back by :func:`~atcs.model.platform_packets.packet_from_bits`.
"""

from __future__ import annotations

from atcs.model.platform_packets import (
    ELEMENT_BITS,
    MAX_ITER,
    NID_XDATA_PLATFORMS,
    NID_XUSER_PLATFORMS,
    P44_BITS,
    PACKET44_CODEC,
    PACKET_44,
)
from atcs.properties.packet69_codec import COLUMNS, codes_fit, slot_read, slot_zero
from atcs.properties.property import Assumption, Property

CODES_FIT = Assumption(
    "codes_fit",
    "every code the sender gives is a whole number within its field's bits (Q_DIR, Q_SCALE and Q_PLATFORM 2, the "
    "distances 15, M_PLATFORM 4, N_ITER 5), in every element slot",
    lambda o, p, s, i: codes_fit(o, i, (("q_dir", 2), ("q_scale", 2), ("n_iter", 5))),
)


def _header(o, p, s, i, out, nxt):
    return o.and_(
        o.eq(out.read_nid_packet, o.const(PACKET_44)),
        o.eq(out.read_q_dir, i.q_dir),
        o.eq(out.read_nid_xuser, o.const(NID_XUSER_PLATFORMS)),
        o.eq(out.read_nid_xdata, o.const(NID_XDATA_PLATFORMS)),
        o.eq(out.read_q_scale, i.q_scale),
    )


def _length(o, p, s, i, out, nxt):
    return o.and_(
        o.eq(out.read_l_packet, o.const(P44_BITS) + o.const(ELEMENT_BITS) * i.n_iter),
        *(o.implies(i.n_iter <= o.const(k), slot_zero(o, out, k)) for k in range(MAX_ITER)),
    )


def _column(name: str):
    """Element codes ``name`` of the N_ITER elements read as written; with the distances, N_ITER itself."""

    def holds(o, p, s, i, out, nxt):
        return o.and_(
            *((o.eq(out.read_n_iter, i.n_iter),) if name == "d_trackcond" else ()),
            *(o.implies(o.const(k) < i.n_iter, slot_read(o, i, out, k, name)) for k in range(MAX_ITER)),
        )

    return holds


def _property(name: str, requirement: str, text: str, holds) -> Property:
    return Property(
        name=f"packet44_codec.{name}",
        requirement=requirement,
        seed="004 §2.3 (Table 2)",
        text=text,
        node=PACKET44_CODEC,
        holds=holds,
        assumptions=(CODES_FIT,),
    )


PROPERTIES = (
    _property(
        "header_read_as_written",
        "PKT-07",
        "With every code within its field, the receiver reads user packet 44's NID_PACKET as 44, NID_XUSER as 210, "
        "NID_XDATA as 1 and its Q_DIR and Q_SCALE as written.",
        _header,
    ),
    _property(
        "length_as_sent",
        "PKT-08",
        "With every code within its field, user packet 44's L_PACKET reads 47 + 36 N_ITER bits and every bit after "
        "that many is zero: the packet sent is the first L_PACKET bits, for every N_ITER from 0 to 31.",
        _length,
    ),
    *(
        _property(
            f"{word}_read_as_written",
            f"PKT-{9 + j:02}",
            f"With every code within its field, the receiver reads user packet 44's {field} of each of its N_ITER "
            "elements as written, for every N_ITER from 0 to 31"
            + (" (and N_ITER itself)." if name == "d_trackcond" else "."),
            _column(name),
        )
        for j, (word, name, field) in enumerate(COLUMNS)
    ),
)

__all__ = ["CODES_FIT", "PROPERTIES"]
