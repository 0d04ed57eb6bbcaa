"""Piecewise-constant profiles over distance: speed limits and gradients (seed 001 §3.3, 000 §2.3).

A profile is a fixed number of segments (as SCADE's fixed-size arrays, docs/design.md):
segment ``j`` holds ``values[j]`` on ``[starts_m[j], starts_m[j + 1])``, the last
one up to ``end_m``. Inside the model everything is SI (m, m/s, m/s^2) and
gradients are per mille (positive uphill); km/h are accepted only by the
constructors below and converted once, exactly.

The constructors validate concrete data and raise :class:`ProfileError` naming
the field, the index and the value. The evaluation functions take an ``Ops`` and
work on concrete and symbolic profiles alike.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Generic

from atcs.model.errors import AtcsInputError
from atcs.model.numbers import exact_number
from atcs.model.ops import N, Ops

KMH_PER_MPS = Fraction(36, 10)
MAX_SPEED_KMH = 600
"""Highest speed limit accepted (km/h): above any railway's."""
MAX_GRADIENT_PERMILLE = 100
"""Steepest gradient accepted (per mille, either sign): above any adhesion railway's."""


class ProfileError(AtcsInputError):
    """Invalid profile data; the message names the field, the index and the value."""


@dataclass(frozen=True)
class Profile(Generic[N]):
    """``values[j]`` on ``[starts_m[j], starts_m[j+1])``; the last segment ends at ``end_m``."""

    starts_m: tuple[N, ...]
    values: tuple[N, ...]
    end_m: N


def parse_number(field: str, what: str, raw, error: type[ValueError] = ProfileError) -> Fraction:
    """``raw`` as an exact number (:func:`~atcs.model.numbers.exact_number`: its size bounded first), or an
    ``error`` (:class:`ProfileError` unless given) naming ``field``, ``what`` and the value."""
    try:
        return exact_number(raw)
    except ValueError as exc:
        raise error(f"{field}: {what} = {_shown(raw)} {exc}") from None


def _shown(raw) -> str:
    """``raw`` as an error message shows it: cut short when long."""
    text = repr(raw)
    return text if len(text) <= 60 else f"{text[:40]}...{text[-10:]} ({len(text)} characters)"


def _segments(field: str, starts_m: Sequence, values: Sequence, end_m) -> tuple[list[Fraction], Fraction]:
    if len(starts_m) == 0 or len(starts_m) != len(values):
        raise ProfileError(
            f"{field}: needs one start per value and at least one segment, "
            f"got {len(starts_m)} starts and {len(values)} values"
        )
    starts = [parse_number(field, f"starts_m[{j}]", s) for j, s in enumerate(starts_m)]
    end = parse_number(field, "end_m", end_m)
    if starts[0] != 0:
        raise ProfileError(f"{field}: starts_m[0] = {starts_m[0]!r} is not 0 (a profile starts at the line's start)")
    for j in range(1, len(starts)):
        if starts[j] <= starts[j - 1]:
            raise ProfileError(
                f"{field}: starts_m[{j}] = {starts_m[j]!r} is not after starts_m[{j - 1}] = {starts_m[j - 1]!r} "
                "(segments must be sorted, with positive lengths, and must not overlap)"
            )
    if end <= starts[-1]:
        raise ProfileError(
            f"{field}: end_m = {end_m!r} is not after the last start starts_m[{len(starts) - 1}] = {starts_m[-1]!r} "
            "(the last segment must have a positive length)"
        )
    return starts, end


def speed_profile(field: str, starts_m: Sequence, limits_kmh: Sequence, end_m) -> Profile[Fraction]:
    """A validated speed-limit profile from limits in km/h (stored in m/s)."""
    starts, end = _segments(field, starts_m, limits_kmh, end_m)
    limits = []
    for j, raw in enumerate(limits_kmh):
        v = parse_number(field, f"limits_kmh[{j}]", raw)
        if not 0 < v <= MAX_SPEED_KMH:
            raise ProfileError(f"{field}: limits_kmh[{j}] = {raw!r} is outside (0, {MAX_SPEED_KMH}] km/h")
        limits.append(v / KMH_PER_MPS)
    return Profile(tuple(starts), tuple(limits), end)


def gradient_profile(field: str, starts_m: Sequence, gradients_permille: Sequence, end_m) -> Profile[Fraction]:
    """A validated gradient profile in per mille (positive uphill)."""
    starts, end = _segments(field, starts_m, gradients_permille, end_m)
    grads = []
    for j, raw in enumerate(gradients_permille):
        g = parse_number(field, f"gradients_permille[{j}]", raw)
        if not -MAX_GRADIENT_PERMILLE <= g <= MAX_GRADIENT_PERMILLE:
            raise ProfileError(
                f"{field}: gradients_permille[{j}] = {raw!r} is outside "
                f"[-{MAX_GRADIENT_PERMILLE}, {MAX_GRADIENT_PERMILLE}] per mille"
            )
        grads.append(g)
    return Profile(tuple(starts), tuple(grads), end)


def is_well_formed(o: Ops, profile: Profile):
    """The symbolic counterpart of the constructors' checks on breakpoints: the profile starts at 0 and
    its breakpoints increase strictly up to ``end_m`` (every segment has a positive length)."""
    bounds = (*profile.starts_m[1:], profile.end_m)
    increasing = (a < b for a, b in zip(profile.starts_m, bounds, strict=True))
    return o.and_(o.eq(profile.starts_m[0], o.const(0)), *increasing)


def step_lookup(o: Ops, starts: Sequence, values: Sequence, x):
    """``values[j]`` for the last ``starts[j] <= x`` (``values[0]`` below ``starts[0]``): a step table."""
    value = values[0]
    for start, v in zip(starts[1:], values[1:], strict=True):
        value = o.ite(x >= start, v, value)
    return value


def value_at(o: Ops, profile: Profile, x_m):
    """The profile's value at ``x_m`` (the first segment's before the line, the last one's after it)."""
    return step_lookup(o, profile.starts_m, profile.values, x_m)


def value_at_bisected(o: Ops, profile: Profile, x_m):
    """:func:`value_at` by bisection over the breakpoints (``Ops.first_above``): the same value on a well-formed
    profile (MRSP-08), in a logarithmic number of comparisons on concrete numbers."""
    return o.select(profile.values, o.first_above(profile.starts_m[1:], x_m))


def min_over(o: Ops, profile: Profile, from_m, to_m):
    """The lowest value on ``[from_m, to_m]`` (``from_m <= to_m``): the value at ``from_m`` and
    every segment that starts in ``(from_m, to_m]``."""
    lowest = value_at(o, profile, from_m)
    for start, v in zip(profile.starts_m[1:], profile.values[1:], strict=True):
        lowest = o.ite(o.and_(from_m < start, start <= to_m), o.min(lowest, v), lowest)
    return lowest


def segment_ends(profile: Profile) -> tuple:
    """Where each segment ends: the next segment's start, and ``end_m`` for the last."""
    return (*profile.starts_m[1:], profile.end_m)


def lowest_under_train(o: Ops, profiles: Sequence[Profile], train_length_m, front_m):
    """The lowest value of any of ``profiles`` anywhere under a train whose front is at ``front_m``.

    Train-length extension (seed 001 §3.3, seed 000 §2.3): segment ``[s, e)`` binds
    the front from ``s`` (a lower value applies as soon as the front reaches it)
    until ``e + train_length_m`` (a higher value only once the rear has cleared
    the lower segment), so every rise is delayed by the train length, and a
    segment shorter than the train between two lower ones disappears (seed 002
    Fig. 4(d)). Behind the profiles' start the first segment binds (as :func:`step_lookup` reads it), past their
    end none does (the highest value).
    """
    lowest = o.max(*(v for p in profiles for v in p.values))
    for p in profiles:
        for j, (start, end, v) in enumerate(zip(p.starts_m, segment_ends(p), p.values, strict=True)):
            ahead = front_m < end + train_length_m
            binds = ahead if j == 0 else o.and_(start <= front_m, ahead)
            lowest = o.ite(binds, o.min(lowest, v), lowest)
    return lowest
