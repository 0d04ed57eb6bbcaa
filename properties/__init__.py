"""The safety properties, registered in one place (``PROPERTIES``, by name).

Each module ``<prefix>.py`` holds exactly the properties named ``<prefix>.*``; add a module's properties by
importing its ``PROPERTIES`` tuple below (``tests/properties/test_registry.py`` checks both).
"""

from __future__ import annotations

import fnmatch

from atcs.properties import (
    adhesion,
    ato,
    ats_status,
    authority,
    ceiling_offset,
    closed_loop,
    curves,
    deceleration,
    doors,
    exceedances,
    gradient_acceleration,
    most_restrictive,
    mrsp,
    packet44_codec,
    packet69_codec,
    packet_platforms,
    position,
    report_channel,
    reported_separation,
    resources,
    separation,
    stopping_point,
    supervision,
    t2t_codec,
    t2t_report,
    tacho_check,
    targets,
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
    supervision.PROPERTIES,
    mrsp.PROPERTIES,
    deceleration.PROPERTIES,
    curves.PROPERTIES,
    closed_loop.PROPERTIES,
    position.PROPERTIES,
    resources.PROPERTIES,
    authority.PROPERTIES,
    ats_status.PROPERTIES,
    separation.PROPERTIES,
    doors.PROPERTIES,
    ceiling_offset.PROPERTIES,
    adhesion.PROPERTIES,
    gradient_acceleration.PROPERTIES,
    most_restrictive.PROPERTIES,
    exceedances.PROPERTIES,
    stopping_point.PROPERTIES,
    tacho_check.PROPERTIES,
    targets.PROPERTIES,
    ato.PROPERTIES,
    t2t_report.PROPERTIES,
    t2t_codec.PROPERTIES,
    packet69_codec.PROPERTIES,
    packet44_codec.PROPERTIES,
    report_channel.PROPERTIES,
    reported_separation.PROPERTIES,
    packet_platforms.PROPERTIES,
)


def select(pattern: str | None = None) -> list[Property]:
    """The registered properties whose name matches the glob ``pattern`` (all if None)."""
    if pattern is None:
        return list(PROPERTIES.values())
    return [p for name, p in PROPERTIES.items() if fnmatch.fnmatchcase(name, pattern)]


__all__ = ["PROPERTIES", "Assumption", "Property", "select"]
