"""The ATO's choice of target speed (seed 003 §2.1, §2.2): bounded by the limits and the MA it drives towards.

Over :data:`~atcs.model.ato.ATO`, every position, speed, limit, deceleration and margin symbolic, under what
:func:`~atcs.model.ato.ato_preconditions` asks. The ATP supervises whatever the ATO commands (the supervision and
closed-loop properties); these say the ATO plans within what it is given, so that the ATP's interventions are for
faults, not for its plan.
"""

from __future__ import annotations

from atcs.model.ato import ATO, FAR, MA_END, SPEED_LIMIT, ato_preconditions
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


def _targets(o, p, i):
    """The three targets of seed 003 §2.1 and §2.2: the smaller of the limit in force and the train's maximum (at
    the front), the next lower limit (at most that) and the MA's speed (at most both limits)."""
    cap = o.min(i.line_limit_mps, p.train_max_mps)
    limit = o.min(i.next_limit_mps, cap)
    return cap, limit, o.min(i.ma_speed_mps, limit)


def _modes(o, p, i):
    """``(limit near, MA near, the MA needs at least the limit's deceleration)`` (seed 003 §2.1.1, §2.1.2 Fig. 6,
    §2.2.1, §2.2.2): a target is near at or behind the front, or within its braking distance at the planning
    deceleration plus the margin (the limit only while the train is faster than it); the deceleration a target
    needs is ``(v^2 - u^2) / (2 d)``, infinite at ``d <= 0``."""
    _, limit, ma = _targets(o, p, i)
    zero, v2 = o.const(0), i.speed_mps * i.speed_mps
    d_limit, d_ma = i.next_limit_m - i.front_m, i.ma_end_m - i.front_m
    limit_near = o.or_(d_limit <= zero, o.and_(i.speed_mps > limit, _braking_distance_holds(o, p, i, d_limit, limit)))
    ma_near = o.or_(d_ma <= zero, _braking_distance_holds(o, p, i, d_ma, ma))
    ma_steeper = o.or_(d_ma <= zero, o.and_(d_limit > zero, (v2 - ma * ma) * d_limit >= (v2 - limit * limit) * d_ma))
    return limit_near, ma_near, ma_steeper


def _chosen(o, out, speed_mps, location_m, reason):
    return o.and_(
        o.eq(out.target_speed_mps, speed_mps), o.eq(out.target_location_m, location_m), o.eq(out.target_reason, reason)
    )


def _far_mode(o, p, s, i, out, nxt):
    cap, _, _ = _targets(o, p, i)
    limit_near, ma_near, _ = _modes(o, p, i)
    return o.implies(o.not_(o.or_(limit_near, ma_near)), _chosen(o, out, cap, i.front_m, o.const(FAR)))


def _ma_mode(o, p, s, i, out, nxt):
    _, _, ma = _targets(o, p, i)
    limit_near, ma_near, ma_steeper = _modes(o, p, i)
    ma_wins = o.and_(ma_near, o.or_(o.not_(limit_near), ma_steeper))
    return o.implies(ma_wins, _chosen(o, out, ma, i.ma_end_m, o.const(MA_END)))


def _limit_mode(o, p, s, i, out, nxt):
    _, limit, _ = _targets(o, p, i)
    limit_near, ma_near, ma_steeper = _modes(o, p, i)
    limit_wins = o.and_(limit_near, o.not_(o.and_(ma_near, ma_steeper)))
    return o.implies(limit_wins, _chosen(o, out, limit, i.next_limit_m, o.const(SPEED_LIMIT)))


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
    _property(
        "ato.far_mode",
        "ATO-05",
        "Neither the MA nor a lower limit near (neither at or behind the front nor within its braking distance, "
        "the limit only while the train is faster than it), the ATO drives towards the smaller of the limit in "
        "force and the train's maximum, at the front (seed 003 §2.1 and §2.2, first bullets).",
        _far_mode,
    ),
    _property(
        "ato.ma_mode",
        "ATO-06",
        "The MA near, and no lower limit near or the MA needing at least its deceleration (a tie included), the ATO "
        "drives towards the MA: the smallest of the MA speed and both limits, at the MA's end (§2.1.2 Fig. 6, "
        "§2.2.2).",
        _ma_mode,
    ),
    _property(
        "ato.limit_mode",
        "ATO-07",
        "A lower limit near, and the MA not near or needing less deceleration than the limit, the ATO drives "
        "towards that limit (at most the limit in force and the train's maximum), where it starts (§2.1.1, §2.1.2 "
        "Fig. 6, §2.2.1).",
        _limit_mode,
    ),
)
