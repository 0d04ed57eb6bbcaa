"""The safety properties, registered in one place (``PROPERTIES``, by name).

Add a module's properties by importing its ``PROPERTIES`` tuple below.
"""

from __future__ import annotations

import fnmatch

from atcs.properties import (
    authority,
    closed_loop,
    curves,
    deceleration,
    doors,
    mrsp,
    position,
    preprocessing,
    resources,
    separation,
    sub_functions,
    supervision,
)
from atcs.properties.property import Assumption, Property


def _register(*groups: tuple[Property, ...]) -> dict[str, Property]:
    registry: dict[str, Property] = {}
    for group in groups:
        for prop in group:
            if prop.name in registry:
                raise ValueError(f"property {prop.name!r} is registered twice")
            registry[prop.name] = prop
    for prop in registry.values():
        for lemma in prop.lemmas:
            if lemma not in registry:
                raise ValueError(f"property {prop.name}: lemma {lemma!r} is not a registered property")
    return registry


PROPERTIES: dict[str, Property] = _register(
    supervision.PROPERTIES, mrsp.PROPERTIES, preprocessing.PROPERTIES, deceleration.PROPERTIES,
    curves.PROPERTIES, closed_loop.PROPERTIES, position.PROPERTIES, resources.PROPERTIES,
    authority.PROPERTIES, separation.PROPERTIES, doors.PROPERTIES, sub_functions.PROPERTIES,
)


def select(pattern: str | None = None) -> list[Property]:
    """The registered properties whose name matches the glob ``pattern`` (all if None)."""
    if pattern is None:
        return list(PROPERTIES.values())
    return [p for name, p in PROPERTIES.items() if fnmatch.fnmatchcase(name, pattern)]


__all__ = ["PROPERTIES", "Assumption", "Property", "select"]
