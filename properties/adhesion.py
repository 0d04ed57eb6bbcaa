"""The adhesion factor K (seed 000 §2.4.1, Subset-026 §3.13.6.2), tested on its own (seed 001 §3.4).

The node runs :data:`~atcs.model.curves.ADHESION`, the very function the larger nodes call, with all its data
symbolic.
"""

from __future__ import annotations

from atcs.model.curves import ADHESION
from atcs.properties.property import Assumption, Property

ADHESION_DATA = Assumption(
    "adhesion_data",
    "0 <= Kwet_rst <= 1, 0 <= Kdry_rst <= 1, 0 <= M_NVAVADH <= 1 (Subset-026's ranges)",
    lambda o, p, s, i: o.and_(
        *(o.and_(o.const(0) <= v, v <= o.const(1)) for v in (p.kwet_rst, p.kdry_rst, p.m_nvavadh))
    ),
)


def _between_wet_and_dry(o, p, s, i, out, nxt):
    wet, dry = p.kdry_rst * p.kwet_rst, p.kdry_rst
    return o.and_(
        wet <= out.k,
        out.k <= dry,
        o.implies(o.eq(p.m_nvavadh, o.const(0)), o.eq(out.k, wet)),
        o.implies(o.eq(p.m_nvavadh, o.const(1)), o.eq(out.k, dry)),
    )


PROPERTIES = (
    Property(
        name="adhesion.between_wet_and_dry",
        requirement="CRV-07",
        seed="000 §2.4.1 (Subset-026 3.13.6.2)",
        text="K is between the wet-rail factor Kdry_rst * Kwet_rst and the dry-rail factor Kdry_rst, and is the "
        "wet one at M_NVAVADH = 0 and the dry one at M_NVAVADH = 1.",
        node=ADHESION,
        holds=_between_wet_and_dry,
        assumptions=(ADHESION_DATA,),
    ),
)
