"""Seed 002 §3.2 preprocessing: the permanent speed limit (PSL) computed once per line and train, and
temporary restrictions merged into it window by window (equations 1 and 2, Fig. 4 and 5).

The MRSP of :mod:`atcs.model.mrsp` is a *query* (the limit at one front position).
Here the same limit is *materialized* as a sorted segment list, so that the
wayside can store it and send it over the MA horizon:

- ``PSL = f(PISL) ∪ TL ∩ PTSL`` (equation 1): PISL with its short convex bumps
  filtered (:func:`filter_convex_bumps`), each profile extended by the train length
  (:func:`extend_by_train_length`), and the two merged (:func:`merge_min`);
- ``MRSP = PSL ∩ (TSR ∪ TL)`` (equation 2): each temporary restriction (TISL or
  TTSL alike) binds the front on ``[start, end + L)`` (:func:`restricted`).

A restriction changes the MRSP only on ``[start, end + L)``, so applying or
withdrawing one recomputes that window alone from the PSL's segments there and
the restrictions then active (:func:`window`, then :func:`restricted`): the cost
grows with the segments in the window, not with the line. Every function here is a
step function under any ``Ops``; the proofs (``mrsp.preprocessed_matches_definition``,
``mrsp.bump_filter_neutral``, ``mrsp.incremental_equals_full``) run them
symbolically, :mod:`atcs.model.restrictions` keeps a line's MRSP up to date with
them on concrete data.

Materialized profiles may contain zero-length segments (repeated breakpoints) and
breakpoints past the line end; :func:`~atcs.model.profile.value_at` reads them
correctly and :func:`atcs.model.restrictions.canonical` removes them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Generic

from atcs.model.node import Stateless, stateless_node
from atcs.model.ops import B, N, Ops
from atcs.model.profile import Profile, segment_ends, value_at


@dataclass(frozen=True)
class Restriction(Generic[N]):
    """A temporary speed restriction (TISL or TTSL): ``limit_mps`` on ``[start_m, end_m)`` of the line."""

    start_m: N
    end_m: N
    limit_mps: N


def merge_min(o: Ops, first: Profile, *rest: Profile) -> Profile:
    """The pointwise minimum of profiles on the same line (``∩`` in equations 1 and 2), materialized.

    Pairs are merged in a balanced tree; each merge sorts the two breakpoint lists
    together (``o.sort_by_key``) and scans them keeping each profile's current value.
    """
    profiles = [first, *rest]
    while len(profiles) > 1:
        pairs = [profiles[k : k + 2] for k in range(0, len(profiles), 2)]
        profiles = [_merge_pair(o, *pair) if len(pair) == 2 else pair[0] for pair in pairs]
    return profiles[0]


def _merge_pair(o: Ops, a: Profile, b: Profile) -> Profile:
    from_a = (o.const_bool(True),) * len(a.starts_m) + (o.const_bool(False),) * len(b.starts_m)
    starts, from_a, values = o.sort_by_key((*a.starts_m, *b.starts_m), from_a, (*a.values, *b.values))
    current_a, current_b = a.values[0], b.values[0]
    merged = []
    for is_a, v in zip(from_a, values, strict=True):
        current_a = o.ite(is_a, v, current_a)
        current_b = o.ite(is_a, current_b, v)
        merged.append(o.min(current_a, current_b))
    return Profile(starts, tuple(merged), a.end_m)


def interval(o: Ops, base: Profile, from_m, to_m, limit) -> Profile:
    """A profile on ``base``'s line that is ``limit`` on ``[from_m, to_m)`` and, elsewhere, no lower
    than any of ``base``'s values (so merging it into ``base`` changes nothing there)."""
    origin = base.starts_m[0]
    top = o.max(limit, *base.values)
    return Profile((origin, o.max(from_m, origin), o.max(to_m, origin)), (top, limit, top), base.end_m)


def extend_by_train_length(o: Ops, profile: Profile, train_length_m) -> Profile:
    """``∪ TL``: every segment ``[s, e)`` binds the front on ``[s, e + L)`` (seed 001 §3.3), materialized.

    Equal, point by point, to :func:`~atcs.model.profile.lowest_under_train` of the profile alone. The result
    starts with zero-length segments; the first one's value, which a braking walk extends behind the line's
    start (:func:`~atcs.model.curves.braking_walk`), is the profile's first value, the one in force there (the
    merge alone would leave the line's highest value in it: on the unsafe side for a gradient).
    """
    extended = merge_min(
        o,
        *(
            interval(o, profile, start, end + train_length_m, v)
            for start, end, v in zip(profile.starts_m, segment_ends(profile), profile.values, strict=True)
        ),
    )
    return Profile(extended.starts_m, (profile.values[0], *extended.values[1:]), extended.end_m)


def filter_convex_bumps(o: Ops, profile: Profile, train_length_m) -> Profile:
    """``f``: a segment shorter than the train and higher than both neighbours (a convex bump,
    Fig. 4(d)) is lowered to the higher of its neighbours, merging into it (Fig. 4(e)).

    Extended by the train length, a bump is never the lowest limit under the train,
    so the filter does not change the extended profile (``mrsp.bump_filter_neutral``);
    it removes segments before the extension. Seed 002 lowers the bump to the
    *preceding* segment's limit; when the following segment is higher that is
    needlessly restrictive for one train length past the bump, so the higher
    neighbour is used here.
    """
    ends = segment_ends(profile)
    values = list(profile.values)
    for j in range(1, len(values) - 1):
        before, v, after = profile.values[j - 1], profile.values[j], profile.values[j + 1]
        bump = o.and_(v > before, v > after, ends[j] - profile.starts_m[j] < train_length_m)
        values[j] = o.ite(bump, o.max(before, after), v)
    return Profile(profile.starts_m, tuple(values), profile.end_m)


def permanent_speed_limit(o: Ops, pisl: Profile, ptsl: Profile, train_length_m) -> Profile:
    """Equation 1: ``PSL = f(PISL) ∪ TL ∩ PTSL ∪ TL``, computed once per line and train."""
    return merge_min(
        o,
        extend_by_train_length(o, filter_convex_bumps(o, pisl, train_length_m), train_length_m),
        extend_by_train_length(o, ptsl, train_length_m),
    )


def restricted(o: Ops, base: Profile, restrictions: tuple[Restriction, ...], train_length_m) -> Profile:
    """Equation 2: ``base`` (the PSL, or a window of it) with each restriction merged in over
    ``[start, end + L)``: the MRSP."""
    return merge_min(
        o, base, *(interval(o, base, r.start_m, r.end_m + train_length_m, r.limit_mps) for r in restrictions)
    )


def affected_m(r: Restriction, train_length_m) -> tuple:
    """The part of the line where applying or withdrawing ``r`` can change the MRSP: ``[start, end + L)``."""
    return r.start_m, r.end_m + train_length_m


def window(o: Ops, profile: Profile, from_m, to_m, lo: int, hi: int) -> Profile:
    """``profile`` cut to ``[from_m, to_m)``, from its segments ``lo`` to ``hi - 1``.

    The caller picks the segments (by bisection on concrete data): segment ``lo``
    must start at or before ``from_m``, and segment ``hi`` (if any) at or after
    ``to_m``. Breakpoints are clamped into the window, so extra segments are harmless.
    """
    inner = tuple(o.min(o.max(s, from_m), to_m) for s in profile.starts_m[lo + 1 : hi])
    return Profile((from_m, *inner), profile.values[lo:hi], to_m)


def spliced_value_at(o: Ops, current: Profile, recomputed: Profile, from_m, to_m, x_m):
    """The value at ``x_m`` of ``current`` with ``[from_m, to_m)`` replaced by ``recomputed``: what
    :class:`atcs.model.restrictions.SpeedRestrictions` splices into its segment list."""
    inside = o.and_(from_m <= x_m, x_m < to_m)
    return o.ite(inside, value_at(o, recomputed, x_m), value_at(o, current, x_m))


def splice(o: Ops, current: Profile, recomputed: Profile, from_m, to_m) -> Profile:
    """``current`` with ``[from_m, to_m)`` replaced by ``recomputed`` (a profile of that window, its first
    breakpoint at ``from_m``), as one profile: current's breakpoints before the window, recomputed's, and from
    ``to_m`` on current's again. Of fixed shape: current's breakpoints inside the window move to ``to_m`` with
    current's value there, one more breakpoint at ``to_m`` carries it too, and one sort orders them all
    (MRSP-09: its value is :func:`spliced_value_at`'s at every position from current's start)."""
    tail = value_at(o, current, to_m)
    keys, values = [], []
    for start, value in zip(current.starts_m, current.values, strict=True):
        inside = o.and_(from_m <= start, start < to_m)
        keys.append(o.ite(inside, to_m, start))
        values.append(o.ite(inside, tail, value))
    keys, values = o.sort_by_key((*keys, *recomputed.starts_m, to_m), (*values, *recomputed.values, tail))
    return Profile(keys, values, current.end_m)


# --- the nodes the proofs quantify over ------------------------------------------------------------


@dataclass(frozen=True)
class PslParams(Generic[N, B]):
    line_end_m: N
    train_length_m: N
    pisl_starts_m: tuple[N, ...]
    pisl_limits_mps: tuple[N, ...]
    ptsl_starts_m: tuple[N, ...]
    ptsl_limits_mps: tuple[N, ...]


@dataclass(frozen=True)
class FrontQuery(Generic[N, B]):
    front_m: N


@dataclass(frozen=True)
class PslOutputs(Generic[N, B]):
    psl_mps: N
    """The materialized PSL at the front."""


def psl_profiles(p: PslParams) -> tuple[Profile, Profile]:
    return (
        Profile(p.pisl_starts_m, p.pisl_limits_mps, p.line_end_m),
        Profile(p.ptsl_starts_m, p.ptsl_limits_mps, p.line_end_m),
    )


def psl_step(o: Ops, p: PslParams, s: Stateless, i: FrontQuery):
    pisl, ptsl = psl_profiles(p)
    psl = permanent_speed_limit(o, pisl, ptsl, p.train_length_m)
    return s, PslOutputs(psl_mps=value_at(o, psl, i.front_m))


PSL = stateless_node(
    name="psl",
    params=PslParams,
    inputs=FrontQuery,
    outputs=PslOutputs,
    step=psl_step,
    seed="002 §3.2",
    sizes={"pisl_starts_m": 3, "pisl_limits_mps": 3, "ptsl_starts_m": 2, "ptsl_limits_mps": 2},
)
"""The PSL as a node for proofs: up to 3 PISL and 2 PTSL segments, every breakpoint, limit and the
train length symbolic."""


@dataclass(frozen=True)
class UpdateParams(Generic[N, B]):
    line_end_m: N
    train_length_m: N
    psl_starts_m: tuple[N, ...]
    """A materialized PSL (any sorted profile)."""
    psl_limits_mps: tuple[N, ...]
    tsr_start_m: N
    """The restriction applied or withdrawn."""
    tsr_end_m: N
    tsr_limit_mps: N
    other_start_m: N
    """A restriction active throughout, which may overlap the first."""
    other_end_m: N
    other_limit_mps: N


@dataclass(frozen=True)
class UpdateOutputs(Generic[N, B]):
    psl_mps: N
    applied_incremental_mps: N
    applied_full_mps: N
    withdrawn_incremental_mps: N
    withdrawn_full_mps: N


UPDATE_WINDOW = (1, 4)
"""The PSL segments the proof's window is cut from: a window on segments 1 to 3 of a 4-segment PSL
(so the window holds up to 3 segments, may reach the line end, and segment 0 lies before it)."""


def update_step(o: Ops, p: UpdateParams, s: Stateless, i: FrontQuery):
    psl = Profile(p.psl_starts_m, p.psl_limits_mps, p.line_end_m)
    tsr = Restriction(p.tsr_start_m, p.tsr_end_m, p.tsr_limit_mps)
    other = Restriction(p.other_start_m, p.other_end_m, p.other_limit_mps)
    from_m, to_m = affected_m(tsr, p.train_length_m)
    psl_window = window(o, psl, from_m, to_m, *UPDATE_WINDOW)
    without = restricted(o, psl, (other,), p.train_length_m)
    with_tsr = restricted(o, psl, (other, tsr), p.train_length_m)
    applied = restricted(o, psl_window, (other, tsr), p.train_length_m)
    withdrawn = restricted(o, psl_window, (other,), p.train_length_m)
    return s, UpdateOutputs(
        psl_mps=value_at(o, psl, i.front_m),
        applied_incremental_mps=spliced_value_at(o, without, applied, from_m, to_m, i.front_m),
        applied_full_mps=value_at(o, with_tsr, i.front_m),
        withdrawn_incremental_mps=spliced_value_at(o, with_tsr, withdrawn, from_m, to_m, i.front_m),
        withdrawn_full_mps=value_at(o, without, i.front_m),
    )


MRSP_UPDATE = stateless_node(
    name="mrsp_update",
    params=UpdateParams,
    inputs=FrontQuery,
    outputs=UpdateOutputs,
    step=update_step,
    seed="002 §3.2",
    sizes={"psl_starts_m": 4, "psl_limits_mps": 4},
)
"""Applying and withdrawing a restriction, window only versus whole line, as a node for proofs: a
4-segment PSL, the restriction and one other active restriction, all symbolic."""


__all__ = [
    "MRSP_UPDATE",
    "PROFILE_SPLICE",
    "PSL",
    "Restriction",
    "affected_m",
    "extend_by_train_length",
    "filter_convex_bumps",
    "interval",
    "merge_min",
    "permanent_speed_limit",
    "restricted",
    "splice",
    "spliced_value_at",
    "window",
]


@dataclass(frozen=True)
class SpliceParams(Generic[N, B]):
    current_starts_m: tuple[N, ...]
    current_values: tuple[N, ...]
    end_m: N
    recomputed_starts_m: tuple[N, ...]
    recomputed_values: tuple[N, ...]
    from_m: N
    to_m: N


@dataclass(frozen=True)
class SpliceQuery(Generic[N, B]):
    x_m: N


@dataclass(frozen=True)
class SpliceOutputs(Generic[N, B]):
    spliced: N
    """The value of :func:`splice`'s profile at ``x_m``."""
    defined: N
    """:func:`spliced_value_at`'s."""


def splice_step(o: Ops, p: SpliceParams, s: Stateless, i: SpliceQuery):
    current = Profile(p.current_starts_m, p.current_values, p.end_m)
    recomputed = Profile(p.recomputed_starts_m, p.recomputed_values, p.to_m)
    return s, SpliceOutputs(
        spliced=value_at(o, splice(o, current, recomputed, p.from_m, p.to_m), i.x_m),
        defined=spliced_value_at(o, current, recomputed, p.from_m, p.to_m, i.x_m),
    )


PROFILE_SPLICE = stateless_node(
    name="profile_splice",
    params=SpliceParams,
    inputs=SpliceQuery,
    outputs=SpliceOutputs,
    step=splice_step,
    seed="002 §3.2",
    sizes={"current_starts_m": 4, "current_values": 4, "recomputed_starts_m": 3, "recomputed_values": 3},
)
"""A window's recomputed profile spliced into the stored one, as a node for proofs: 4 stored segments (the ones
around the window :class:`~atcs.model.restrictions.SpeedRestrictions` cuts out) and 3 recomputed, every
breakpoint, value and the window symbolic."""
