"""A train's route as resources: track sections and switches in the order it runs over them (seed 001 §3.2,
Fig. 6; seed 000 §2.2).

Each resource covers ``[start_m, end_m)`` in route coordinates (the direction of
travel), contiguous from one to the next; a switch also names the direction the
route needs it in (``normal`` or ``reverse``). Loaded from TOML::

    line_end_m = 3000
    [[resource]]
    id = 1
    kind = "track"
    start_m = 0
    end_m = 500
    [[resource]]
    id = 2
    kind = "switch"
    start_m = 500
    end_m = 560
    direction = "reverse"

:func:`route` and :func:`read_route` reject malformed data with a :class:`RouteError`
naming the file, the resource, the field and the value.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

from atcs.model.data_files import read_toml
from atcs.model.errors import AtcsInputError
from atcs.model.profile import parse_number

KINDS = ("track", "switch")
DIRECTIONS = ("normal", "reverse")


class RouteError(AtcsInputError):
    """Malformed route or switch data; the message names the source, the resource, the field and the value."""


@dataclass(frozen=True)
class Resource:
    id: int
    kind: str
    start_m: Fraction
    end_m: Fraction
    direction: str | None = None
    """For a switch: the direction the route needs (``normal`` or ``reverse``)."""

    @property
    def is_switch(self) -> bool:
        return self.kind == "switch"


@dataclass(frozen=True)
class Route:
    resources: tuple[Resource, ...]
    line_end_m: Fraction

    def __len__(self) -> int:
        return len(self.resources)


def _number(where: str, field: str, raw) -> Fraction:
    return parse_number(where, field, raw, RouteError)


def route(source: str, resources: Sequence[Mapping], line_end_m) -> Route:
    """A validated :class:`Route` (see the module docstring), or a :class:`RouteError`."""
    checked = resource_list(source, resources)
    end_of_line = _number(source, "line_end_m", line_end_m)
    if not checked[0].start_m < end_of_line <= checked[-1].end_m:
        raise RouteError(
            f"{source}: line_end_m = {line_end_m!r} is not within the route ({checked[0].start_m}, {checked[-1].end_m}]"
        )
    return Route(checked, end_of_line)


def resource_list(
    source: str, resources: Sequence[Mapping], entry: Callable[[int], str] = "resource {}".format
) -> tuple[Resource, ...]:
    """Validated resources, contiguous from the first (see the module docstring), or a :class:`RouteError` naming
    ``source``, the entry (``entry(k)``), the field and the value."""
    if not resources:
        raise RouteError(f"{source}: a route needs at least one resource")
    checked: list[Resource] = []
    ids: dict[int, int] = {}
    for k, row in enumerate(resources):
        checked.append(_resource(f"{source}: {entry(k)}", k, row, ids, checked[-1] if checked else None))
    return tuple(checked)


def line_resources(source: str, key: str, rows, length_m: Fraction) -> tuple[Resource, ...]:
    """A line's resources (``key = [{id, kind, start_m, end_m, direction}, ...]``): contiguous from 0 to the line's
    end ``length_m``."""
    if not isinstance(rows, list):
        raise RouteError(f"{source}: {key} = {rows!r} must be a list of tables")
    checked = resource_list(source, rows, lambda k: f"{key}[{k}]")
    if checked[0].start_m != 0:
        raise RouteError(f"{source}: {key}[0].start_m = {checked[0].start_m} must be 0 (the line's start)")
    if checked[-1].end_m != length_m:
        raise RouteError(
            f"{source}: {key}[{len(checked) - 1}].end_m = {checked[-1].end_m} must be the line's end ({length_m} m)"
        )
    return checked


def grid_resources(length_m: Fraction, resource_length_m: Fraction) -> tuple[Resource, ...]:
    """Track resources ``resource_length_m`` long from 0 to ``length_m`` (the last one shorter), ids from 1."""
    starts = [k * resource_length_m for k in range(-(-length_m // resource_length_m))]
    ends = [*starts[1:], length_m]
    return tuple(Resource(k + 1, "track", a, b) for k, (a, b) in enumerate(zip(starts, ends, strict=True)))


def _resource(where: str, k: int, entry, ids: dict[int, int], previous: Resource | None) -> Resource:
    """Resource ``k`` of a route, contiguous with the ``previous`` one; ``ids`` the ids so far (updated)."""
    if not isinstance(entry, Mapping):
        raise RouteError(f"{where}: expected a table of fields, got {entry!r}")
    unknown = sorted(set(entry) - {"id", "kind", "start_m", "end_m", "direction"})
    if unknown:
        raise RouteError(f"{where}: unknown field {unknown[0]!r} (fields: id, kind, start_m, end_m, direction)")
    for field in ("id", "kind", "start_m", "end_m"):
        if field not in entry:
            raise RouteError(f"{where}: {field} is missing")
    raw_id = entry["id"]
    if isinstance(raw_id, bool) or not isinstance(raw_id, int):
        raise RouteError(f"{where}: id = {raw_id!r} is not a whole number")
    if raw_id in ids:
        raise RouteError(f"{where}: id = {raw_id!r} duplicates the id of resource {ids[raw_id]}")
    ids[raw_id] = k
    kind = entry["kind"]
    if kind not in KINDS:
        raise RouteError(f"{where}: kind = {kind!r} is not one of {', '.join(KINDS)}")
    start, end = _extent(where, k, entry, previous)
    return Resource(raw_id, kind, start, end, _direction(where, kind, entry))


def _extent(where: str, k: int, entry: Mapping, previous: Resource | None) -> tuple[Fraction, Fraction]:
    """The start and end of resource ``k``: the first starts at or after 0, each other where the ``previous`` ends."""
    start, end = _number(where, "start_m", entry["start_m"]), _number(where, "end_m", entry["end_m"])
    if previous is None and start < 0:
        raise RouteError(f"{where}: start_m = {entry['start_m']!r} is negative")
    if previous is not None and start != previous.end_m:
        raise RouteError(
            f"{where}: start_m = {entry['start_m']!r} does not continue resource {k - 1}, which ends at "
            f"{previous.end_m} (resources must be contiguous along the route)"
        )
    if end <= start:
        raise RouteError(f"{where}: end_m = {entry['end_m']!r} is not after start_m = {entry['start_m']!r}")
    return start, end


def _direction(where: str, kind: str, entry: Mapping) -> str | None:
    """A resource's direction: a switch's is 'normal' or 'reverse', a track has none."""
    direction = entry.get("direction")
    if kind == "switch" and direction not in DIRECTIONS:
        raise RouteError(f"{where}: a switch needs direction = 'normal' or 'reverse', got {direction!r}")
    if kind == "track" and direction is not None:
        raise RouteError(f"{where}: direction = {direction!r} is given for a track resource (only switches)")
    return direction


def read_route(path: str | Path) -> Route:
    """A route from a TOML file (see the module docstring)."""
    path = Path(path)
    doc = read_toml(path, RouteError, "the route")
    unknown = sorted(set(doc) - {"resource", "line_end_m"})
    if unknown:
        raise RouteError(f"{path}: unknown key {unknown[0]!r} (keys: line_end_m, [[resource]])")
    if "line_end_m" not in doc:
        raise RouteError(f"{path}: line_end_m is missing")
    resources = doc.get("resource", [])
    if not isinstance(resources, list):
        raise RouteError(f"{path}: resource must be an array of tables ([[resource]]), got {resources!r}")
    return route(str(path), resources, doc["line_end_m"])
