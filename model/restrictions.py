"""A line's MRSP for one train, kept current as temporary restrictions come and go (seed 002 §3.2).

The wayside computes the PSL once (:func:`~atcs.model.psl.permanent_speed_limit`);
applying or withdrawing a restriction recomputes only the window it affects
(:func:`~atcs.model.psl.window` and :func:`~atcs.model.psl.restricted`, the step
functions ``mrsp.incremental_equals_full`` is proved about) and splices the result
into the stored segment list (:func:`~atcs.model.psl.splice`, ``mrsp.splice_equals_definition``). Finding the
window is a bisection, the splice a sort of the segments around it put back by a list-slice assignment: the
arithmetic grows with the segments in the window, not with the line.
"""

from __future__ import annotations

import bisect
from collections.abc import Sequence

from atcs.model.ops import Ops
from atcs.model.ops.exact import EXACT
from atcs.model.profile import KMH_PER_MPS, MAX_SPEED_KMH, Profile, ProfileError, parse_number
from atcs.model.psl import Restriction, affected_m, permanent_speed_limit, restricted, splice, window


def canonical(profile: Profile) -> Profile:
    """The same profile without zero-length segments, breakpoints at or past the line end, or equal
    neighbours (concrete profiles only): two profiles are equal everywhere iff their canonical forms are."""
    starts: list = []
    values: list = []
    bounds = (*profile.starts_m[1:], profile.end_m)
    for start, bound, v in zip(profile.starts_m, bounds, profile.values, strict=True):
        if not (start < bound and start < profile.end_m):
            continue  # empty, or past the end: the next segment takes over
        if not values or values[-1] != v:
            starts.append(start)
            values.append(v)
    return Profile(tuple(starts), tuple(values), profile.end_m)


def restriction(field: str, start_m, end_m, limit_kmh, line_end_m) -> Restriction:
    """A validated temporary restriction on ``[start_m, end_m)`` of a line ending at ``line_end_m``,
    its limit given in km/h (stored in m/s)."""
    start = parse_number(field, "start_m", start_m)
    end = parse_number(field, "end_m", end_m)
    limit = parse_number(field, "limit_kmh", limit_kmh)
    if not 0 <= start < end <= line_end_m:
        raise ProfileError(
            f"{field}: [start_m, end_m) = [{start_m!r}, {end_m!r}) is not a non-empty part of the line "
            f"[0, {line_end_m})"
        )
    if not 0 < limit <= MAX_SPEED_KMH:
        raise ProfileError(f"{field}: limit_kmh = {limit_kmh!r} is outside (0, {MAX_SPEED_KMH}] km/h")
    return Restriction(start, end, limit / KMH_PER_MPS)


class SpeedRestrictions:
    """The MRSP of one train on one line: the PSL with the active temporary restrictions merged in."""

    def __init__(self, pisl: Profile, ptsl: Profile, train_length_m, ops: Ops = EXACT):
        if not train_length_m >= 0:
            raise ProfileError(f"train_length_m = {train_length_m!r} is negative")
        self.ops = ops
        self.train_length_m = train_length_m
        self.psl = canonical(permanent_speed_limit(ops, pisl, ptsl, train_length_m))
        self.active: dict[str, Restriction] = {}
        self._starts = list(self.psl.starts_m)
        self._values = list(self.psl.values)

    @property
    def end_m(self):
        return self.psl.end_m

    def mrsp(self) -> Profile:
        """The current MRSP (canonical)."""
        return Profile(tuple(self._starts), tuple(self._values), self.end_m)

    def full(self) -> Profile:
        """The current MRSP recomputed over the whole line (what :meth:`mrsp` must equal)."""
        return canonical(restricted(self.ops, self.psl, tuple(self.active.values()), self.train_length_m))

    def apply(self, name: str, r: Restriction) -> None:
        """Add the restriction ``name`` and update the window it affects."""
        if name in self.active:
            raise ProfileError(f"restriction {name!r} is already applied; withdraw it first")
        if not (0 <= r.start_m < r.end_m <= self.end_m and r.limit_mps > 0):
            raise ProfileError(f"restriction {name!r}: {r} is not a non-empty part of the line with a positive limit")
        self.active[name] = r
        self._update(r)

    def withdraw(self, name: str) -> None:
        """Remove the restriction ``name`` and restore the window it affected."""
        if name not in self.active:
            known = ", ".join(map(repr, self.active)) or "none"
            raise ProfileError(f"restriction {name!r} is not applied (applied: {known})")
        self._update(self.active.pop(name))

    def _update(self, changed: Restriction) -> None:
        from_m, to_m = affected_m(changed, self.train_length_m)
        to_m = min(to_m, self.end_m)
        psl = self.psl
        lo = bisect.bisect_right(psl.starts_m, from_m) - 1
        hi = bisect.bisect_left(psl.starts_m, to_m)
        overlapping = tuple(
            r for r in self.active.values() if r.start_m < to_m and from_m < r.end_m + self.train_length_m
        )
        recomputed = canonical(
            restricted(self.ops, window(self.ops, psl, from_m, to_m, lo, hi), overlapping, self.train_length_m)
        )
        self._splice(from_m, to_m, recomputed)

    def _splice(self, from_m, to_m, recomputed: Profile) -> None:
        """Write ``recomputed`` over ``[from_m, to_m)``: :func:`~atcs.model.psl.splice` (MRSP-09) on the stored
        segments from the one before the window to the one holding ``to_m``, put back in their place."""
        if recomputed.starts_m[0] != from_m:  # MRSP-09's assumption, on the data at hand
            raise AssertionError(f"the recomputed window starts at {recomputed.starts_m[0]}, not at {from_m}")
        starts, values = self._starts, self._values
        lo = max(bisect.bisect_left(starts, from_m) - 1, 0)  # the segment before the window (or the first)
        hi = bisect.bisect_right(starts, to_m)  # past the segment holding to_m
        around = Profile(tuple(starts[lo:hi]), tuple(values[lo:hi]), self.end_m)
        spliced = canonical(splice(self.ops, around, recomputed, from_m, to_m))
        starts[lo:hi] = spliced.starts_m
        values[lo:hi] = spliced.values
        _merge_equal(starts, values, lo + len(spliced.values))  # with the segment after
        _merge_equal(starts, values, lo)  # with the one before


def _merge_equal(starts: list, values: list, k: int) -> None:
    """Merge segment ``k`` into segment ``k - 1`` if they have the same value."""
    if 0 < k < len(values) and values[k] == values[k - 1]:
        del starts[k], values[k]


def as_float(profile: Profile) -> Profile:
    """The profile with float breakpoints and values (for the float backend)."""
    return Profile(_floats(profile.starts_m), _floats(profile.values), float(profile.end_m))


def _floats(values: Sequence) -> tuple[float, ...]:
    return tuple(float(v) for v in values)
