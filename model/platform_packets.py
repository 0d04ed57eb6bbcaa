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

from atcs.model.bits import BitReader, BitWriter, PacketError

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
HEADER_BITS = 8 + 2 + 13
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


# --- decoding --------------------------------------------------------------------------------------------


def _read_header(bits: BitReader, nid_packet: int) -> tuple[int, int]:
    """(Q_DIR, L_PACKET)."""
    bits.expect("NID_PACKET", 8, {nid_packet: bits.packet}, meaning=f"not {bits.packet}")
    return bits.expect("Q_DIR", 2, Q_DIR, meaning="spare"), bits.read("L_PACKET", 13)


def _read_element(bits: BitReader, k: int | None) -> PlatformElement:
    suffix = "" if k is None else f"({k})"
    return PlatformElement(
        d_trackcond=bits.read(f"D_TRACKCOND{suffix}", 15),
        l_trackcond=bits.read(f"L_TRACKCOND{suffix}", 15),
        m_platform=bits.expect(f"M_PLATFORM{suffix}", 4, M_PLATFORM_MM, meaning="reserved"),
        q_platform=bits.expect(f"Q_PLATFORM{suffix}", 2, Q_PLATFORM, meaning="spare"),
    )


def decode_packet69(data: bytes) -> Packet69:
    """Packet 69 from its bytes (:class:`PacketError` on anything but a well-formed packet)."""
    bits = BitReader("packet 69", data)
    q_dir, length = _read_header(bits, PACKET_69)
    q_scale = bits.expect("Q_SCALE", 2, Q_SCALE_M, meaning="spare")
    q_trackinit = bits.read("Q_TRACKINIT", 1)
    if q_trackinit:
        packet = Packet69(q_dir, q_scale, (), 1, bits.read("D_TRACKINIT", 15))
    else:
        first = _read_element(bits, None)
        n_iter = bits.read("N_ITER", 5)
        rest = tuple(_read_element(bits, k) for k in range(1, n_iter + 1))
        packet = Packet69(q_dir, q_scale, (first, *rest))
    bits.finish(length)
    return packet


def decode_packet44(data: bytes) -> Packet44Platforms:
    """User packet 44 with platform information from its bytes."""
    bits = BitReader("packet 44", data)
    q_dir, length = _read_header(bits, PACKET_44)
    bits.expect("NID_XUSER", 9, {NID_XUSER_PLATFORMS: "platform data (seed 004)"}, meaning="another user system")
    bits.expect("NID_XDATA", 8, {NID_XDATA_PLATFORMS: "platform information"}, meaning="not platform information")
    q_scale = bits.expect("Q_SCALE", 2, Q_SCALE_M, meaning="spare")
    n_iter = bits.read("N_ITER", 5)
    elements = tuple(_read_element(bits, k) for k in range(1, n_iter + 1))
    bits.finish(length)
    return Packet44Platforms(q_dir, q_scale, elements)


def decode_platform_packet(data: bytes) -> PlatformPacket:
    """Packet 69 or 44, by its NID_PACKET."""
    if not data:
        raise PacketError("platform packet", "NID_PACKET", 0, "truncated: no bytes")
    if data[0] == PACKET_44:
        return decode_packet44(data)
    if data[0] != PACKET_69:
        raise PacketError("platform packet", "NID_PACKET", 0, f"{data[0]} is neither 69 nor 44")
    return decode_packet69(data)


# --- encoding --------------------------------------------------------------------------------------------


def _write_header(bits: BitWriter, nid_packet: int, q_dir: int) -> None:
    bits.write("NID_PACKET", 8, nid_packet)
    bits.check("Q_DIR", 2, q_dir, Q_DIR)
    bits.write("L_PACKET", 13, 0)


def _write_element(bits: BitWriter, element: PlatformElement, k: int | None) -> None:
    suffix = "" if k is None else f"({k})"
    bits.write(f"D_TRACKCOND{suffix}", 15, element.d_trackcond)
    bits.write(f"L_TRACKCOND{suffix}", 15, element.l_trackcond)
    bits.check(f"M_PLATFORM{suffix}", 4, element.m_platform, M_PLATFORM_MM)
    bits.check(f"Q_PLATFORM{suffix}", 2, element.q_platform, Q_PLATFORM)


def _finish(bits: BitWriter) -> bytes:
    bits.patch("L_PACKET", bits.offset)
    return bits.to_bytes()


def encode_packet69(packet: Packet69) -> bytes:
    bits = BitWriter("packet 69")
    _write_header(bits, PACKET_69, packet.q_dir)
    bits.check("Q_SCALE", 2, packet.q_scale, Q_SCALE_M)
    bits.check("Q_TRACKINIT", 1, packet.q_trackinit, (0, 1))
    if packet.q_trackinit:
        if packet.elements or packet.d_trackinit is None:
            raise PacketError(
                "packet 69", "D_TRACKINIT", bits.offset, "Q_TRACKINIT 1 needs D_TRACKINIT and no platform elements"
            )
        bits.write("D_TRACKINIT", 15, packet.d_trackinit)
        return _finish(bits)
    if packet.d_trackinit is not None:
        raise PacketError("packet 69", "D_TRACKINIT", bits.offset, "given with Q_TRACKINIT 0")
    if not 1 <= len(packet.elements) <= MAX_ITER + 1:
        raise PacketError(
            "packet 69",
            "N_ITER",
            bits.offset + ELEMENT_BITS,
            f"{len(packet.elements)} elements; Q_TRACKINIT 0 needs 1 to {MAX_ITER + 1}",
        )
    first, *rest = packet.elements
    _write_element(bits, first, None)
    bits.write("N_ITER", 5, len(rest))
    for k, element in enumerate(rest, start=1):
        _write_element(bits, element, k)
    return _finish(bits)


def encode_packet44(packet: Packet44Platforms) -> bytes:
    bits = BitWriter("packet 44")
    _write_header(bits, PACKET_44, packet.q_dir)
    bits.write("NID_XUSER", 9, NID_XUSER_PLATFORMS)
    bits.write("NID_XDATA", 8, NID_XDATA_PLATFORMS)
    bits.check("Q_SCALE", 2, packet.q_scale, Q_SCALE_M)
    if len(packet.elements) > MAX_ITER:
        raise PacketError("packet 44", "N_ITER", bits.offset, f"{len(packet.elements)} elements; at most {MAX_ITER}")
    bits.write("N_ITER", 5, len(packet.elements))
    for k, element in enumerate(packet.elements, start=1):
        _write_element(bits, element, k)
    return _finish(bits)


def encode_platform_packet(packet: PlatformPacket) -> bytes:
    if isinstance(packet, Packet69):
        return encode_packet69(packet)
    if isinstance(packet, Packet44Platforms):
        return encode_packet44(packet)
    raise TypeError(f"not a platform packet: {packet!r}")
