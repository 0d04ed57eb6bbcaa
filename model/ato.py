"""ATO target-speed selection (seed 003 §2.1, §2.2; docs/design.md domain summary).

Seed 003 gives the rules by which the onboard controller chooses the speed it
drives towards, for a balise (fixed, "discontinuous") MA in §2.1 and for a radio
(train-to-train, "continuous") MA in §2.2:

- far from the MA and far from the next track's speed limit: the smaller of the
  current track's limit and the train's maximum speed (§2.1 first bullet, §2.2
  first bullet);
- far from the MA, faster than the next track's (lower) limit and not far from
  it: that limit (§2.1 second bullet, §2.1.1, §2.2 second bullet, §2.2.1: the
  train starts braking as soon as it enters the limit's "yellow" zone);
- not far from the MA: 0 for a balise MA, braking with the service brake (§2.1
  third bullet, §2.1.2 Fig. 5); for a radio MA the smallest of the preceding
  train's speed, the train's maximum speed and the current and next limits (§2.2
  third bullet, §2.2.2);
- when both the MA and the next limit are near, the controller works out the
  deceleration each needs and follows the one that needs the larger (§2.1.2
  Fig. 6: "compute the deceleration for each and choose the larger").

"Far" and "near" are decided here by braking distance at the ATO's planning
deceleration ``a``: a target (location ``x``, speed ``u``) is near once the
distance to it is at most ``(v^2 - u^2) / (2 a)`` plus a margin (§2.2.2 asks for
a buffer that covers the train length and its braking capability). The seed
gives no formula; docs/design.md's kinetic-energy form keeps it free of square roots
and, multiplied out by ``2 a > 0``, free of division, so the same source runs on
floats, Fractions and z3 (a proof may quantify over ``a`` and the margin).

The deceleration a target needs is ``(v^2 - u^2) / (2 d)`` at distance ``d``; a
target at or behind the front (``d <= 0``) needs an infinite one and wins. The
comparison is multiplied out by ``2 d_1 d_2 > 0``. On a tie the MA wins.

:func:`ato_target_speed` is written once over the :class:`~atcs.model.ops.Ops`;
:func:`limits_ahead` extracts its speed-limit inputs from a concrete MRSP
:class:`~atcs.model.profile.Profile`. This is the ATO's choice of target, not a
supervision function: the ATP's curves (:mod:`atcs.model.curves`) still
supervise whatever the ATO does.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass
from typing import Generic

from atcs.model.curves import FAR_M
from atcs.model.errors import AtcsInputError
from atcs.model.node import Stateless, stateless_node
from atcs.model.ops import B, N, Ops
from atcs.model.profile import Profile

FAR = 0
"""Reason code: neither the MA nor a lower limit is near; the target is min(current limit, train max)."""
SPEED_LIMIT = 1
"""Reason code: the next lower speed limit is the target (seed 003 §2.1.1, §2.2.1)."""
MA_END = 2
"""Reason code: the end of the MA is the target: 0 for a balise MA, the preceding train's speed for a
radio MA (seed 003 §2.1.2, §2.2.2)."""
REASON_NAMES = {FAR: "far", SPEED_LIMIT: "speed limit", MA_END: "MA end"}


class AtoError(AtcsInputError):
    """Invalid ATO planning data; the message names the argument and the value."""


@dataclass(frozen=True)
class AtoTarget(Generic[N]):
    """What the ATO drives towards: ``speed_mps`` at ``location_m`` (the front itself when the
    target is the limit in force), chosen by rule ``reason`` (:data:`FAR`, :data:`SPEED_LIMIT` or
    :data:`MA_END`, as a number so that it is a term under the symbolic backend)."""

    speed_mps: N
    location_m: N
    reason: N


@dataclass(frozen=True)
class LimitsAhead(Generic[N]):
    """The speed-limit inputs of :func:`ato_target_speed` from an MRSP: the limit in force at the
    front and the first lower one ahead (``next_limit_m`` is :data:`~atcs.model.curves.FAR_M` and
    ``next_limit_mps`` the limit in force when there is none)."""

    line_limit_mps: N
    next_limit_m: N
    next_limit_mps: N


def within_braking_distance(o: Ops, speed_mps, target_speed_mps, distance_m, planning_decel_mps2, margin_m):
    """The target ``distance_m`` ahead is near: ``distance_m <= (v^2 - u^2) / (2 a) + margin_m``
    (multiplied out by ``2 a > 0``), or the target is at or behind the front."""
    braking = speed_mps * speed_mps - target_speed_mps * target_speed_mps
    return o.or_(distance_m <= o.const(0), o.const(2) * planning_decel_mps2 * (distance_m - margin_m) <= braking)


def needs_at_least_the_deceleration_of(
    o: Ops, speed_mps, first_speed_mps, first_distance_m, second_speed_mps, second_distance_m
):
    """The first target needs at least the deceleration of the second: ``(v^2 - u1^2) / (2 d1) >=
    (v^2 - u2^2) / (2 d2)``, where a distance ``<= 0`` needs an infinite deceleration (seed 003 §2.1.2).

    Both infinite counts as at least as much. With both distances positive the inequality is
    multiplied out by ``2 d1 d2 > 0``.
    """
    v2 = speed_mps * speed_mps
    first_needs = (v2 - first_speed_mps * first_speed_mps) * second_distance_m
    second_needs = (v2 - second_speed_mps * second_speed_mps) * first_distance_m
    return o.or_(first_distance_m <= o.const(0), o.and_(second_distance_m > o.const(0), first_needs >= second_needs))


def ato_target_speed(o: Ops, **inputs) -> AtoTarget:
    """:func:`choose_target` (the same keywords) on checked planning data: a concrete ``planning_decel_mps2`` that
    is not positive and finite, or ``margin_m`` that is not non-negative and finite, is an :class:`AtoError`
    naming it; symbolic ones are the proof's business (:func:`ato_preconditions`)."""
    _check("planning_decel_mps2", inputs.get("planning_decel_mps2"), allow_zero=False)
    _check("margin_m", inputs.get("margin_m"), allow_zero=True)
    return choose_target(o, **inputs)


def choose_target(
    o: Ops,
    *,
    front_m,
    speed_mps,
    line_limit_mps,
    train_max_mps,
    next_limit_m,
    next_limit_mps,
    ma_end_m,
    ma_speed_mps,
    planning_decel_mps2,
    margin_m,
) -> AtoTarget:
    """The ATO's target speed and the rule that chose it (seed 003 §2.1, §2.2).

    - ``front_m``, ``speed_mps``: the train's front and (estimated) speed;
    - ``line_limit_mps``: the speed limit in force at the front; ``train_max_mps``: the train's maximum;
    - ``next_limit_m``, ``next_limit_mps``: the next lower limit ahead and where it starts
      (:func:`limits_ahead`; a limit at or behind the front is taken as in force);
    - ``ma_end_m``, ``ma_speed_mps``: the end of the MA and the speed allowed there: 0 for a balise
      (fixed) MA, the preceding train's speed for a radio (train-to-train) MA;
    - ``planning_decel_mps2`` (> 0), ``margin_m`` (>= 0): the ATO's planning deceleration and the
      distance margin added to every braking distance.

    Rules (``v`` the speed, ``cap = min(line_limit, train_max)``):

    1. the limit's target speed is ``u_lim = min(next_limit, cap)``; it is near when the train is
       faster than it (§2.1, §2.2 second bullets) and within its braking distance, or it is at or
       behind the front (§2.1.1, §2.2.1: braking starts on entering its yellow zone);
    2. the MA's target speed is ``u_ma = min(ma_speed, next_limit, cap)`` (0 for a balise MA, §2.1
       third bullet; the smallest of the preceding train's speed, the train max and both limits for a
       radio MA, §2.2 third bullet); it is near when within its braking distance or at or behind the
       front (§2.1.2, §2.2.2);
    3. both near: the one that needs the larger deceleration wins, the MA on a tie (§2.1.2 Fig. 6);
       one near: that one; neither: ``cap`` at the front (§2.1, §2.2 first bullets).

    So the target never exceeds ``cap``, and within the MA's braking distance it is at most the MA
    speed unless a speed limit nearer than the MA needs a larger deceleration (then its braking
    pattern reaches the MA's location at or below the MA speed): ATO-01 to ATO-04 prove both.

    :func:`ato_target_speed` checks concrete planning data first; the node :data:`ATO` proves the rules on any
    data :func:`ato_preconditions` admits.
    """
    cap_mps = o.min(line_limit_mps, train_max_mps)
    limit_target_mps = o.min(next_limit_mps, cap_mps)
    ma_target_mps = o.min(ma_speed_mps, limit_target_mps)
    limit_distance_m = next_limit_m - front_m
    ma_distance_m = ma_end_m - front_m

    limit_near = o.or_(
        limit_distance_m <= o.const(0),
        o.and_(
            speed_mps > limit_target_mps,
            within_braking_distance(o, speed_mps, limit_target_mps, limit_distance_m, planning_decel_mps2, margin_m),
        ),
    )
    ma_near = within_braking_distance(o, speed_mps, ma_target_mps, ma_distance_m, planning_decel_mps2, margin_m)
    ma_wins = o.and_(
        ma_near,
        o.or_(
            o.not_(limit_near),
            needs_at_least_the_deceleration_of(
                o, speed_mps, ma_target_mps, ma_distance_m, limit_target_mps, limit_distance_m
            ),
        ),
    )
    limit_wins = o.and_(limit_near, o.not_(ma_wins))
    return AtoTarget(
        speed_mps=o.ite(ma_wins, ma_target_mps, o.ite(limit_wins, limit_target_mps, cap_mps)),
        location_m=o.ite(ma_wins, ma_end_m, o.ite(limit_wins, next_limit_m, front_m)),
        reason=o.ite(ma_wins, o.const(MA_END), o.ite(limit_wins, o.const(SPEED_LIMIT), o.const(FAR))),
    )


def ato_preconditions(
    o: Ops,
    *,
    front_m,
    speed_mps,
    line_limit_mps,
    train_max_mps,
    next_limit_m,
    next_limit_mps,
    ma_end_m,
    ma_speed_mps,
    planning_decel_mps2,
    margin_m,
):
    """What :func:`ato_target_speed` assumes of its inputs, as a predicate for proofs: a positive
    planning deceleration, a non-negative margin and speed, positive limits and non-negative target
    speeds (positions are unconstrained). Takes the same keywords."""
    zero = o.const(0)
    return o.and_(
        planning_decel_mps2 > zero,
        margin_m >= zero,
        speed_mps >= zero,
        line_limit_mps > zero,
        train_max_mps > zero,
        next_limit_mps >= zero,
        ma_speed_mps >= zero,
    )


def limits_ahead(profile: Profile, front_m, *, below_mps=None) -> LimitsAhead:
    """The limit in force at ``front_m`` and the first lower one ahead, from a concrete MRSP profile.

    The limit in force is the profile's value at the front (a segment starting exactly at the front
    already binds; the first segment's value before the profile, the last one's after it). The next
    lower limit is the first segment starting strictly ahead of the front whose limit is below both
    the limit in force and ``below_mps`` when given (pass the train's maximum speed, so that a drop
    that stays above it does not hide a lower one further on). Without one, ``next_limit_m`` is
    :data:`~atcs.model.curves.FAR_M` and ``next_limit_mps`` the limit in force, which never becomes
    a target.

    Seed 003 knows one "next track" at a time (§2.1, §2.2): a still lower limit behind the first
    lower one is seen only once the front has passed the first.
    """
    if below_mps is not None:
        _check("below_mps", below_mps, allow_zero=False)
    line_limit_mps = profile.values[0]
    for start, limit in zip(profile.starts_m[1:], profile.values[1:], strict=True):
        if start <= front_m:
            line_limit_mps = limit
    threshold = line_limit_mps if below_mps is None else min(line_limit_mps, below_mps)
    for start, limit in zip(profile.starts_m[1:], profile.values[1:], strict=True):
        if start > front_m and limit < threshold:
            return LimitsAhead(line_limit_mps, start, limit)
    return LimitsAhead(line_limit_mps, FAR_M, line_limit_mps)


def _check(name: str, value, *, allow_zero: bool) -> None:
    """Raise :class:`AtoError` for a concrete value (a number or an array of them) that is not finite and
    positive (non-negative with ``allow_zero``); symbolic values pass (they are the proof's to constrain)."""
    expected = "non-negative" if allow_zero else "positive"
    if isinstance(value, bool):
        raise AtoError(f"{name} must be a {expected} number, got {value!r}")
    if isinstance(value, numbers.Real):
        items = [(name, value)]
    elif hasattr(value, "dtype") and hasattr(value, "flat"):  # a numpy array: a batch of trains
        items = [(f"{name}[{k}]", x) for k, x in enumerate(value.flat)]
    else:
        return
    for label, x in items:
        finite = x - x == 0  # false for inf and nan, whatever the number type
        if not (finite and (x >= 0 if allow_zero else x > 0)):
            raise AtoError(f"{label} must be {expected} and finite, got {x!r}")


# --- the target selection as a node ------------------------------------------------------------------------------


@dataclass(frozen=True)
class AtoParams(Generic[N, B]):
    train_max_mps: N
    planning_decel_mps2: N
    margin_m: N


@dataclass(frozen=True)
class AtoQuery(Generic[N, B]):
    front_m: N
    speed_mps: N
    line_limit_mps: N
    next_limit_m: N
    next_limit_mps: N
    ma_end_m: N
    ma_speed_mps: N


@dataclass(frozen=True)
class AtoChoice(Generic[N, B]):
    """:class:`AtoTarget` as a node's outputs."""

    target_speed_mps: N
    target_location_m: N
    target_reason: N


def ato_step(o: Ops, p: AtoParams, s: Stateless, i: AtoQuery):
    target = choose_target(o, **vars(p), **vars(i))
    return s, AtoChoice(target.speed_mps, target.location_m, target.reason)


ATO = stateless_node(
    name="ato",
    params=AtoParams,
    inputs=AtoQuery,
    outputs=AtoChoice,
    step=ato_step,
    seed="003 §2.1, §2.2",
)
""":func:`choose_target` with every position, speed, limit, deceleration and margin symbolic."""


__all__ = [
    "ATO",
    "FAR",
    "MA_END",
    "REASON_NAMES",
    "SPEED_LIMIT",
    "AtoChoice",
    "AtoError",
    "AtoParams",
    "AtoQuery",
    "AtoTarget",
    "LimitsAhead",
    "ato_preconditions",
    "ato_target_speed",
    "choose_target",
    "limits_ahead",
    "needs_at_least_the_deceleration_of",
    "within_braking_distance",
]
