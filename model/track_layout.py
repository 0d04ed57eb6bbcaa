"""A line's tags and resources one by one, as a configuration's ``[[lines]]`` or a scenario's ``[line]`` gives
them (docs/configuration.md, "Tags, resources and switches")::

    tags = [{ id = 1, position_m = 0 }, { id = 2, position_m = 5 }, ...]
    resources = [
        { id = 1, kind = "track", start_m = 0, end_m = 500 },
        { id = 2, kind = "switch", start_m = 500, end_m = 560, direction = "reverse" },
        ...
    ]
    switch_throw_s = 6

in place of a tag every ``tag_spacing_m`` and track resources ``resource_length_m`` long. Tags follow
:func:`~atcs.model.position.tag_table`'s rules, on the line; resources :mod:`~atcs.model.route`'s, from 0 to the
line's end. A line with a switch gives ``switch_throw_s``, how long its object controller takes to throw a
switch and report it locked (seed 001 §3.2: the MA extends over a switch only once it is locked in the route's
direction).
"""

from __future__ import annotations

from fractions import Fraction

from atcs.model.data_files import TableReader
from atcs.model.position import TagTableError, line_tags
from atcs.model.route import RouteError, line_resources

__all__ = ["MAX_SWITCH_THROW_S", "track_layout"]

MAX_SWITCH_THROW_S = 60
"""The longest switch throw time accepted (s)."""

_SPACING = {"tags": "tag_spacing_m", "resources": "resource_length_m"}


def track_layout(r: TableReader, length_m: Fraction) -> dict:
    """``tags``, ``resources`` and ``switch_throw_s`` of the table ``r`` (each None where not given); refused, in
    ``r``'s error, where one is given with its spacing form or is malformed."""
    for key, spacing in _SPACING.items():
        if key in r.table and spacing in r.table:
            r.fail(key, f"and {r.name(spacing)} both given: give the {key} one by one or by a spacing")
    try:
        tags = line_tags(r.source, r.name("tags"), r.table["tags"], length_m) if "tags" in r.table else None
        resources = (
            line_resources(r.source, r.name("resources"), r.table["resources"], length_m)
            if "resources" in r.table
            else None
        )
    except (TagTableError, RouteError) as exc:
        raise r.error(str(exc)) from None
    switches = [x for x in resources or () if x.is_switch]
    throw_s = r.optional_number("switch_throw_s", positive=True)
    if switches and throw_s is None:
        raise r.error(
            f"{r.source}: {r.name('switch_throw_s')} is missing: resource {switches[0].id} is a switch, and the "
            "object controller's throw time is needed"
        )
    if throw_s is not None and not switches:
        r.fail("switch_throw_s", f"is given, but {r.name('resources')} has no switch")
    if throw_s is not None and throw_s > MAX_SWITCH_THROW_S:
        r.fail("switch_throw_s", f"is above {MAX_SWITCH_THROW_S} s")
    return {"tags": tags, "resources": resources, "switch_throw_s": throw_s}
