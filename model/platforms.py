"""The platform table the door-enable node reads (seed 004 §2.2-2.3): from a packet or from a table.

A platform is a stretch of line ``[start_m, end_m]`` (line coordinates in the train's
direction of travel) with a side (left, right or both, seen in that direction) and a
nominal height. The table comes either from the wayside as packet 69 or user packet
44 (:mod:`atcs.model.platform_packets`), placed at the location of the balise group
that sent it, or from a scenario's table. Both forms are read by
:func:`platform_data`, the one place a scenario's ``[platforms]`` section is checked::

    [platforms]                      # a packet, as sent (hex), and where it was read
    packet = "4540ce803200fa74212c007d38"
    reference_m = 4500

    [[platforms.table]]              # or a table
    start_m = 4600
    length_m = 250
    side = "right"
    height_mm = 760                  # optional
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Generic

from atcs.model.bits import PacketError, hex_bytes
from atcs.model.data_files import TableReader, read_toml
from atcs.model.errors import AtcsInputError
from atcs.model.node import Stateless, stateless_node
from atcs.model.ops import B, N, Ops
from atcs.model.ops.exact import EXACT
from atcs.model.platform_packets import (
    M_PLATFORM_MM,
    MAX_DISTANCE,
    MAX_ITER,
    Q_PLATFORM,
    Q_SCALE_M,
    Packet44Platforms,
    Packet69,
    PlatformElement,
    PlatformPacket,
    decode_platform_packet,
)
from atcs.model.profile import parse_number

SIDES = ("left", "right", "both")


@dataclass(frozen=True)
class Station:
    """A station stop: the ATO stops the front at ``stop_m``, opens the doors on the platform's side, waits
    ``dwell_s`` from the doors opening, closes them and departs once they are closed and locked (seed 004 §2.1)."""

    name: str
    stop_m: Fraction
    dwell_s: Fraction


def station_stops(reader: TableReader, key: str, length_m: Fraction) -> tuple[Station, ...]:
    """The stations of ``reader``'s list ``key`` (``{ name, stop_m, dwell_s }``, the name ``S<j>`` by default): each
    stop on the line of ``length_m`` and after the previous one; errors as ``reader``'s."""
    stations = []
    for j, row in enumerate(reader.rows(key)):
        x = type(reader)(reader.source, row, f"{reader.name(key)}[{j}]", ("name", "stop_m", "dwell_s"))
        stop = x.number("stop_m", positive=True)
        if stop > length_m or (stations and stop <= stations[-1].stop_m):
            x.fail("stop_m", f"must be on the line ({length_m} m) and after the previous station's stop")
        stations.append(Station(x.text("name", f"S{j + 1}"), stop, x.number("dwell_s", minimum=0)))
    return tuple(stations)


class PlatformDataError(AtcsInputError):
    """Bad platform data; the message names the source, the field and the value."""


@dataclass(frozen=True)
class Platform:
    start_m: Fraction
    end_m: Fraction
    side: str
    """``left``, ``right`` or ``both``, in the train's direction of travel."""
    height_mm: int | None = None

    @property
    def left(self) -> bool:
        return self.side in ("left", "both")

    @property
    def right(self) -> bool:
        return self.side in ("right", "both")


@dataclass(frozen=True)
class PacketPlatforms(Generic[N, B]):
    """A packet's platform elements as the door node's table reads them: the codes, decoded (seed 004 Table 1)."""

    reference_m: N
    """Where the balise group that sent the packet was read."""
    q_dir: N
    reverse: B
    """The train runs against the balise group's nominal direction."""
    q_scale: N
    elements: N
    """How many elements the packet holds (the slots after them are not read)."""
    d_trackcond: tuple[N, ...]
    l_trackcond: tuple[N, ...]
    q_platform: tuple[N, ...]


@dataclass(frozen=True)
class PlatformTable(Generic[N, B]):
    """The door node's platform table (:func:`platform_inputs`' fields)."""

    platform_start_m: tuple[N, ...]
    platform_end_m: tuple[N, ...]
    platform_left: tuple[B, ...]
    platform_right: tuple[B, ...]


def packet_platform_table(o: Ops, i: PacketPlatforms) -> PlatformTable:
    """The platforms a packet describes, slot by slot: each element's start its distance (in Q_SCALE units) after
    the previous one's (the first's after the reference), its end its length after its start, its sides its
    Q_PLATFORM's; a slot after the packet's elements, or every slot of a packet for the other direction (Q_DIR),
    on no side."""
    scale_m = o.ite(
        o.eq(i.q_scale, o.const(0)),
        o.const(Q_SCALE_M[0]),
        o.ite(o.eq(i.q_scale, o.const(1)), o.const(Q_SCALE_M[1]), o.const(Q_SCALE_M[2])),
    )
    applies = o.or_(o.eq(i.q_dir, o.const(2)), o.eq(i.q_dir, o.ite(i.reverse, o.const(0), o.const(1))))
    start, starts, ends, left, right = i.reference_m, [], [], [], []
    for k, (d, length, side) in enumerate(zip(i.d_trackcond, i.l_trackcond, i.q_platform, strict=True)):
        start = start + d * scale_m
        present = o.and_(applies, o.const(k) < i.elements)
        starts.append(start)
        ends.append(start + length * scale_m)
        left.append(o.and_(present, o.or_(o.eq(side, o.const(0)), o.eq(side, o.const(2)))))
        right.append(o.and_(present, o.or_(o.eq(side, o.const(1)), o.eq(side, o.const(2)))))
    return PlatformTable(tuple(starts), tuple(ends), tuple(left), tuple(right))


def packet_platforms_step(o: Ops, p: Stateless, s: Stateless, i: PacketPlatforms):
    return s, packet_platform_table(o, i)


PACKET_PLATFORMS = stateless_node(
    name="packet_platforms",
    params=Stateless,
    inputs=PacketPlatforms,
    outputs=PlatformTable,
    step=packet_platforms_step,
    seed="004 §2.2-2.3 (Tables 1-2)",
    sizes={
        name: MAX_ITER + 1
        for name in ("d_trackcond", "l_trackcond", "q_platform", *(f.name for f in dataclasses.fields(PlatformTable)))
    },
)
"""The door node's platform table from a packet's codes, every code symbolic (32 elements, packet 69's most)."""


def platforms_from_packet(packet: PlatformPacket, reference_m, *, direction: str = "nominal") -> tuple[Platform, ...]:
    """The platforms a packet read at ``reference_m`` describes for a train running ``direction`` relative to the
    balise group (none if the packet is for the other direction, or is packet 69's empty profile): the table of
    :func:`packet_platform_table`."""
    if direction not in ("nominal", "reverse"):
        raise ValueError(f"direction must be 'nominal' or 'reverse', got {direction!r}")
    elements = packet.elements
    table = packet_platform_table(
        EXACT,
        PacketPlatforms(
            reference_m=Fraction(reference_m),
            q_dir=Fraction(packet.q_dir),
            reverse=direction == "reverse",
            q_scale=Fraction(packet.q_scale),
            elements=Fraction(len(elements)),
            d_trackcond=tuple(Fraction(e.d_trackcond) for e in elements),
            l_trackcond=tuple(Fraction(e.l_trackcond) for e in elements),
            q_platform=tuple(Fraction(e.q_platform) for e in elements),
        ),
    )
    rows = zip(
        table.platform_start_m, table.platform_end_m, table.platform_left, table.platform_right, elements, strict=True
    )
    return tuple(
        Platform(start, end, Q_PLATFORM[e.q_platform], M_PLATFORM_MM[e.m_platform])
        for start, end, left, right, e in rows
        if left or right
    )


def packet_for_platforms(
    platforms: Sequence[Platform], reference_m, *, q_scale: int = 1, nid_packet: int = 69, q_dir: int = 1
) -> PlatformPacket:
    """The packet that :func:`platforms_from_packet` turns back into ``platforms`` (sorted by start, each
    distance a whole number of Q_SCALE units from the previous start); a ValueError names what does not fit."""
    if q_scale not in Q_SCALE_M:
        raise ValueError(f"q_scale must be one of {sorted(Q_SCALE_M)}, got {q_scale!r}")
    scale, heights = Q_SCALE_M[q_scale], {mm: code for code, mm in M_PLATFORM_MM.items()}
    previous, elements = Fraction(reference_m), []
    for k, platform in enumerate(platforms):
        d, length = (platform.start_m - previous) / scale, (platform.end_m - platform.start_m) / scale
        for name, units in (("start_m", d), ("length", length)):
            if units.denominator != 1 or not 0 <= units <= MAX_DISTANCE:
                raise ValueError(
                    f"platform {k}: {name} gives {units} units of {scale} m; it must be a whole number "
                    f"in 0..{MAX_DISTANCE}"
                )
        if platform.height_mm not in heights:
            raise ValueError(
                f"platform {k}: height_mm = {platform.height_mm!r} has no M_PLATFORM code "
                f"(codes exist for {sorted(heights)})"
            )
        if platform.side not in SIDES:
            raise ValueError(
                f"platform {k}: side = {platform.side!r} has no Q_PLATFORM code (codes exist for {', '.join(SIDES)})"
            )
        elements.append(PlatformElement(int(d), int(length), heights[platform.height_mm], SIDES.index(platform.side)))
        previous = platform.start_m
    if nid_packet == 69:
        return Packet69(q_dir, q_scale, tuple(elements))
    if nid_packet == 44:
        return Packet44Platforms(q_dir, q_scale, tuple(elements))
    raise ValueError(f"nid_packet must be 69 or 44, got {nid_packet!r}")


def platform_data(section: Mapping, source: str, field: str = "[platforms]") -> tuple[Platform, ...]:
    """The platforms of a scenario's ``[platforms]`` section (see the module docstring), or of the table ``field``
    in the same form; ``source`` names the file in errors."""
    where = f"{source}: {field}"
    if not isinstance(section, Mapping):
        raise PlatformDataError(f"{where} must be a table, got {section!r}")
    unknown = sorted(set(section) - {"packet", "reference_m", "direction", "table"})
    if unknown:
        raise PlatformDataError(
            f"{where}: unknown field {unknown[0]!r} (fields: packet, reference_m, direction, table)"
        )
    if ("packet" in section) == ("table" in section):
        raise PlatformDataError(
            f"{where}: give either 'packet' (hex) with 'reference_m', or 'table', not "
            f"{'both' if 'packet' in section else 'neither'}"
        )
    if "table" in section:
        extra = sorted({"reference_m", "direction"} & set(section))
        if extra:
            raise PlatformDataError(f"{where}: {extra[0]} belongs to a packet; a table's positions are line positions")
        return _table(section["table"], where)
    return _packet(section, where)


def _packet(section: Mapping, where: str) -> tuple[Platform, ...]:
    """The platforms of the packet form of ``[platforms]``: a hex packet and the reference_m it was read at."""
    raw, direction = section["packet"], section.get("direction", "nominal")
    if not isinstance(raw, str):
        raise PlatformDataError(f"{where}: packet = {raw!r} must be a hex string")
    if direction not in ("nominal", "reverse"):
        raise PlatformDataError(f"{where}: direction = {direction!r} must be 'nominal' or 'reverse'")
    if "reference_m" not in section:
        raise PlatformDataError(f"{where}: a packet needs reference_m, where its balise group was read")
    reference = parse_number(where, "reference_m", section["reference_m"], PlatformDataError)
    if reference < 0:
        raise PlatformDataError(f"{where}: reference_m = {section['reference_m']!r} is negative")
    try:
        packet = decode_platform_packet(hex_bytes(raw))
    except PacketError as exc:
        raise PlatformDataError(f"{where}: packet: {exc}") from None
    if isinstance(packet, Packet69) and packet.q_trackinit:
        return ()
    platforms = platforms_from_packet(packet, reference, direction=direction)
    if not platforms and packet.elements:
        raise PlatformDataError(
            f"{where}: the packet's Q_DIR ({packet.q_dir}) does not apply to a train running {direction}"
        )
    return platforms


def _table(rows, where: str) -> tuple[Platform, ...]:
    if not isinstance(rows, list):
        raise PlatformDataError(f"{where}: table = {rows!r} must be a list of [[platforms.table]] entries")
    table = tuple(_table_row(row, f"{where} table[{k}]") for k, row in enumerate(rows))
    for (j, a), (k, b) in itertools.combinations(enumerate(table), 2):
        if a.start_m < b.end_m and b.start_m < a.end_m and ((a.left and b.left) or (a.right and b.right)):
            raise PlatformDataError(
                f"{where} table[{k}]: [{b.start_m}, {b.end_m}] m overlaps table[{j}] ([{a.start_m}, {a.end_m}] m) "
                "on the same side: one platform edge per side and place"
            )
    return table


def _table_row(row, entry: str) -> Platform:
    """One entry of the table form of ``[platforms]``: start_m, length_m, side and an optional height_mm."""
    if not isinstance(row, Mapping):
        raise PlatformDataError(f"{entry} must be a table, got {row!r}")
    unknown = sorted(set(row) - {"start_m", "length_m", "side", "height_mm"})
    if unknown:
        raise PlatformDataError(f"{entry}: unknown field {unknown[0]!r} (fields: start_m, length_m, side, height_mm)")
    for key in ("start_m", "length_m", "side"):
        if key not in row:
            raise PlatformDataError(f"{entry}: {key} is missing")
    start = parse_number(entry, "start_m", row["start_m"], PlatformDataError)
    length = parse_number(entry, "length_m", row["length_m"], PlatformDataError)
    if start < 0:
        raise PlatformDataError(f"{entry}: start_m = {row['start_m']!r} is negative")
    if length <= 0:
        raise PlatformDataError(f"{entry}: length_m = {row['length_m']!r} must be positive")
    if row["side"] not in SIDES:
        raise PlatformDataError(f"{entry}: side = {row['side']!r} must be one of {', '.join(SIDES)}")
    height = row.get("height_mm")
    if height is not None and (type(height) is not int or height not in M_PLATFORM_MM.values()):
        raise PlatformDataError(
            f"{entry}: height_mm = {height!r} is not a height packet 69 can give "
            f"({', '.join(map(str, M_PLATFORM_MM.values()))})"
        )
    return Platform(start, start + length, row["side"], height)


def read_platform_data(path: str | Path) -> tuple[Platform, ...]:
    """The ``[platforms]`` section of a TOML file."""
    document = read_toml(path, PlatformDataError, "the platform data")
    if "platforms" not in document:
        raise PlatformDataError(f"{path}: no [platforms] section")
    return platform_data(document["platforms"], str(path))


def platform_inputs(platforms: Sequence[Platform], capacity: int | None = None) -> dict[str, tuple]:
    """The door-enable node's platform-table fields, padded with empty entries (no side) up to ``capacity``."""
    capacity = len(platforms) if capacity is None else capacity
    if len(platforms) > capacity:
        raise ValueError(f"{len(platforms)} platforms do not fit a table of capacity {capacity}")
    empty = Platform(Fraction(0), Fraction(0), "none")
    rows = [*platforms, *[empty] * (capacity - len(platforms))]
    return {
        "platform_start_m": tuple(p.start_m for p in rows),
        "platform_end_m": tuple(p.end_m for p in rows),
        "platform_left": tuple(p.left for p in rows),
        "platform_right": tuple(p.right for p in rows),
    }
