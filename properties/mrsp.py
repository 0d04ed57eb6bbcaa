"""Properties of the MRSP (seed 001 §3.3, seed 002 §3.2), for all profiles up to the node's capacity.

The node :data:`~atcs.model.mrsp.MRSP` has every breakpoint, limit and the train
length symbolic: up to 4 PISL segments and 2 segments of each of TISL, PTSL and
TTSL (a profile with fewer segments is the same profile split at extra
breakpoints with equal limits). The line starts at 0.

Seed 002's preprocessed MRSP (§3.2, equations 1 and 2, Fig. 4 and 5): the materialized profiles of
:mod:`atcs.model.psl` are checked against the definition the other MRSP properties are proved about
(:func:`~atcs.model.profile.lowest_under_train`, the lowest limit under the train), for every profile up
to the nodes' capacities, all symbolic.
"""

from __future__ import annotations

import itertools

from atcs.model.mrsp import MRSP, PROFILE_LOOKUP, mrsp_profiles
from atcs.model.profile import Profile, is_well_formed, lowest_under_train, min_over, value_at
from atcs.model.psl import MRSP_UPDATE, PROFILE_SPLICE, PSL, UPDATE_WINDOW, filter_convex_bumps, psl_profiles
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


def _restriction_ok(o, p, start, end, limit, first_allowed):
    return o.and_(first_allowed <= start, start < end, end <= p.line_end_m, limit > o.const(0))


def _psl_data_ok(o, p, s, i):
    profiles = psl_profiles(p)
    return o.and_(
        p.train_length_m >= o.const(0),
        *(is_well_formed(o, profile) for profile in profiles),
        *(v > o.const(0) for profile in profiles for v in profile.values),
    )


def _update_data_ok(o, p, s, i):
    psl = Profile(p.psl_starts_m, p.psl_limits_mps, p.line_end_m)
    lo, _ = UPDATE_WINDOW
    return o.and_(
        p.train_length_m >= o.const(0),
        is_well_formed(o, psl),
        *(v > o.const(0) for v in psl.values),
        _restriction_ok(o, p, p.tsr_start_m, p.tsr_end_m, p.tsr_limit_mps, psl.starts_m[lo]),
        _restriction_ok(o, p, p.other_start_m, p.other_end_m, p.other_limit_mps, o.const(0)),
    )


FRONT_ON_LINE = Assumption(
    "front_on_line",
    "0 <= front < line end",
    lambda o, p, s, i: o.and_(o.const(0) <= i.front_m, i.front_m < p.line_end_m),
)

FRONT_BEFORE_LINE_END = Assumption(
    "front_before_line_end",
    "front < line end (behind the line's start too, where a braking curve walking back from a target reaches)",
    lambda o, p, s, i: i.front_m < p.line_end_m,
)

PSL_DATA = Assumption(
    "psl_data_well_formed",
    "PISL and PTSL start at 0, their breakpoints increase strictly up to the line end, their limits are "
    "positive; the train length is >= 0",
    _psl_data_ok,
)

UPDATE_DATA = Assumption(
    "update_data_well_formed",
    "the PSL starts at 0, increases strictly up to the line end, with positive limits; both restrictions "
    "lie on the line with positive lengths and limits; the updated one starts in the window's first "
    "segment or later (what bisection guarantees); the train length is >= 0",
    _update_data_ok,
)


LOOKUP_PROFILE_WELL_FORMED = Assumption(
    "lookup_profile_well_formed",
    "the profile starts at 0 and its breakpoints increase strictly up to its end",
    lambda o, p, s, i: is_well_formed(o, Profile(p.starts_m, p.values, p.end_m)),
)


def _splice_data_ok(o, p, s, i):
    stored, r = (*p.current_starts_m, p.end_m), p.recomputed_starts_m
    return o.and_(
        *(a < b for a, b in itertools.pairwise(stored)),
        stored[0] <= p.from_m,
        p.from_m < p.to_m,
        o.eq(r[0], p.from_m),
        *(a <= b for a, b in itertools.pairwise(r)),
        r[-1] <= p.to_m,
        stored[0] <= i.x_m,
    )


SPLICE_DATA = Assumption(
    "splice_data",
    "the stored profile's breakpoints increase strictly (from any start) up to its end; the window [from, to) is "
    "non-empty and starts at or after the stored profile's start; the recomputed profile's breakpoints start at "
    "from and never fall, up to to; the position is at or after the stored profile's start",
    _splice_data_ok,
)


def _matches_definition(o, p, s, i, out, nxt):
    pisl, ptsl = psl_profiles(p)
    return o.eq(out.psl_mps, lowest_under_train(o, (pisl, ptsl), p.train_length_m, i.front_m))


def _as_profile(o, p, start_m, end_m, limit_mps) -> Profile:
    """A restriction as a TISL profile of the line (no limit outside it: the highest limit around)."""
    top = o.max(limit_mps, p.tsr_limit_mps, p.other_limit_mps, *p.psl_limits_mps)
    return Profile((o.const(0), start_m, end_m), (top, limit_mps, top), p.line_end_m)


def _restricted_matches_definition(o, p, s, i, out, nxt):
    restrictions = (
        _as_profile(o, p, p.tsr_start_m, p.tsr_end_m, p.tsr_limit_mps),
        _as_profile(o, p, p.other_start_m, p.other_end_m, p.other_limit_mps),
    )
    return o.eq(
        out.applied_full_mps, o.min(out.psl_mps, lowest_under_train(o, restrictions, p.train_length_m, i.front_m))
    )


def _filter_neutral(o, p, s, i, out, nxt):
    pisl, _ = psl_profiles(p)
    filtered = filter_convex_bumps(o, pisl, p.train_length_m)
    return o.eq(
        lowest_under_train(o, (filtered,), p.train_length_m, i.front_m),
        lowest_under_train(o, (pisl,), p.train_length_m, i.front_m),
    )


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
        holds=lambda o, p, s, i, out, nxt: (
            out.mrsp_mps >= o.min(*(min_over(o, profile, rear_m(o, p, i), i.front_m) for profile in mrsp_profiles(p)))
        ),
        assumptions=ASSUMPTIONS,
    ),
    Property(
        name="mrsp.psl_matches_definition",
        requirement="MRSP-04",
        seed="002 §3.2 (equation 1, Fig. 5(a) to 5(d))",
        text=(
            "The materialized PSL (PISL with its short convex bumps filtered, and PTSL, each extended by the "
            "train length, merged) equals at every position, behind the line's start too, the lowest PISL or "
            "PTSL limit under the train."
        ),
        node=PSL,
        holds=_matches_definition,
        assumptions=(PSL_DATA, FRONT_BEFORE_LINE_END),
    ),
    Property(
        name="mrsp.restricted_matches_definition",
        requirement="MRSP-05",
        seed="002 §3.2 (equation 2, Fig. 5(e), 5(f))",
        text=(
            "The materialized MRSP with two temporary restrictions merged into the PSL equals at every position "
            "the lower of the PSL and the lowest restriction under the train."
        ),
        node=MRSP_UPDATE,
        holds=_restricted_matches_definition,
        assumptions=(UPDATE_DATA, FRONT_ON_LINE),
    ),
    Property(
        name="mrsp.bump_filter_neutral",
        requirement="MRSP-06",
        seed="002 §3.2 (Fig. 4(d), 4(e))",
        text=(
            "Removing the convex bumps shorter than the train from PISL does not change the lowest PISL limit "
            "under the train at any position."
        ),
        node=PSL,
        holds=_filter_neutral,
        assumptions=(PSL_DATA, FRONT_ON_LINE),
    ),
    Property(
        name="mrsp.incremental_equals_full",
        requirement="MRSP-07",
        seed="002 §3.2",
        text=(
            "Applying or withdrawing a temporary restriction by recomputing only [start, end + L) from the PSL "
            "gives, at every position, the MRSP recomputed over the whole line (with another restriction active)."
        ),
        node=MRSP_UPDATE,
        holds=lambda o, p, s, i, out, nxt: o.and_(
            o.eq(out.applied_incremental_mps, out.applied_full_mps),
            o.eq(out.withdrawn_incremental_mps, out.withdrawn_full_mps),
        ),
        assumptions=(UPDATE_DATA, FRONT_ON_LINE),
    ),
    Property(
        name="mrsp.bisected_lookup_equals_chain",
        requirement="MRSP-08",
        seed="002 §3.2",
        text=(
            "On a well-formed profile of up to 9 segments, the value at any position (on, before or past the "
            "line) found by bisection over the breakpoints is the value the chain over every breakpoint gives: "
            "what lets supervision on concrete data read the MRSP in logarithmic time."
        ),
        node=PROFILE_LOOKUP,
        holds=lambda o, p, s, i, out, nxt: o.eq(out.bisected, out.chained),
        assumptions=(LOOKUP_PROFILE_WELL_FORMED,),
    ),
    Property(
        name="mrsp.splice_equals_definition",
        requirement="MRSP-09",
        seed="002 §3.2",
        text=(
            "A window's recomputed profile spliced into the stored one (the segment list a temporary restriction's "
            "update writes) has, at every position from the stored profile's start, the value MRSP-07's "
            "incremental update is proved with: the recomputed profile's inside the window, the stored one's "
            "outside."
        ),
        node=PROFILE_SPLICE,
        holds=lambda o, p, s, i, out, nxt: o.eq(out.spliced, out.defined),
        assumptions=(SPLICE_DATA,),
    ),
)
