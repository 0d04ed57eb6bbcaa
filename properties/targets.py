"""The targets supervision takes from the horizon (seed 000 §2.4, 002 §3.2; Subset-026 §3.13.8.3), tested on their
own (seed 001 §3.4).

The node runs :data:`~atcs.model.dynamic_profile.TARGETS`: :func:`~atcs.model.dynamic_profile.decrease_targets`
and :func:`~atcs.model.dynamic_profile.eoa_target`, the functions :func:`supervised_targets` takes the targets
with, for an MRSP of four segments (starts and values symbolic), any EoA, front and national data. Each claim is
stated from the MRSP and the ceilings, not through the node's own code: a speed decrease missed, or a foot speed
above the ceiling the train is then held to, leaves a stretch where neither a curve nor a ceiling holds the
train to the lower limit.
"""

from __future__ import annotations

from atcs.model.dynamic_profile import TARGETS, ceilings
from atcs.properties.property import Property


def _every_decrease_ahead(o, p, s, i, out, nxt):
    starts, values = p.mrsp_starts_m, p.mrsp_values_mps
    claims = []
    for j in range(1, len(values)):
        ahead = o.and_(values[j] < values[j - 1], i.max_safe_front_m < starts[j], starts[j] < p.eoa_m)
        claims += [
            o.eq(out.supervised[j - 1], ahead),
            o.eq(out.target_location_m[j - 1], starts[j]),
            o.eq(out.target_speed_mps[j - 1], values[j]),
        ]
    return o.and_(*claims)


def _foot_at_the_ebi_ceiling(o, p, s, i, out, nxt):
    values, feet = p.mrsp_values_mps, out.target_ebd_foot_mps
    return o.and_(*(o.eq(feet[j - 1], ceilings(o, p, values[j]).ebi_mps) for j in range(1, len(values))))


def _eoa_target(o, p, s, i, out, nxt):
    released = p.eoa_speed_mps > o.const(0)
    return o.and_(
        o.eq(out.eoa_target_location_m, p.eoa_m),
        o.eq(out.eoa_target_speed_mps, p.eoa_speed_mps),
        o.implies(released, o.eq(out.eoa_target_ebd_foot_mps, ceilings(o, p, p.eoa_speed_mps).ebi_mps)),
        o.implies(o.not_(released), o.eq(out.eoa_target_ebd_foot_mps, p.eoa_speed_mps)),
    )


def _property(name, requirement, seed, text, holds):
    return Property(name=name, requirement=requirement, seed=seed, text=text, node=TARGETS, holds=holds)


PROPERTIES = (
    _property(
        "targets.every_decrease_ahead",
        "DYN-03",
        "000 §2.4, 002 §3.2",
        "A boundary of the MRSP is supervised as a target exactly when the speed decreases there and it lies ahead "
        "of the max safe front and short of the end of authority; the target is at the boundary, at the lower speed.",
        _every_decrease_ahead,
    ),
    _property(
        "targets.foot_at_the_ebi_ceiling",
        "DYN-04",
        "Subset-026 §3.13.8.3.1, §3.13.9.3",
        "A speed decrease's EBD ends at the EBI ceiling of the lower speed (V_target + dV_ebi(V_target), as the "
        "ceiling supervision computes it past the decrease): the curve hands the train to the ceiling there.",
        _foot_at_the_ebi_ceiling,
    ),
    _property(
        "targets.eoa_target",
        "DYN-05",
        "Subset-026 §3.13.8.3.1-2",
        "The end of authority is a target at dMA with speed vMA; its EBD ends at standstill when vMA is 0, and at "
        "the EBI ceiling of vMA when it is above 0 (a limit of authority).",
        _eoa_target,
    ),
)
