"""The ATO's choice of target speed (seed 003 §2.1, §2.2): bounded by the limits and the MA it drives towards.

Over :data:`~atcs.model.ato.ATO`, every position, speed, limit, deceleration and margin symbolic, under what
:func:`~atcs.model.ato.ato_preconditions` asks. The ATP supervises whatever the ATO commands (the supervision and
closed-loop properties); these say the ATO plans within what it is given, so that the ATP's interventions are for
faults, not for its plan.
"""

from __future__ import annotations

from atcs.model.ato import ATO, SPEED_LIMIT, ato_preconditions
from atcs.properties.property import Assumption, Property

PLANNING_DATA = Assumption(
    "planning_data",
    "a positive planning deceleration, a non-negative margin and speed, positive limits and non-negative target "
    "speeds (positions any)",
    lambda o, p, s, i: ato_preconditions(o, **vars(p), **vars(i)),
)


def _braking_distance_holds(o, p, i, distance_m, target_speed_mps):
    """``distance <= (v^2 - u^2) / (2 a) + margin``, multiplied out by ``2 a > 0``."""
    v, u = i.speed_mps, target_speed_mps
    return o.const(2) * p.planning_decel_mps2 * (distance_m - p.margin_m) <= v * v - u * u


def _within_the_cap(o, p, s, i, out, nxt):
    cap = o.min(i.line_limit_mps, p.train_max_mps)
    return o.and_(out.target_speed_mps <= cap, out.target_speed_mps >= o.const(0))


def _within_a_near_limit(o, p, s, i, out, nxt):
    near = o.and_(
        i.speed_mps > i.next_limit_mps, _braking_distance_holds(o, p, i, i.next_limit_m - i.front_m, i.next_limit_mps)
    )
    return o.implies(near, out.target_speed_mps <= i.next_limit_mps)


def _ma_near(o, p, i):
    return _braking_distance_holds(o, p, i, i.ma_end_m - i.front_m, i.ma_speed_mps)


def _ma_speed_or_a_steeper_limit(o, p, s, i, out, nxt):
    """At most the MA speed, or a speed limit needing at least the MA's deceleration (``(v^2 - u^2) / d_lim >=
    (v^2 - v_MA^2) / d_MA``, infinite for ``d_lim <= 0``): its pattern passes the MA at or below the MA speed."""
    v2, u = i.speed_mps * i.speed_mps, out.target_speed_mps
    d_ma, d_lim = i.ma_end_m - i.front_m, i.next_limit_m - i.front_m
    steeper = (v2 - u * u) * d_ma >= (v2 - i.ma_speed_mps * i.ma_speed_mps) * d_lim
    limit = o.and_(o.eq(out.target_reason, o.const(SPEED_LIMIT)), o.or_(d_lim <= o.const(0), steeper))
    return o.implies(_ma_near(o, p, i), o.or_(u <= i.ma_speed_mps, limit))


def _ma_speed_with_no_nearer_limit(o, p, s, i, out, nxt):
    return o.implies(o.and_(_ma_near(o, p, i), i.next_limit_m >= i.ma_end_m), out.target_speed_mps <= i.ma_speed_mps)


def _property(name, requirement, text, holds):
    return Property(
        name=name,
        requirement=requirement,
        seed="003 §2.1, §2.2",
        text=text,
        node=ATO,
        holds=holds,
        assumptions=(PLANNING_DATA,),
    )


PROPERTIES = (
    _property(
        "ato.within_the_cap",
        "ATO-01",
        "The ATO's target speed is never negative and never above the smaller of the limit in force and the "
        "train's maximum speed.",
        _within_the_cap,
    ),
    _property(
        "ato.within_a_near_limit",
        "ATO-02",
        "Faster than the next lower limit and within its braking distance at the planning deceleration (plus the "
        "margin), the ATO's target speed is at most that limit.",
        _within_a_near_limit,
    ),
    _property(
        "ato.ma_speed_or_a_steeper_limit",
        "ATO-03",
        "Within the MA's braking distance, the ATO's target speed is at most the MA speed, or it is a speed limit "
        "needing at least the MA's deceleration (whose braking pattern passes the MA at or below its speed).",
        _ma_speed_or_a_steeper_limit,
    ),
    _property(
        "ato.ma_speed_with_no_nearer_limit",
        "ATO-04",
        "Within the MA's braking distance, with no lower limit nearer than the MA, the ATO's target speed is at "
        "most the MA speed.",
        _ma_speed_with_no_nearer_limit,
    ),
)
