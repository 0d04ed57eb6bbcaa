"""The speed-dependent ceiling offset dV (seed 000 §2.4.2, Subset-026 §3.13.9.3), tested on its own (seed 001 §3.4).

The node runs :data:`~atcs.model.curves.CEILING_OFFSET`, the very function the larger nodes call,
with all its data symbolic.
"""

from __future__ import annotations

from atcs.model.curves import CEILING_OFFSET, MIN_SPAN
from atcs.properties.property import Assumption, Property

NATIONAL_OFFSET = Assumption(
    "national_offset",
    f"0 <= dV_min <= dV_max and 0 <= V_min, V_max - V_min >= {MIN_SPAN} m/s (Subset-026's ranges for dV_ebi, "
    "dV_sbi, dV_warning; the guard in ceiling_offset_mps is for invalid data only)",
    lambda o, p, s, i: o.and_(
        o.const(0) <= p.dv_min_mps,
        p.dv_min_mps <= p.dv_max_mps,
        o.const(0) <= p.v_min_mps,
        p.v_max_mps - p.v_min_mps >= o.const(MIN_SPAN),
    ),
)


def _offset_between(o, p, s, i, out, nxt):
    return o.and_(p.dv_min_mps <= out.offset_mps, out.offset_mps <= p.dv_max_mps)


def _offset_ends(o, p, s, i, out, nxt):
    return o.and_(
        o.implies(i.speed_mps <= p.v_min_mps, o.eq(out.offset_mps, p.dv_min_mps)),
        o.implies(i.speed_mps >= p.v_max_mps, o.eq(out.offset_mps, p.dv_max_mps)),
    )


def _offset_interpolated(o, p, s, i, out, nxt):
    """(dV - dV_min) * (V_max - V_min) = (dV_max - dV_min) * (V - V_min) between the ends: the line through them."""
    between = o.and_(p.v_min_mps < i.speed_mps, i.speed_mps < p.v_max_mps)
    return o.implies(
        between,
        o.eq(
            (out.offset_mps - p.dv_min_mps) * (p.v_max_mps - p.v_min_mps),
            (p.dv_max_mps - p.dv_min_mps) * (i.speed_mps - p.v_min_mps),
        ),
    )


PROPERTIES = (
    Property(
        name="ceiling_offset.between_its_ends",
        requirement="CRV-03",
        seed="000 §2.4.2 (Subset-026 3.13.9.3)",
        text="The speed-dependent offset dV is never below dV_min nor above dV_max, at any speed.",
        node=CEILING_OFFSET,
        holds=_offset_between,
        assumptions=(NATIONAL_OFFSET,),
    ),
    Property(
        name="ceiling_offset.ends_at_the_stated_speeds",
        requirement="CRV-04",
        seed="000 §2.4.2 (Subset-026 3.13.9.3)",
        text="dV is dV_min at or below V_min and dV_max at or above V_max.",
        node=CEILING_OFFSET,
        holds=_offset_ends,
        assumptions=(NATIONAL_OFFSET,),
    ),
    Property(
        name="ceiling_offset.linear_between_its_ends",
        requirement="CRV-05",
        seed="000 §2.4.2 (Subset-026 3.13.9.3)",
        text="Between V_min and V_max, dV is on the straight line from (V_min, dV_min) to (V_max, dV_max).",
        node=CEILING_OFFSET,
        holds=_offset_interpolated,
        assumptions=(NATIONAL_OFFSET,),
    ),
)
