"""Bit strings as ETCS packets carry them: unsigned fields, most significant bit first (Subset-026-7 §7.3).

:class:`BitReader` and :class:`BitWriter` track the bit offset of every field, so a
codec's errors can name the field and the offset where it starts. A packet is sent
as whole bytes: its bits, then zero padding up to the next byte boundary.
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


class BitReader:
    """Reads fields from ``data`` in order; every error names the field and the bit offset."""

    def __init__(self, packet: str, data: bytes):
        self.packet = packet
        self.value = int.from_bytes(data, "big")
        self.size = 8 * len(data)
        self.offset = 0

    def read(self, field: str, width: int) -> int:
        if self.offset + width > self.size:
            raise PacketError(
                self.packet,
                field,
                self.offset,
                f"truncated: needs {width} bits, {self.size - self.offset} left in {self.size // 8} bytes",
            )
        shift = self.size - self.offset - width
        self.offset += width
        return (self.value >> shift) & ((1 << width) - 1)

    def expect(self, field: str, width: int, allowed: dict[int, str] | range, *, meaning: str = "") -> int:
        """Read a field that must take one of ``allowed`` (codes, or a mapping from code to meaning)."""
        start = self.offset
        code = self.read(field, width)
        if code not in allowed:
            listed = (
                ", ".join(f"{c:0{width}b}b {m}" for c, m in allowed.items())
                if isinstance(allowed, dict)
                else f"{allowed.start}..{allowed.stop - 1}"
            )
            raise PacketError(
                self.packet,
                field,
                start,
                f"{code:0{width}b}b ({code}) is {meaning or 'not allowed'}; allowed: {listed}",
            )
        return code

    def finish(self, length_bits: int) -> None:
        """The packet ended at ``length_bits`` (its L_PACKET): only zero padding to the byte boundary may follow."""
        if self.offset != length_bits:
            raise PacketError(
                self.packet, "L_PACKET", 10, f"{length_bits} bits declared, but the fields end at bit {self.offset}"
            )
        padding = self.size - self.offset
        if padding >= 8:
            raise PacketError(
                self.packet,
                "padding",
                self.offset,
                f"over-long: {padding} bits follow the packet's {length_bits}, at most 7 may",
            )
        if self.value & ((1 << padding) - 1):
            raise PacketError(self.packet, "padding", self.offset, "the bits after the packet must be 0")


class BitWriter:
    """Appends fields; a value that does not fit its width is an error naming the field and the offset."""

    def __init__(self, packet: str):
        self.packet = packet
        self.fields: list[tuple[str, int, int]] = []
        self.offset = 0

    def write(self, field: str, width: int, value: int) -> None:
        if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value < 1 << width:
            raise PacketError(
                self.packet, field, self.offset, f"{value!r} does not fit {width} bits (0..{(1 << width) - 1})"
            )
        self.fields.append((field, width, value))
        self.offset += width

    def check(self, field: str, width: int, value: int, allowed) -> None:
        """Write a field that must take one of ``allowed``."""
        if value not in allowed:
            raise PacketError(self.packet, field, self.offset, f"{value!r} is not allowed (allowed: {sorted(allowed)})")
        self.write(field, width, value)

    def patch(self, field: str, value: int) -> None:
        """Set an already written field (L_PACKET, once the length is known)."""
        for j, (name, width, _) in enumerate(self.fields):
            if name == field:
                if not 0 <= value < 1 << width:
                    raise PacketError(
                        self.packet,
                        field,
                        sum(w for _, w, _ in self.fields[:j]),
                        f"{value} does not fit {width} bits: the packet is too long",
                    )
                self.fields[j] = (name, width, value)
                return
        raise KeyError(field)

    def to_bytes(self) -> bytes:
        value = 0
        for _, width, field_value in self.fields:
            value = (value << width) | field_value
        padding = -self.offset % 8
        return (value << padding).to_bytes((self.offset + padding) // 8, "big")
