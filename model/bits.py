"""Bit strings as ETCS packets carry them: unsigned fields, most significant bit first (Subset-026-7 §7.3).

A field's bits and its value are step functions over the Ops (:func:`field_bits`, :func:`field_value`), proved
to be each other's inverse for every value of every width the formats use (``packets.field_round_trip``,
``packets.bits_round_trip``). :class:`BitReader` and :class:`BitWriter` run them on floats (every value is a
whole number below 2^53, so each operation is exact) and track the bit offset of every field, so a codec's
errors can name the field and the offset where it starts. A packet is sent as whole bytes: its bits, then zero
padding up to the next byte boundary.
"""

from __future__ import annotations

import string
from dataclasses import dataclass
from typing import Generic

from atcs.model.errors import AtcsInputError
from atcs.model.node import Stateless, stateless_node
from atcs.model.ops import B, N, Ops
from atcs.model.ops.floating import FLOAT

FIELD_WIDTHS = (1, 2, 4, 5, 8, 9, 13, 15, 16, 24, 32)
"""Every field width of the packets atcs reads and writes (platform packets 69 and 44, the T2T report)."""


def field_bits(o: Ops, value, width: int) -> tuple:
    """The ``width`` bits of a whole ``value`` in ``0 .. 2^width - 1``, most significant first: each the
    remainder of halving what is left."""
    bits, rest = [], value
    for _ in range(width):
        half = o.floor(rest / o.const(2))
        bits.append(rest - o.const(2) * half)
        rest = half
    return tuple(reversed(bits))


def field_value(o: Ops, bits) -> N:
    """The value of ``bits``, most significant first."""
    value = o.const(0)
    for bit in bits:
        value = value * o.const(2) + bit
    return value


@dataclass(frozen=True)
class FieldValues(Generic[N, B]):
    values: tuple[N, ...]
    """One value per width of :data:`FIELD_WIDTHS`."""


@dataclass(frozen=True)
class FieldBits(Generic[N, B]):
    bits: tuple[N, ...]
    """The bits of one field per width of :data:`FIELD_WIDTHS`, one after the other."""


@dataclass(frozen=True)
class FieldCodecOutputs(Generic[N, B]):
    encoded: tuple[N, ...]
    """:func:`field_bits` of each value, one field after the other."""
    decoded: tuple[N, ...]
    """:func:`field_value` of each field of the input bits."""
    reencoded: tuple[N, ...]
    """:func:`field_bits` of each decoded value."""


def _fields(bits: tuple) -> tuple[tuple, ...]:
    fields, start = [], 0
    for width in FIELD_WIDTHS:
        fields.append(bits[start : start + width])
        start += width
    return tuple(fields)


def field_codec_step(o: Ops, p: FieldValues, s: Stateless, i: FieldBits):
    decoded = tuple(field_value(o, bits) for bits in _fields(i.bits))
    return s, FieldCodecOutputs(
        encoded=tuple(b for v, w in zip(p.values, FIELD_WIDTHS, strict=True) for b in field_bits(o, v, w)),
        decoded=decoded,
        reencoded=tuple(b for v, w in zip(decoded, FIELD_WIDTHS, strict=True) for b in field_bits(o, v, w)),
    )


FIELD_CODEC = stateless_node(
    name="field_codec",
    params=FieldValues,
    inputs=FieldBits,
    outputs=FieldCodecOutputs,
    step=field_codec_step,
    seed="004 §2.2-2.3, Subset-026-7 §7.3",
    sizes={
        "values": len(FIELD_WIDTHS),
        "bits": sum(FIELD_WIDTHS),
        "encoded": sum(FIELD_WIDTHS),
        "decoded": len(FIELD_WIDTHS),
        "reencoded": sum(FIELD_WIDTHS),
    },
)
"""A value of every field width encoded, and a field of every width decoded and encoded again, all symbolic."""


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
        self.bits = tuple(float(b) for b in format(self.value, f"0{self.size}b")) if data else ()
        self.offset = 0

    def read(self, field: str, width: int) -> int:
        if self.offset + width > self.size:
            raise PacketError(
                self.packet,
                field,
                self.offset,
                f"truncated: needs {width} bits, {self.size - self.offset} left in {self.size // 8} bytes",
            )
        start = self.offset
        self.offset += width
        return int(field_value(FLOAT, self.bits[start : self.offset]))

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
        bits = [bit for _, width, value in self.fields for bit in field_bits(FLOAT, float(value), width)]
        bits += [0.0] * (-self.offset % 8)
        return bytes(int(field_value(FLOAT, bits[k : k + 8])) for k in range(0, len(bits), 8))
