"""Platform data from the wayside, bit-exact: ETCS packet 69 and user packet 44 (seed 004 §2.2-2.3, Tables 1-2).

Packet 69, *track conditions: station platforms* (Subset-026-7 §7.4.2)::

    NID_PACKET 8 (69)  Q_DIR 2  L_PACKET 13  Q_SCALE 2  Q_TRACKINIT 1
    Q_TRACKINIT = 1:   D_TRACKINIT 15
    Q_TRACKINIT = 0:   D_TRACKCOND 15  L_TRACKCOND 15  M_PLATFORM 4  Q_PLATFORM 2
                       N_ITER 5, then N_ITER times D_TRACKCOND L_TRACKCOND M_PLATFORM Q_PLATFORM

User packet 44 carrying the same platform elements (seed 004 Table 2)::

    NID_PACKET 8 (44)  Q_DIR 2  L_PACKET 13  NID_XUSER 9 (210)  NID_XDATA 8 (1: platform information)
    Q_SCALE 2  N_ITER 5, then N_ITER times D_TRACKCOND L_TRACKCOND M_PLATFORM Q_PLATFORM

Each element's D_TRACKCOND is the distance from the previous element's start (the
first's from the packet's reference location, the balise group that sent it) and
L_TRACKCOND the platform's length, both in units of Q_SCALE. L_PACKET counts the
packet's bits, header included; the packet is sent as whole bytes, zero padded.

The dataclasses hold the raw codes, so ``decode(encode(x)) == x`` holds exactly; a
spare or reserved code (Q_DIR 11b, Q_SCALE 11b, Q_PLATFORM 11b, M_PLATFORM 14 and
15), a truncated or over-long packet, or an L_PACKET that disagrees with the fields
is a :class:`~atcs.model.bits.PacketError` naming the field and its bit offset.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Generic

from atcs.model.bits import PacketError, check_packet_end
from atcs.model.node import Stateless, stateless_node
from atcs.model.ops import B, BitString, N, Ops
from atcs.model.ops.exact import EXACT

PACKET_69, PACKET_44 = 69, 44
NID_XUSER_PLATFORMS, NID_XDATA_PLATFORMS = 210, 1
"""Seed 004 §2.3.1: the user packet's system id and data id for platform information."""

Q_DIR = {0: "reverse", 1: "nominal", 2: "both directions"}
"""Q_DIR 11b is spare."""
Q_SCALE_M = {0: Fraction(1, 10), 1: Fraction(1), 2: Fraction(10)}
"""Q_SCALE: the distance unit in metres (10 cm, 1 m, 10 m); 11b is spare."""
Q_PLATFORM = {0: "left", 1: "right", 2: "both"}
"""The side of the train (in its direction of travel) the platform is on; 11b is spare."""
M_PLATFORM_MM = {
    0: 200,
    1: 300,
    2: 550,
    3: 580,
    4: 680,
    5: 685,
    6: 730,
    7: 760,
    8: 840,
    9: 900,
    10: 915,
    11: 920,
    12: 960,
    13: 1100,
}
"""M_PLATFORM: the platform's nominal height above rail level (mm); 14 and 15 are spare (ERA_ERTMS_040001)."""

MAX_DISTANCE = (1 << 15) - 1
MAX_ITER = (1 << 5) - 1
ELEMENT_BITS = 15 + 15 + 4 + 2


@dataclass(frozen=True)
class PlatformElement:
    """One platform, as coded (seed 004 Table 1)."""

    d_trackcond: int
    """Distance from the previous element's start (the first's from the reference location), Q_SCALE units."""
    l_trackcond: int
    """The platform's length, Q_SCALE units."""
    m_platform: int
    """Nominal height code (:data:`M_PLATFORM_MM`)."""
    q_platform: int
    """Side code (:data:`Q_PLATFORM`)."""


@dataclass(frozen=True)
class Packet69:
    """ETCS packet 69, track conditions: station platforms."""

    q_dir: int
    q_scale: int
    elements: tuple[PlatformElement, ...] = ()
    """1 to 32 elements with ``q_trackinit`` 0; none with ``q_trackinit`` 1."""
    q_trackinit: int = 0
    """1: an empty profile (no platforms), initial states resumed at ``d_trackinit``."""
    d_trackinit: int | None = None


@dataclass(frozen=True)
class Packet44Platforms:
    """User packet 44 with platform information (NID_XUSER 210, NID_XDATA 1; seed 004 Table 2)."""

    q_dir: int
    q_scale: int
    elements: tuple[PlatformElement, ...] = ()
    """0 to 31 elements."""


PlatformPacket = Packet69 | Packet44Platforms


# --- the layout: every field of a packet filled to its capacity, in order ---------------------------------


@dataclass(frozen=True)
class _Field:
    name: str
    width: int
    codes: dict | None = None
    """The codes the field may take, with their meanings (None: any value that fits its width)."""
    refused: str = "not allowed"
    """What a code outside ``codes`` is called when a packet is read."""


def _header(nid_packet: int) -> tuple[_Field, ...]:
    return (
        _Field("NID_PACKET", 8, {nid_packet: f"packet {nid_packet}"}, f"not packet {nid_packet}"),
        _Field("Q_DIR", 2, Q_DIR, "spare"),
        _Field("L_PACKET", 13),
    )


def _element(k: int) -> tuple[_Field, ...]:
    """Element ``k``'s fields (0: packet 69's first, before N_ITER, named without a number)."""
    suffix = f"({k})" if k else ""
    return (
        _Field(f"D_TRACKCOND{suffix}", 15),
        _Field(f"L_TRACKCOND{suffix}", 15),
        _Field(f"M_PLATFORM{suffix}", 4, M_PLATFORM_MM, "reserved"),
        _Field(f"Q_PLATFORM{suffix}", 2, Q_PLATFORM, "spare"),
    )


_Q_SCALE = _Field("Q_SCALE", 2, Q_SCALE_M, "spare")
_N_ITER = _Field("N_ITER", 5)
P69_LAYOUT = (
    *_header(PACKET_69),
    _Q_SCALE,
    _Field("Q_TRACKINIT", 1, {0: "platforms follow", 1: "initial states"}),
    *_element(0),
    _N_ITER,
    *(field for k in range(1, MAX_ITER + 1) for field in _element(k)),
)
"""Packet 69 with 32 elements, field by field. With Q_TRACKINIT 1, D_TRACKINIT takes the first D_TRACKCOND's bits
and the packet ends there; otherwise it ends after element N_ITER."""
P69_INIT_LAYOUT = (*P69_LAYOUT[:5], _Field("D_TRACKINIT", 15))
P69_FIRST_ELEMENT = 5
"""Where packet 69's first element starts in :data:`P69_LAYOUT` (N_ITER follows it)."""
P44_LAYOUT = (
    *_header(PACKET_44),
    _Field("NID_XUSER", 9, {NID_XUSER_PLATFORMS: "platform data (seed 004)"}, "another user system"),
    _Field("NID_XDATA", 8, {NID_XDATA_PLATFORMS: "platform information"}, "not platform information"),
    _Q_SCALE,
    _N_ITER,
    *(field for k in range(1, MAX_ITER + 1) for field in _element(k)),
)
"""User packet 44 with 31 elements, field by field; it ends after element N_ITER."""
P44_FIRST_ELEMENT = 7


def _bits(layout) -> int:
    return sum(field.width for field in layout)


P69_INIT_BITS = _bits(P69_INIT_LAYOUT)
P69_BITS = _bits(P69_LAYOUT[: P69_FIRST_ELEMENT + 5])
"""Packet 69's length with its first element alone (N_ITER 0); each further element adds :data:`ELEMENT_BITS`."""
P44_BITS = _bits(P44_LAYOUT[:P44_FIRST_ELEMENT])
"""Packet 44's length without elements."""


# --- the codec as step functions: the bits filled to the capacity -------------------------------------------


@dataclass(frozen=True)
class Packet69Fields(Generic[N, B]):
    """Packet 69's codes as the sender gives them, its 32 element slots filled (those after element N_ITER are not
    sent, whatever they hold)."""

    q_dir: N
    q_scale: N
    q_trackinit: N
    d_trackinit: N
    n_iter: N
    """The elements after the first."""
    d_trackcond: tuple[N, ...]
    l_trackcond: tuple[N, ...]
    m_platform: tuple[N, ...]
    q_platform: tuple[N, ...]


@dataclass(frozen=True)
class Packet44Fields(Generic[N, B]):
    """Packet 44's codes as the sender gives them, its 31 element slots filled (those from N_ITER on not sent)."""

    q_dir: N
    q_scale: N
    n_iter: N
    d_trackcond: tuple[N, ...]
    l_trackcond: tuple[N, ...]
    m_platform: tuple[N, ...]
    q_platform: tuple[N, ...]


def _slot(o: Ops, f, k: int, sent) -> list:
    """Element slot ``k``'s four codes, or zeros where it is not sent."""
    zero = o.const(0)
    return [o.ite(sent, column[k], zero) for column in (f.d_trackcond, f.l_trackcond, f.m_platform, f.q_platform)]


def packet69_bits(o: Ops, f: Packet69Fields):
    """Packet 69's bits, :data:`P69_LAYOUT` filled to its 32 elements: the packet, L_PACKET long, then zeros (with
    Q_TRACKINIT 1, D_TRACKINIT in the first D_TRACKCOND's bits and nothing after it)."""
    init = o.eq(f.q_trackinit, o.const(1))
    listed, zero = o.not_(init), o.const(0)
    length = o.ite(init, o.const(P69_INIT_BITS), o.const(P69_BITS) + o.const(ELEMENT_BITS) * f.n_iter)
    first = [o.ite(init, f.d_trackinit, f.d_trackcond[0]), *_slot(o, f, 0, listed)[1:]]
    values = [o.const(PACKET_69), f.q_dir, length, f.q_scale, f.q_trackinit, *first, o.ite(listed, f.n_iter, zero)]
    for k in range(1, MAX_ITER + 1):
        values += _slot(o, f, k, o.and_(listed, o.const(k) <= f.n_iter))
    return o.pack_bits(tuple(zip(values, (field.width for field in P69_LAYOUT), strict=True)))


def packet44_bits(o: Ops, f: Packet44Fields):
    """Packet 44's bits, :data:`P44_LAYOUT` filled to its 31 elements: the packet, L_PACKET long, then zeros."""
    length = o.const(P44_BITS) + o.const(ELEMENT_BITS) * f.n_iter
    values = [
        o.const(PACKET_44),
        f.q_dir,
        length,
        o.const(NID_XUSER_PLATFORMS),
        o.const(NID_XDATA_PLATFORMS),
        f.q_scale,
        f.n_iter,
    ]
    for k in range(MAX_ITER):
        values += _slot(o, f, k, o.const(k) < f.n_iter)
    return o.pack_bits(tuple(zip(values, (field.width for field in P44_LAYOUT), strict=True)))


def packet_from_bits(o: Ops, layout: tuple[_Field, ...], bits) -> tuple:
    """Every field of ``layout`` read from ``bits`` (from :func:`packet69_bits` or :func:`packet44_bits`)."""
    return o.unpack_bits(bits, tuple(field.width for field in layout))


# --- the codec's proofs: the sender's fields written and read back ------------------------------------------


@dataclass(frozen=True)
class Packet69Read(Generic[N, B]):
    """What the receiver reads of packet 69's bits, field by field (the elements' slots by number, the first at
    index 0)."""

    read_nid_packet: N
    read_q_dir: N
    read_l_packet: N
    read_q_scale: N
    read_q_trackinit: N
    read_n_iter: N
    read_d_trackcond: tuple[N, ...]
    read_l_trackcond: tuple[N, ...]
    read_m_platform: tuple[N, ...]
    read_q_platform: tuple[N, ...]


@dataclass(frozen=True)
class Packet44Read(Generic[N, B]):
    """What the receiver reads of packet 44's bits, field by field."""

    read_nid_packet: N
    read_q_dir: N
    read_l_packet: N
    read_nid_xuser: N
    read_nid_xdata: N
    read_q_scale: N
    read_n_iter: N
    read_d_trackcond: tuple[N, ...]
    read_l_trackcond: tuple[N, ...]
    read_m_platform: tuple[N, ...]
    read_q_platform: tuple[N, ...]


def _columns(values) -> tuple[tuple, ...]:
    """Element slots' fields (four per slot, in order) as four columns."""
    return tuple(tuple(values[c::4]) for c in range(4))


def packet69_codec_step(o: Ops, p: Stateless, s: Stateless, i: Packet69Fields):
    read, first = packet_from_bits(o, P69_LAYOUT, packet69_bits(o, i)), P69_FIRST_ELEMENT
    elements = _columns((*read[first : first + 4], *read[first + 5 :]))
    return s, Packet69Read(*read[:first], read[first + 4], *elements)


def packet44_codec_step(o: Ops, p: Stateless, s: Stateless, i: Packet44Fields):
    read = packet_from_bits(o, P44_LAYOUT, packet44_bits(o, i))
    return s, Packet44Read(*read[:P44_FIRST_ELEMENT], *_columns(read[P44_FIRST_ELEMENT:]))


_SLOTS69 = {name: MAX_ITER + 1 for name in ("d_trackcond", "l_trackcond", "m_platform", "q_platform")}
PACKET69_CODEC = stateless_node(
    name="packet69_codec",
    params=Stateless,
    inputs=Packet69Fields,
    outputs=Packet69Read,
    step=packet69_codec_step,
    seed="004 §2.2 (Table 1); Subset-026-7 §7.4.2",
    sizes={**_SLOTS69, **{f"read_{name}": size for name, size in _SLOTS69.items()}},
)
"""Packet 69 written as bits and read back, every code symbolic (N_ITER too)."""

PACKET44_CODEC = stateless_node(
    name="packet44_codec",
    params=Stateless,
    inputs=Packet44Fields,
    outputs=Packet44Read,
    step=packet44_codec_step,
    seed="004 §2.3 (Table 2)",
    sizes={name: size - 1 for name, size in PACKET69_CODEC.sizes.items()},
)
"""User packet 44 written as bits and read back, every code symbolic (N_ITER too)."""


# --- bytes: the codec's bits, their codes checked ---------------------------------------------------------


def _check_values(packet: str, layout, values, offset: int = 0) -> None:
    """The codes a sender gives, field by field from bit ``offset``: each an allowed code and a whole number that
    fits its field."""
    for field, value in zip(layout, values, strict=True):
        if field.codes is not None and value not in field.codes:
            raise PacketError(packet, field.name, offset, f"{value!r} is not allowed (allowed: {sorted(field.codes)})")
        if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value < 1 << field.width:
            raise PacketError(
                packet,
                field.name,
                offset,
                f"{value!r} does not fit {field.width} bits (0..{(1 << field.width) - 1})",
            )
        offset += field.width


def _element_values(elements) -> list[int]:
    return [v for e in elements for v in (e.d_trackcond, e.l_trackcond, e.m_platform, e.q_platform)]


def _slots(elements, count: int) -> tuple[tuple[Fraction, ...], ...]:
    """The elements' codes as four columns of ``count`` slots, the unused ones 0."""
    filled = [Fraction(v) for v in _element_values(elements)] + [Fraction(0)] * 4 * (count - len(elements))
    return _columns(filled)


def _sent(bits: BitString, length: int) -> bytes:
    """The packet's first ``length`` bits, zero padded to whole bytes (the bits after them are zeros:
    PKT-02, PKT-05)."""
    padding = -length % 8
    return ((bits.value >> (bits.width - length)) << padding).to_bytes((length + padding) // 8, "big")


def encode_packet69(packet: Packet69) -> bytes:
    """Packet 69's bytes (:func:`packet69_bits`); a code that is not allowed or does not fit its field raises
    :class:`PacketError` naming it and the bit it starts at."""
    name = "packet 69"
    _check_values(name, P69_LAYOUT[:5], (PACKET_69, packet.q_dir, 0, packet.q_scale, packet.q_trackinit))
    init_at = _bits(P69_LAYOUT[:5])
    if packet.q_trackinit:
        if packet.elements or packet.d_trackinit is None:
            raise PacketError(name, "D_TRACKINIT", init_at, "Q_TRACKINIT 1 needs D_TRACKINIT and no platform elements")
        _check_values(name, P69_INIT_LAYOUT[5:], (packet.d_trackinit,), init_at)
        fields = Packet69Fields(
            *map(Fraction, (packet.q_dir, packet.q_scale, 1, packet.d_trackinit, 0)), *_slots((), 32)
        )
        return _sent(packet69_bits(EXACT, fields), P69_INIT_BITS)
    if packet.d_trackinit is not None:
        raise PacketError(name, "D_TRACKINIT", init_at, "given with Q_TRACKINIT 0")
    if not 1 <= len(packet.elements) <= MAX_ITER + 1:
        raise PacketError(
            name,
            "N_ITER",
            init_at + ELEMENT_BITS,
            f"{len(packet.elements)} elements; Q_TRACKINIT 0 needs 1 to {MAX_ITER + 1}",
        )
    first, *rest = packet.elements
    n_iter = len(rest)
    layout = P69_LAYOUT[5 : P69_FIRST_ELEMENT + 5 + 4 * n_iter]
    _check_values(name, layout, [*_element_values([first]), n_iter, *_element_values(rest)], init_at)
    fields = Packet69Fields(
        *map(Fraction, (packet.q_dir, packet.q_scale, 0, 0, n_iter)), *_slots(packet.elements, MAX_ITER + 1)
    )
    return _sent(packet69_bits(EXACT, fields), P69_BITS + ELEMENT_BITS * n_iter)


def encode_packet44(packet: Packet44Platforms) -> bytes:
    """User packet 44's bytes (:func:`packet44_bits`); errors as :func:`encode_packet69`'s."""
    name = "packet 44"
    header = P44_LAYOUT[: P44_FIRST_ELEMENT - 1]
    _check_values(name, header, (PACKET_44, packet.q_dir, 0, NID_XUSER_PLATFORMS, NID_XDATA_PLATFORMS, packet.q_scale))
    if len(packet.elements) > MAX_ITER:
        raise PacketError(name, "N_ITER", _bits(header), f"{len(packet.elements)} elements; at most {MAX_ITER}")
    n_iter = len(packet.elements)
    layout = P44_LAYOUT[P44_FIRST_ELEMENT : P44_FIRST_ELEMENT + 4 * n_iter]
    _check_values(name, layout, _element_values(packet.elements), P44_BITS)
    fields = Packet44Fields(*map(Fraction, (packet.q_dir, packet.q_scale, n_iter)), *_slots(packet.elements, MAX_ITER))
    return _sent(packet44_bits(EXACT, fields), P44_BITS + ELEMENT_BITS * n_iter)


def _read_values(packet: str, data: bytes, layout: tuple[_Field, ...], shape) -> list[int]:
    """The fields of the packet in ``data``, read by :func:`packet_from_bits` (the bytes zero padded or cut to the
    layout's capacity); ``shape(values)`` gives the fields the packet holds, a prefix of ``layout``. A field past the
    data's end or with a code that is not allowed raises :class:`PacketError`, the first in the packet's order; so
    does an L_PACKET other than the fields' length, or anything but zero padding to the byte after them."""
    capacity, size = _bits(layout), 8 * len(data)
    number = int.from_bytes(data, "big")
    number = number << (capacity - size) if size <= capacity else number >> (size - capacity)
    values = [int(v) for v in packet_from_bits(EXACT, layout, BitString(number, capacity))]
    offset = 0
    for field, value in zip(shape(values), values, strict=False):  # the packet's fields, a prefix of its layout
        if offset + field.width > size:
            raise PacketError(
                packet,
                field.name,
                offset,
                f"truncated: needs {field.width} bits, {size - offset} left in {size // 8} bytes",
            )
        if field.codes is not None and value not in field.codes:
            listed = ", ".join(f"{c:0{field.width}b}b {m}" for c, m in field.codes.items())
            raise PacketError(
                packet,
                field.name,
                offset,
                f"{value:0{field.width}b}b ({value}) is {field.refused}; allowed: {listed}",
            )
        offset += field.width
    check_packet_end(packet, data, offset, values[2])
    return values


def _elements(values) -> tuple[PlatformElement, ...]:
    return tuple(PlatformElement(*values[j : j + 4]) for j in range(0, len(values), 4))


def decode_packet69(data: bytes) -> Packet69:
    """Packet 69 from its bytes (:class:`PacketError` on anything but a well-formed packet)."""

    def shape(values):
        if values[4]:
            return P69_INIT_LAYOUT
        return P69_LAYOUT[: P69_FIRST_ELEMENT + 5 + 4 * values[P69_FIRST_ELEMENT + 4]]

    values = _read_values("packet 69", data, P69_LAYOUT, shape)
    _, q_dir, _, q_scale, init, *first = values[: P69_FIRST_ELEMENT + 4]
    if init:
        return Packet69(q_dir, q_scale, (), 1, first[0])
    n_iter = values[P69_FIRST_ELEMENT + 4]
    start = P69_FIRST_ELEMENT + 5
    return Packet69(q_dir, q_scale, _elements([*first, *values[start : start + 4 * n_iter]]))


def decode_packet44(data: bytes) -> Packet44Platforms:
    """User packet 44 with platform information from its bytes."""
    start = P44_FIRST_ELEMENT
    values = _read_values("packet 44", data, P44_LAYOUT, lambda values: P44_LAYOUT[: start + 4 * values[start - 1]])
    return Packet44Platforms(values[1], values[5], _elements(values[start : start + 4 * values[start - 1]]))


def decode_platform_packet(data: bytes) -> PlatformPacket:
    """Packet 69 or 44, by its NID_PACKET."""
    if not data:
        raise PacketError("platform packet", "NID_PACKET", 0, "truncated: no bytes")
    if data[0] == PACKET_44:
        return decode_packet44(data)
    if data[0] != PACKET_69:
        raise PacketError("platform packet", "NID_PACKET", 0, f"{data[0]} is neither 69 nor 44")
    return decode_packet69(data)


def encode_platform_packet(packet: PlatformPacket) -> bytes:
    if isinstance(packet, Packet69):
        return encode_packet69(packet)
    if isinstance(packet, Packet44Platforms):
        return encode_packet44(packet)
    raise TypeError(f"not a platform packet: {packet!r}")


__all__ = [
    "ELEMENT_BITS",
    "MAX_DISTANCE",
    "MAX_ITER",
    "M_PLATFORM_MM",
    "P44_BITS",
    "P44_LAYOUT",
    "P69_BITS",
    "P69_INIT_BITS",
    "P69_LAYOUT",
    "PACKET44_CODEC",
    "PACKET69_CODEC",
    "PACKET_44",
    "PACKET_69",
    "Q_DIR",
    "Q_PLATFORM",
    "Q_SCALE_M",
    "Packet44Fields",
    "Packet44Platforms",
    "Packet44Read",
    "Packet69",
    "Packet69Fields",
    "Packet69Read",
    "PlatformElement",
    "PlatformPacket",
    "decode_packet44",
    "decode_packet69",
    "decode_platform_packet",
    "encode_packet44",
    "encode_packet69",
    "encode_platform_packet",
    "packet44_bits",
    "packet69_bits",
    "packet_from_bits",
]
