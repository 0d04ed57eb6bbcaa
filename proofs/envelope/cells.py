"""The cells of a train's ranges: the whole box first, then halves along the field with the most resolution
steps left, on the grid of each range's resolution from its minimum, until every side is one step."""

from __future__ import annotations

import math

from atcs.model.configuration import DataRange
from atcs.properties.envelope import Cell

__all__ = ["split", "whole_range"]


def whole_range(ranges: tuple[DataRange, ...]) -> Cell:
    """The cell of every value of ``ranges``."""
    return Cell(tuple((r.field, r.min, r.max) for r in ranges))


def _steps(low, high, resolution) -> int:
    return math.ceil((high - low) / resolution)


def split(cell: Cell, ranges: tuple[DataRange, ...]) -> tuple[Cell, Cell] | None:
    """``cell`` in two along its field with the most resolution steps (the first such in order), cut on the
    resolution grid; None when every side is at most one step (the declared resolution reached)."""
    resolution = {r.field: r.resolution for r in ranges}
    origin = {r.field: r.min for r in ranges}
    steps = [_steps(lo, hi, resolution[f]) for f, lo, hi in cell.bounds]
    widest = max(range(len(steps)), key=lambda j: (steps[j], -j))
    if steps[widest] <= 1:
        return None
    field, low, high = cell.bounds[widest]
    first = _steps(origin[field], low, resolution[field])  # low is on the grid, or the range's minimum
    cut = origin[field] + (first + steps[widest] // 2) * resolution[field]
    halves = []
    for lo, hi in ((low, cut), (cut, high)):
        bounds = list(cell.bounds)
        bounds[widest] = (field, lo, hi)
        halves.append(Cell(tuple(bounds)))
    return halves[0], halves[1]
