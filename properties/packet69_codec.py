"""Packet 69's bits (seed 004 §2.2, Table 1; Subset-026-7 §7.4.2): what the receiver reads is what the sender wrote,
for every code of every field and every N_ITER up to the format's 31.

Over :data:`~atcs.model.platform_packets.PACKET69_CODEC`, every code symbolic: the fields
written by :func:`~atcs.model.platform_packets.packet69_bits`, filled to the format's 32 elements, and read back by
:func:`~atcs.model.platform_packets.packet_from_bits`, the functions the byte codec runs. A packet is the first
L_PACKET bits of that string and the rest are zeros, so the bytes sent are its prefix. Which codes are spare or
reserved, truncation and over-long data are the byte codec's checks around the bits, tested
(tests/model/test_platform_packets.py), not proved.
"""

from __future__ import annotations

from atcs.model.platform_packets import (
    ELEMENT_BITS,
    MAX_ITER,
    P69_BITS,
    P69_INIT_BITS,
    PACKET69_CODEC,
    PACKET_69,
)
from atcs.properties.property import Assumption, Property

ELEMENT_WIDTHS = (("d_trackcond", 15), ("l_trackcond", 15), ("m_platform", 4), ("q_platform", 2))
"""An element's codes, as the codec nodes name them, and their widths."""


def _fits(o, value, width: int):
    """A whole number within ``width`` bits."""
    return o.and_(o.eq(o.floor(value), value), o.const(0) <= value, value <= o.const((1 << width) - 1))


def codes_fit(o, i, scalars: tuple[tuple[str, int], ...]):
    """The codes ``scalars`` (name, width) and every element slot's codes, each within its field."""
    return o.and_(
        *(_fits(o, getattr(i, name), width) for name, width in scalars),
        *(_fits(o, value, width) for name, width in ELEMENT_WIDTHS for value in getattr(i, name)),
    )


def slot_read(o, i, out, k: int, name: str):
    """Element slot ``k``'s code ``name`` read as written."""
    return o.eq(getattr(out, f"read_{name}")[k], getattr(i, name)[k])


COLUMNS = (
    ("distances", "d_trackcond", "D_TRACKCOND"),
    ("lengths", "l_trackcond", "L_TRACKCOND"),
    ("heights", "m_platform", "M_PLATFORM"),
    ("sides", "q_platform", "Q_PLATFORM"),
)
"""An element's codes, one property each (the four together take z3 minutes, each alone under a second): the
property's word, the codec nodes' name, the packet's."""


def slot_zero(o, out, k: int, names: tuple[str, ...] = tuple(name for name, _ in ELEMENT_WIDTHS)):
    """Element slot ``k``'s codes ``names`` read as zeros."""
    return o.and_(*(o.eq(getattr(out, f"read_{name}")[k], o.const(0)) for name in names))


CODES_FIT = Assumption(
    "codes_fit",
    "every code the sender gives is a whole number within its field's bits (Q_DIR, Q_SCALE and Q_PLATFORM 2, "
    "Q_TRACKINIT 1, the distances 15, M_PLATFORM 4, N_ITER 5), in every element slot",
    lambda o, p, s, i: codes_fit(
        o, i, (("q_dir", 2), ("q_scale", 2), ("q_trackinit", 1), ("d_trackinit", 15), ("n_iter", 5))
    ),
)


def _init(o, i):
    return o.eq(i.q_trackinit, o.const(1))


def _header(o, p, s, i, out, nxt):
    return o.and_(
        o.eq(out.read_nid_packet, o.const(PACKET_69)),
        o.eq(out.read_q_dir, i.q_dir),
        o.eq(out.read_q_scale, i.q_scale),
        o.eq(out.read_q_trackinit, i.q_trackinit),
    )


def _length(o, p, s, i, out, nxt):
    init = _init(o, i)
    after_first = ("l_trackcond", "m_platform", "q_platform")
    return o.and_(
        o.eq(
            out.read_l_packet,
            o.ite(init, o.const(P69_INIT_BITS), o.const(P69_BITS) + o.const(ELEMENT_BITS) * i.n_iter),
        ),
        o.implies(init, o.and_(o.eq(out.read_n_iter, o.const(0)), slot_zero(o, out, 0, after_first))),
        *(o.implies(o.or_(init, i.n_iter < o.const(k)), slot_zero(o, out, k)) for k in range(1, MAX_ITER + 1)),
    )


def _column(name: str):
    """Element codes ``name`` read as written, the first element's and the N_ITER after it (with Q_TRACKINIT 1,
    D_TRACKINIT in the first D_TRACKCOND's place); with the distances, N_ITER itself."""

    def holds(o, p, s, i, out, nxt):
        listed = o.and_(
            *((o.eq(out.read_n_iter, i.n_iter),) if name == "d_trackcond" else ()),
            slot_read(o, i, out, 0, name),
            *(o.implies(o.const(k) <= i.n_iter, slot_read(o, i, out, k, name)) for k in range(1, MAX_ITER + 1)),
        )
        if name != "d_trackcond":
            return o.implies(o.not_(_init(o, i)), listed)
        return o.and_(
            o.implies(_init(o, i), o.eq(out.read_d_trackcond[0], i.d_trackinit)),
            o.implies(o.not_(_init(o, i)), listed),
        )

    return holds


def _property(name: str, requirement: str, text: str, holds) -> Property:
    return Property(
        name=f"packet69_codec.{name}",
        requirement=requirement,
        seed="004 §2.2 (Table 1); Subset-026-7 §7.4.2",
        text=text,
        node=PACKET69_CODEC,
        holds=holds,
        assumptions=(CODES_FIT,),
    )


PROPERTIES = (
    _property(
        "header_read_as_written",
        "PKT-01",
        "With every code within its field, the receiver reads packet 69's NID_PACKET as 69 and its Q_DIR, Q_SCALE "
        "and Q_TRACKINIT as written.",
        _header,
    ),
    _property(
        "length_as_sent",
        "PKT-02",
        "With every code within its field, packet 69's L_PACKET reads 41 bits with Q_TRACKINIT 1, else 67 + 36 "
        "N_ITER, and every bit after that many is zero: the packet sent is the first L_PACKET bits, for every "
        "N_ITER from 0 to 31.",
        _length,
    ),
    *(
        _property(
            f"{word}_read_as_written",
            f"PKT-{3 + j:02}",
            f"With every code within its field, the receiver reads packet 69's {field} of the first element and of "
            "each of the N_ITER after it as written, for every N_ITER from 0 to 31"
            + (" (and N_ITER itself; with Q_TRACKINIT 1, D_TRACKINIT)." if name == "d_trackcond" else "."),
            _column(name),
        )
        for j, (word, name, field) in enumerate(COLUMNS)
    ),
)

__all__ = ["CODES_FIT", "COLUMNS", "ELEMENT_WIDTHS", "PROPERTIES", "codes_fit", "slot_read", "slot_zero"]
