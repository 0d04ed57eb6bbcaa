"""Properties of the MRSP (seed 001 §3.3, seed 002 §3.2), for all profiles up to the node's capacity.

The node :data:`~atcs.model.mrsp.MRSP` has every breakpoint, limit and the train
length symbolic: up to 4 PISL segments and 2 segments of each of TISL, PTSL and
TTSL (a profile with fewer segments is the same profile split at extra
breakpoints with equal limits). The line starts at 0.
"""

from __future__ import annotations

from atcs.model.mrsp import MRSP, mrsp_profiles
from atcs.model.profile import is_well_formed, min_over, value_at
from atcs.properties.property import Assumption, Property
from atcs.properties.under_train import TRAIN_ON_LINE, rear_m


def _well_formed(o, p, s, i):
    profiles = mrsp_profiles(p)
    return o.and_(
        p.train_length_m >= o.const(0),
        *(is_well_formed(o, profile) for profile in profiles),
        *(v > o.const(0) for profile in profiles for v in profile.values),
    )


PROFILES_WELL_FORMED = Assumption(
    "profiles_well_formed",
    "every profile starts at 0, its breakpoints increase strictly up to the line end, its limits are positive; "
    "the train length is non-negative",
    _well_formed,
)


ASSUMPTIONS = (PROFILES_WELL_FORMED, TRAIN_ON_LINE)

PROPERTIES = (
    Property(
        name="mrsp.below_every_profile",
        requirement="MRSP-01",
        seed="001 §3.3",
        text="The MRSP at the front is never above any of PISL, TISL, PTSL, TTSL at the front.",
        node=MRSP,
        holds=lambda o, p, s, i, out, nxt: o.and_(
            *(out.mrsp_mps <= value_at(o, profile, i.front_m) for profile in mrsp_profiles(p))
        ),
        assumptions=ASSUMPTIONS,
    ),
    Property(
        name="mrsp.respects_limits_under_train",
        requirement="MRSP-02",
        seed="001 §3.3, 002 §3.2 (Fig. 4)",
        text="The MRSP at the front is never above any of the four profiles anywhere under the train.",
        node=MRSP,
        holds=lambda o, p, s, i, out, nxt: o.and_(
            *(out.mrsp_mps <= value_at(o, profile, i.probe_m) for profile in mrsp_profiles(p))
        ),
        assumptions=ASSUMPTIONS,
    ),
    Property(
        name="mrsp.least_restrictive",
        requirement="MRSP-03",
        seed="001 §3.3",
        text=(
            "The MRSP is not needlessly restrictive: it is at least the lowest limit of the four profiles "
            "under the train, so with MRSP-02 it is the largest profile that respects them."
        ),
        node=MRSP,
        holds=lambda o, p, s, i, out, nxt: out.mrsp_mps >= o.min(
            *(min_over(o, profile, rear_m(o, p, i), i.front_m) for profile in mrsp_profiles(p))
        ),
        assumptions=ASSUMPTIONS,
    ),
)
