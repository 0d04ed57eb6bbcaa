"""Bit strings as ETCS packets carry them: unsigned fields, most significant bit first (Subset-026-7 §7.3).

A codec's errors name the field and the bit offset where it starts (:class:`PacketError`). A
packet is sent as whole bytes: its bits, then zero padding up to the next byte boundary.
"""

from __future__ import annotations

import string

from atcs.model.errors import AtcsInputError


class PacketError(AtcsInputError):
    """Malformed packet data: the message names the packet, the field, its bit offset and the value."""

    def __init__(self, packet: str, field: str, bit_offset: int, problem: str):
        self.packet, self.field, self.bit_offset = packet, field, bit_offset
        super().__init__(f"{packet}: {field} at bit {bit_offset}: {problem}")


def hex_bytes(text: str, *, what: str = "packet") -> bytes:
    """The bytes of a hex string (spaces and underscores between digits allowed)."""
    digits = "".join(text.split()).replace("_", "")
    for position, char in enumerate(digits):
        if char not in string.hexdigits:
            raise PacketError(what, "hex string", 4 * position, f"{char!r} is not a hex digit")
    if len(digits) % 2:
        raise PacketError(what, "hex string", 4 * len(digits), f"{len(digits)} hex digits are not whole bytes")
    return bytes.fromhex(digits)


def check_packet_end(packet: str, data: bytes, end_bits: int, length_bits: int) -> None:
    """A packet's fields end at bit ``end_bits`` of ``data``: its L_PACKET (``length_bits``) must say so, and only
    zero padding to the byte boundary may follow."""
    if end_bits != length_bits:
        raise PacketError(packet, "L_PACKET", 10, f"{length_bits} bits declared, but the fields end at bit {end_bits}")
    padding = 8 * len(data) - end_bits
    if padding >= 8:
        raise PacketError(
            packet, "padding", end_bits, f"over-long: {padding} bits follow the packet's {length_bits}, at most 7 may"
        )
    if int.from_bytes(data, "big") & ((1 << padding) - 1):
        raise PacketError(packet, "padding", end_bits, "the bits after the packet must be 0")
