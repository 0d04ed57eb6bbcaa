"""The limits exceeded (seed 000 §2.4.3), tested on their own (seed 001 §3.4).

The node runs :data:`~atcs.model.dynamic_profile.EXCEEDANCES`, the very function supervision calls.
"""

from __future__ import annotations

from atcs.model.dynamic_profile import EXCEEDANCES
from atcs.properties.property import Property


def _strictly_beyond(o, p, s, i, out, nxt):
    """Over a limit exactly when the max safe front is strictly beyond its curve's location or the measured speed
    strictly above its ceiling (at the limit itself the train is not over it)."""

    def over(name):
        return o.or_(
            i.max_safe_front_m > getattr(i, f"{name}_location_m"),
            i.measured_speed_mps > getattr(i, f"{name}_ceiling_mps"),
        )

    return o.and_(*(o.eq(getattr(out, f"over_{name}"), over(name)) for name in ("permitted", "warning", "sbi", "ebi")))


PROPERTIES = (
    Property(
        name="exceedances.strictly_beyond",
        requirement="DYN-02",
        seed="000 §2.4.3",
        text="Each limit (permitted, warning, SBI, EBI) is exceeded exactly when the max safe front is strictly "
        "beyond its curve's location for the measured speed or the measured speed strictly above its ceiling.",
        node=EXCEEDANCES,
        holds=_strictly_beyond,
    ),
)
