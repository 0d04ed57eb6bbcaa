"""The choice of the most restrictive target (seed 000 §2.4, 003 §2.2), tested on its own (seed 001 §3.4).

The node runs :data:`~atcs.model.dynamic_profile.MOST_RESTRICTIVE`, the very function the larger nodes call.
"""

from __future__ import annotations

from dataclasses import fields

from atcs.model.curves import CurveLocations
from atcs.model.dynamic_profile import MOST_RESTRICTIVE
from atcs.properties.property import Property


def _nearest_target(o, p, s, i, out, nxt):
    """For each curve: at or behind every target's location, and one of them."""

    def nearest(name):
        locations, chosen = getattr(i, f"target_{name}"), getattr(out, name)
        return o.and_(*(chosen <= x for x in locations), o.or_(*(o.eq(chosen, x) for x in locations)))

    return o.and_(*(nearest(f.name) for f in fields(CurveLocations)))


PROPERTIES = (
    Property(
        name="most_restrictive.nearest_target",
        requirement="DYN-01",
        seed="000 §2.4, 003 §2.2",
        text="With several targets, each curve is supervised at the nearest of the targets' locations for it: at "
        "or behind every target's, and one of them.",
        node=MOST_RESTRICTIVE,
        holds=_nearest_target,
    ),
)
