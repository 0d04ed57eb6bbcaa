"""Train position and speed from tags and the tachometer (seed 001 §3.2, Fig. 4 and 7; seed 002 §3.1).

The position is kept as seed 001's ``(LRTI, offset)``: the last read tag (LRT) and
the tachometer distance since it. Each cycle the tachometer's distance increment
``d`` is added to the offset. The tag reader reports a tag with the odometer reading
at its passage, as a balise transmission module does: ``since_tag_m``, the
tachometer's distance from the passage to the end of the cycle. A tag read resets
the offset to that distance (seed 001 Fig. 7 resets it to 0: a read at the cycle's
end), so the position does not depend on how far the train runs in a cycle: it holds
at any speed at which a cycle passes at most one tag. The confidence interval is
docs/design.md's odometry formula, with the LRT's position as the reference and the
tag window as its accuracy::

    min safe front = ref + (1 - e) * offset - w      max safe front = ref + (1 + e) * offset + w

where ``e`` is the tachometer error as a fraction of the *measured* distance (the true
distance of a cycle, or from a passage, is within ``e * d`` of the measured ``d``) and
``w`` the tag window (the reader locates the passage within ``w`` of the tag). The rear
is the front less the train length (seed 001 §3.2). The estimated speed is the
distance per cycle, and its accuracy follows from the tachometer error and the
train's acceleration bounds (a mean over a cycle is within ``A * dt / 2`` of the end
speed).

A train that cannot determine its position must emergency brake (seed 001 §3.2):
the position is invalid from power-up until a known tag is read, and becomes invalid
in the cycle any of these faults is seen:

- ``unknown_tag``: a tag id that is not in the tag table;
- ``unexpected_tag``: a known tag other than the table's next tag after the LRT;
- ``tag_passage_outside_cycle``: a tag read whose passage is not in this cycle (its
  distance since the passage negative or over the cycle's tachometer distance);
- ``tag_outside_window``: the next tag, read where the odometry interval says the
  front cannot be (the interval from the LRT and the interval from the tag's passage
  do not overlap);
- ``missed_tag``: the min safe front is past the next tag's window and it was not read;
- ``implausible_tacho``: an increment that is negative or changes from the previous
  one by more than the train's acceleration bounds allow (tachometer standstill while
  running, spin or slide).

A known tag read while the position is invalid re-establishes it (the first tag after
power-up), *unconfirmed*: one tag read cannot be checked, so a wrong one (a misplaced
tag, a wrong id of the table) would go unnoticed until the next. The position is
*confirmed* by the next tag read from a valid position, which the checks above compare
with the odometry. Until then the train sends no position report and releases no
resource (:mod:`atcs.model.authority`). The tag table runs in the direction of travel: a train running the other
way uses the table of that direction (ids and positions along it).
"""

from __future__ import annotations

import csv
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Generic

from atcs.model.errors import AtcsInputError
from atcs.model.node import Node, Stateless, stateless_node
from atcs.model.ops import B, N, Ops
from atcs.model.profile import parse_number

MIN_CYCLE_S = "0.001"
"""Guard on the cycle time as a divisor: valid data (and every proof) has cycles far longer, so it never acts;
with data out of range the outputs are meaningless but the backends stay comparable on any input."""


class TagTableError(AtcsInputError):
    """A malformed tag table or position parameter; the message names the source, the field and the value."""


@dataclass(frozen=True)
class PositionParams(Generic[N, B]):
    tag_ids: tuple[N, ...]
    """The tag table's ids, in the order the train passes them (distinct whole numbers)."""
    tag_positions_m: tuple[N, ...]
    """Each tag's position along the line (strictly increasing)."""
    tag_window_m: N
    """Tag reading accuracy: the reader locates a tag's passage (its odometer reading) within this distance of the
    tag."""
    tacho_error: N
    """Tachometer error: the true distance of a cycle is within ``tacho_error * d`` of the measured ``d``
    (wheel wear and diameter included), in [0, 1)."""
    train_length_m: N
    cycle_s: N
    """One ATP cycle (seed 001: 100 ms)."""
    max_acceleration_mps2: N
    """The highest acceleration of the train (traction and the steepest downhill): the plausibility bound."""
    max_deceleration_mps2: N
    """The highest deceleration of the train (brakes and the steepest uphill): the plausibility bound."""


@dataclass(frozen=True)
class PositionState(Generic[N, B]):
    localised: B
    """The position is valid."""
    lrt_index: N
    """The last read tag's index in the tag table."""
    offset_m: N
    """The tachometer distance since the last read tag."""
    last_tacho_m: N
    """The previous cycle's tachometer increment."""
    confirmed: B
    """The position was set, or set again, at a tag read while it was valid (module docstring)."""


@dataclass(frozen=True)
class PositionInputs(Generic[N, B]):
    tag_read: B
    """The tag reader reports a tag this cycle."""
    tag_id: N
    """The id it reports (ignored without ``tag_read``)."""
    since_tag_m: N
    """The tachometer's distance from the reported tag's passage to the end of this cycle: the odometer reading now
    less the one at the passage (ignored without ``tag_read``)."""
    tacho_m: N
    """The tachometer's distance since the previous cycle (:func:`tacho_distance_m` from pulses)."""


@dataclass(frozen=True)
class PositionOutputs(Generic[N, B]):
    position_valid: B
    position_confirmed: B
    """Valid, and checked by a tag read since it was last established from an invalid position."""
    lrti: N
    """The last read tag's id (seed 001: LRTI)."""
    lrt_offset_m: N
    """The tachometer distance since it (seed 001: offset)."""
    front_est_m: N
    front_min_m: N
    """The min safe front."""
    front_max_m: N
    """The max safe front."""
    rear_est_m: N
    rear_min_m: N
    rear_max_m: N
    speed_est_mps: N
    """The distance per cycle over the cycle time."""
    speed_accuracy_mps: N
    """The true speed is within this of ``speed_est_mps``."""
    standstill: B
    """No distance this cycle."""
    unknown_tag: B
    unexpected_tag: B
    tag_passage_outside_cycle: B
    tag_outside_window: B
    missed_tag: B
    implausible_tacho: B


def odometry_interval(o: Ops, p: PositionParams, ref_m, offset_m):
    """``(min safe front, max safe front)`` at ``offset_m`` past a tag at ``ref_m`` (docs/design.md odometry)."""
    return (
        ref_m + (o.const(1) - p.tacho_error) * offset_m - p.tag_window_m,
        ref_m + (o.const(1) + p.tacho_error) * offset_m + p.tag_window_m,
    )


def speed_accuracy_mps(o: Ops, p: PositionParams, speed_est_mps):
    """How far the true end-of-cycle speed can be from the mean measured speed of the cycle."""
    a = o.max(p.max_acceleration_mps2, p.max_deceleration_mps2)
    return p.tacho_error * speed_est_mps + a * p.cycle_s / o.const(2)


def implausible_increment(o: Ops, p: PositionParams, last_m, tacho_m):
    """The tachometer increment is negative, or differs from the last one by more than the acceleration bounds
    and the tachometer error of both allow (consecutive true distances differ by at most ``A * dt^2``)."""
    dt2 = p.cycle_s * p.cycle_s
    change = tacho_m - last_m
    slack = p.tacho_error * (tacho_m + last_m)
    return o.or_(
        tacho_m < o.const(0),
        change > p.max_acceleration_mps2 * dt2 + slack,
        -change > p.max_deceleration_mps2 * dt2 + slack,
    )


def position_init(o: Ops, p: PositionParams, s: PositionState):
    """Power-up at standstill: no position until the first tag."""
    zero = o.const(0)
    return o.and_(
        o.not_(s.localised),
        o.eq(s.lrt_index, zero),
        o.eq(s.offset_m, zero),
        o.eq(s.last_tacho_m, zero),
        o.not_(s.confirmed),
    )


def position_step(o: Ops, p: PositionParams, s: PositionState, i: PositionInputs):
    """One cycle of position determination (module docstring)."""
    zero, one, w = o.const(0), o.const(1), p.tag_window_m
    last = o.const(len(p.tag_ids) - 1)
    offset = s.offset_m + i.tacho_m
    low, high = odometry_interval(o, p, o.select(p.tag_positions_m, s.lrt_index), offset)
    has_next = s.lrt_index < last
    next_index = o.min(s.lrt_index + one, last)
    next_m = o.select(p.tag_positions_m, next_index)
    known, read_index = o.find(p.tag_ids, i.tag_id)
    expected = o.and_(i.tag_read, has_next, o.eq(i.tag_id, o.select(p.tag_ids, next_index)))
    tag_low, tag_high = odometry_interval(o, p, next_m, i.since_tag_m)

    unknown_tag = o.and_(i.tag_read, o.not_(known))
    unexpected_tag = o.and_(s.localised, i.tag_read, known, o.not_(expected))
    tag_passage_outside_cycle = o.and_(i.tag_read, o.or_(i.since_tag_m < zero, i.since_tag_m > i.tacho_m))
    tag_outside_window = o.and_(s.localised, expected, o.or_(high < tag_low, low > tag_high))
    missed_tag = o.and_(s.localised, has_next, o.not_(expected), low > next_m + w)
    implausible_tacho = implausible_increment(o, p, s.last_tacho_m, i.tacho_m)
    fault = o.or_(
        unknown_tag, unexpected_tag, tag_passage_outside_cycle, tag_outside_window, missed_tag, implausible_tacho
    )

    reset = o.and_(i.tag_read, known, o.not_(fault))
    localised = o.and_(o.not_(fault), o.or_(s.localised, reset))
    confirmed = o.and_(localised, o.or_(s.confirmed, o.and_(s.localised, reset)))
    lrt_index = o.ite(reset, read_index, s.lrt_index)
    offset = o.ite(reset, i.since_tag_m, offset)
    ref = o.select(p.tag_positions_m, lrt_index)
    front_min, front_max = odometry_interval(o, p, ref, offset)
    dt = o.max(p.cycle_s, o.const(MIN_CYCLE_S))
    speed = i.tacho_m / dt
    outputs = PositionOutputs(
        position_valid=localised,
        position_confirmed=confirmed,
        lrti=o.select(p.tag_ids, lrt_index),
        lrt_offset_m=offset,
        front_est_m=ref + offset,
        front_min_m=front_min,
        front_max_m=front_max,
        rear_est_m=ref + offset - p.train_length_m,
        rear_min_m=front_min - p.train_length_m,
        rear_max_m=front_max - p.train_length_m,
        speed_est_mps=speed,
        speed_accuracy_mps=speed_accuracy_mps(o, p, speed),
        standstill=o.eq(i.tacho_m, zero),
        unknown_tag=unknown_tag,
        unexpected_tag=unexpected_tag,
        tag_passage_outside_cycle=tag_passage_outside_cycle,
        tag_outside_window=tag_outside_window,
        missed_tag=missed_tag,
        implausible_tacho=implausible_tacho,
    )
    return PositionState(localised, lrt_index, offset, i.tacho_m, confirmed), outputs


PROOF_TAGS = 16
"""The tag-table capacity the proofs cover (ids and positions symbolic)."""

POSITION = Node(
    name="position",
    params=PositionParams,
    state=PositionState,
    inputs=PositionInputs,
    outputs=PositionOutputs,
    init=position_init,
    step=position_step,
    seed="001 §3.2 (Fig. 4, 7), 002 §3.1",
    sizes={"tag_ids": PROOF_TAGS, "tag_positions_m": PROOF_TAGS},
)


# --- tag tables ---------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class TagTable:
    """A validated tag table: ids and positions in the direction of travel."""

    ids: tuple[Fraction, ...]
    positions_m: tuple[Fraction, ...]

    def __len__(self) -> int:
        return len(self.ids)


def _number(source: str, field: str, raw) -> Fraction:
    return parse_number(source, field, raw, TagTableError)


def tag_table(
    source: str, ids: Sequence, positions_m: Sequence, entry: Callable[[int], str] = "tag {}".format
) -> TagTable:
    """A :class:`TagTable`, or a :class:`TagTableError` naming ``source``, the entry (``entry(j)``) and the value:
    ids must be distinct whole numbers, positions strictly increasing (the order the train passes them)."""
    if len(ids) != len(positions_m):
        raise TagTableError(f"{source}: {len(ids)} ids but {len(positions_m)} positions")
    if len(ids) < 2:
        raise TagTableError(f"{source}: a tag table needs at least 2 tags, got {len(ids)}")
    table_ids, table_positions, seen = [], [], {}
    for j, (raw_id, raw_m) in enumerate(zip(ids, positions_m, strict=True)):
        tag_id = _number(source, f"{entry(j)}: id", raw_id)
        if tag_id.denominator != 1:
            raise TagTableError(f"{source}: {entry(j)}: id = {raw_id!r} is not a whole number")
        if tag_id in seen:
            raise TagTableError(f"{source}: {entry(j)}: id = {raw_id!r} duplicates the id of {entry(seen[tag_id])}")
        seen[tag_id] = j
        position = _number(source, f"{entry(j)}: position_m", raw_m)
        if table_positions and position <= table_positions[-1]:
            raise TagTableError(
                f"{source}: {entry(j)}: position_m = {raw_m!r} is not after {entry(j - 1)}'s {table_positions[-1]} "
                "(positions must strictly increase in the direction of travel)"
            )
        table_ids.append(tag_id)
        table_positions.append(position)
    return TagTable(tuple(table_ids), tuple(table_positions))


def line_tags(source: str, key: str, rows, length_m: Fraction) -> TagTable:
    """A line's tags (``key = [{id, position_m}, ...]`` in the order a train passes them), each on the line from 0
    to ``length_m``."""
    if not isinstance(rows, list) or not all(isinstance(row, Mapping) for row in rows):
        raise TagTableError(f"{source}: {key} = {rows!r} must be a list of tables {{id, position_m}}")
    for j, row in enumerate(rows):
        unknown = sorted(set(row) - {"id", "position_m"})
        if unknown:
            raise TagTableError(f"{source}: {key}[{j}]: unknown field {unknown[0]!r} (fields: id, position_m)")
        for field in ("id", "position_m"):
            if field not in row:
                raise TagTableError(f"{source}: {key}[{j}]: {field} is missing")
    table = tag_table(source, [r["id"] for r in rows], [r["position_m"] for r in rows], f"{key}[{{}}]".format)
    for j, x in enumerate(table.positions_m):
        if not 0 <= x <= length_m:
            raise TagTableError(f"{source}: {key}[{j}].position_m = {x} is off the line (0 to {length_m} m)")
    return table


def grid_tags(length_m: Fraction, tag_spacing_m: Fraction) -> TagTable:
    """A tag every ``tag_spacing_m`` from 0 up to (not at) ``length_m``, ids from 1."""
    count = -(-length_m // tag_spacing_m)
    return tag_table(f"a tag every {tag_spacing_m} m", range(1, count + 1), [k * tag_spacing_m for k in range(count)])


def read_tag_table(path: str | Path) -> TagTable:
    """A tag table from a CSV file with the header ``id,position_m`` (one tag per row)."""
    path = Path(path)
    try:
        with path.open(newline="") as f:
            rows = list(csv.reader(f))
    except OSError as exc:
        raise TagTableError(f"{path}: cannot read the tag table: {exc.strerror}") from None
    except UnicodeDecodeError:
        raise TagTableError(f"{path}: the tag table is not UTF-8 text") from None
    if not rows or [c.strip() for c in rows[0]] != ["id", "position_m"]:
        header = ",".join(rows[0]) if rows else ""
        raise TagTableError(f"{path}: the header must be 'id,position_m', got {header!r}")
    for line, row in enumerate(rows[1:], start=2):
        if len(row) != 2:
            raise TagTableError(f"{path}: line {line}: expected 2 fields (id, position_m), got {len(row)}: {row!r}")
    return tag_table(str(path), [r[0] for r in rows[1:]], [r[1] for r in rows[1:]], entry=lambda j: f"line {j + 2}")


def seed000_tags(line_m: int = 15_000, spacing_m: int = 100) -> TagTable:
    """Seed 000 §2.5: a tag every 100 m from 0 m (tag 1) to 15 km (tag 1501): the id counts 10 m units."""
    return tag_table(
        "seed000 tags", [x // 10 + 1 for x in range(0, line_m + 1, spacing_m)], list(range(0, line_m + 1, spacing_m))
    )


def seed002_tags(line_m: int = 56_800, spacing_m: int = 200, group_gap_m: int = 5) -> TagTable:
    """Seed 002 §4.2: tag groups every 200 m; a group is two tags ``group_gap_m`` apart (the seed gives no gap),
    ids ``10 * group + 1`` and ``10 * group + 2``."""
    ids, positions = [], []
    for g, x in enumerate(range(0, line_m - group_gap_m + 1, spacing_m)):
        ids += [10 * g + 1, 10 * g + 2]
        positions += [x, x + group_gap_m]
    return tag_table("seed002 tags", ids, positions)


def position_params(
    table: TagTable,
    *,
    tag_window_m,
    tacho_error,
    train_length_m,
    cycle_s,
    max_acceleration_mps2,
    max_deceleration_mps2,
    source: str = "position data",
) -> PositionParams:
    """Exact :class:`PositionParams` for a tag table, or a :class:`TagTableError` naming the field and value."""
    values = {
        "tag_window_m": tag_window_m,
        "tacho_error": tacho_error,
        "train_length_m": train_length_m,
        "cycle_s": cycle_s,
        "max_acceleration_mps2": max_acceleration_mps2,
        "max_deceleration_mps2": max_deceleration_mps2,
    }
    exact = {name: _number(source, name, raw) for name, raw in values.items()}
    for name in ("tag_window_m", "max_acceleration_mps2", "max_deceleration_mps2"):
        if exact[name] < 0:
            raise TagTableError(f"{source}: {name} = {values[name]!r} is negative")
    for name in ("train_length_m", "cycle_s"):
        if exact[name] <= 0:
            raise TagTableError(f"{source}: {name} = {values[name]!r} is not positive")
    if not 0 <= exact["tacho_error"] < 1:
        raise TagTableError(f"{source}: tacho_error = {tacho_error!r} is outside [0, 1)")
    return PositionParams(tag_ids=table.ids, tag_positions_m=table.positions_m, **exact)


def tacho_distance_m(pulses, wheel_diameter_m, pulses_per_revolution):
    """The distance ``pulses`` tachometer pulses stand for on a wheel of ``wheel_diameter_m`` (float: the
    simulator's sensor; the diameter's uncertainty belongs in ``tacho_error``)."""
    return pulses * math.pi * wheel_diameter_m / pulses_per_revolution


# --- the tachometer's plausibility check as a sub-function node ------------------------------------------------


@dataclass(frozen=True)
class TachoCheckParams(Generic[N, B]):
    tacho_error: N
    cycle_s: N
    max_acceleration_mps2: N
    max_deceleration_mps2: N


@dataclass(frozen=True)
class TachoCheckInputs(Generic[N, B]):
    last_tacho_m: N
    """The tachometer's distance of the previous cycle."""
    tacho_m: N
    """The tachometer's distance of this cycle."""
    last_distance_m: N
    """The true distance of the previous cycle (properties only)."""
    distance_m: N
    """The true distance of this cycle (properties only)."""


@dataclass(frozen=True)
class TachoCheckOutputs(Generic[N, B]):
    implausible_tacho: B


def tacho_check_step(o: Ops, p: TachoCheckParams, s: Stateless, i: TachoCheckInputs):
    return s, TachoCheckOutputs(implausible_increment(o, p, i.last_tacho_m, i.tacho_m))


TACHO_CHECK = stateless_node(
    name="tacho_check",
    params=TachoCheckParams,
    inputs=TachoCheckInputs,
    outputs=TachoCheckOutputs,
    step=tacho_check_step,
    seed="001 §3.2, 002 §3.1",
)
""":func:`implausible_increment` (standstill while running, spin, slide) as a sub-function of its own."""
