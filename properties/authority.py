"""Properties of the movement authority and onboard resource management (seed 001 §3.2-3.3, Fig. 6 and 8;
seed 000 §2.2; seed 002 §4.2).

Over :data:`~atcs.model.authority.AUTHORITY` for a route of 4 resources whose extents,
kinds and needed directions are symbolic, any position interval, holdings, switch
reports, T2T report and protection zone. Each claim is stated resource by resource
from the route data, not through the node's own fold.
"""

from __future__ import annotations

from atcs.model.authority import AUTHORITY
from atcs.model.curves import MIN_SPAN
from atcs.properties.property import Assumption, Property

LEADER_DATA = Assumption(
    "leader_data",
    f"the leader's highest deceleration is at least {MIN_SPAN} m/s^2 and the safety margin is >= 0",
    lambda o, p, s, i: o.and_(p.leader_max_deceleration_mps2 >= o.const(MIN_SPAN), p.safety_margin_m >= o.const(0)),
)


def _route(o, p, s, i):
    starts, ends = p.resource_start_m, p.resource_end_m
    return o.and_(
        *(starts[r] < ends[r] for r in range(len(ends))), *(o.eq(starts[r + 1], ends[r]) for r in range(len(ends) - 1))
    )


ROUTE = Assumption(
    "route",
    "the route's resources are contiguous, each of positive length, in the order the train runs over them",
    _route,
)


def route_resources(p):
    """The indices of the route's resources."""
    return range(len(p.resource_end_m))


def resource_ahead(p, i, r):
    """Resource ``r`` reaches past the max safe front."""
    return p.resource_end_m[r] > i.front_max_m


def _within_held(o, p, s, i, out, nxt):
    return o.and_(
        *(
            o.implies(o.and_(o.not_(i.held[r]), resource_ahead(p, i, r)), out.eoa_m <= p.resource_start_m[r])
            for r in route_resources(p)
        )
    )


def _before_unconfirmed_switch(o, p, s, i, out, nxt):
    def unconfirmed(r):
        locked_right = o.and_(i.switch_locked[r], o.eq(i.switch_reversed[r], p.switch_needs_reverse[r]))
        return o.and_(p.resource_is_switch[r], o.not_(locked_right))

    return o.and_(
        *(
            o.implies(o.and_(unconfirmed(r), resource_ahead(p, i, r)), out.eoa_m <= p.resource_start_m[r])
            for r in route_resources(p)
        )
    )


def _behind_leader(o, p, s, i, out, nxt):
    stale = nxt.since_report_s > p.report_timeout_s
    margin = p.safety_margin_m
    return o.implies(
        nxt.leader_known,
        o.and_(
            out.eoa_m + margin <= nxt.best_stop_m,
            o.implies(o.or_(p.brick_wall, stale), out.eoa_m + margin <= nxt.best_rear_m),
        ),
    )


def _bounds_from_reports(o, p, s, i, out, nxt):
    """Each bound kept is the previous one or the one this cycle's report gives, never more."""
    d, v = p.leader_max_deceleration_mps2, i.report_speed_mps
    kept = s.leader_known
    return o.implies(
        nxt.leader_known,
        o.and_(
            o.or_(
                o.and_(kept, nxt.best_rear_m <= s.best_rear_m),
                o.and_(i.report_delivered, nxt.best_rear_m <= i.report_rear_m),
            ),
            o.or_(
                o.and_(kept, nxt.best_stop_m <= s.best_stop_m),
                o.and_(i.report_delivered, o.const(2) * d * (nxt.best_stop_m - i.report_rear_m) <= v * v),
            ),
        ),
    )


def _blocked_ahead(o, p, i, r):
    """Resource ``r`` lies ahead and is not held, or is a switch not reported locked in the route's direction."""
    locked_right = o.and_(i.switch_locked[r], o.eq(i.switch_reversed[r], p.switch_needs_reverse[r]))
    clear = o.and_(i.held[r], o.or_(o.not_(p.resource_is_switch[r]), locked_right))
    return o.and_(o.not_(clear), resource_ahead(p, i, r))


def _locked_end(o, p, s, i, out, nxt):
    """dLockedResource resource by resource: the start of the first blocked resource ahead, else the route's end."""
    blocked = [_blocked_ahead(o, p, i, r) for r in route_resources(p)]
    return o.and_(
        *(
            o.implies(
                o.and_(blocked[r], *(o.not_(b) for b in blocked[:r])), o.eq(out.d_locked_m, p.resource_start_m[r])
            )
            for r in route_resources(p)
        ),
        o.implies(o.and_(*(o.not_(b) for b in blocked)), o.eq(out.d_locked_m, p.resource_end_m[-1])),
    )


def _bounds_never_lowered(o, p, s, i, out, nxt):
    d, v = p.leader_max_deceleration_mps2, i.report_speed_mps
    return o.and_(
        o.implies(
            s.leader_known, o.and_(nxt.leader_known, s.best_rear_m <= nxt.best_rear_m, s.best_stop_m <= nxt.best_stop_m)
        ),
        o.implies(
            i.report_delivered,
            o.and_(
                nxt.leader_known,
                i.report_rear_m <= nxt.best_rear_m,
                v * v <= o.const(2) * d * (nxt.best_stop_m - i.report_rear_m),
            ),
        ),
    )


def _report_age(o, p, s, i, out, nxt):
    return o.and_(
        o.implies(i.report_delivered, o.eq(nxt.since_report_s, o.const(0))),
        o.implies(o.not_(i.report_delivered), o.eq(nxt.since_report_s, s.since_report_s + p.cycle_s)),
    )


def _credit_while_fresh(o, p, s, i, out, nxt):
    fresh = o.and_(nxt.leader_known, o.not_(p.brick_wall), nxt.since_report_s <= p.report_timeout_s)
    return o.implies(fresh, o.eq(out.leader_limit_m, nxt.best_stop_m - p.safety_margin_m))


def _property(name, requirement, seed, text, holds, assumptions=(), lemmas=()):
    return Property(
        name=name,
        requirement=requirement,
        seed=seed,
        text=text,
        node=AUTHORITY,
        holds=holds,
        assumptions=assumptions,
        lemmas=lemmas,
    )


PROPERTIES = (
    _property(
        "authority.within_held_resources",
        "AUT-01",
        "001 §3.2 (Fig. 6)",
        "The end of authority never lies past the start of a resource ahead that the train does not hold.",
        _within_held,
        (ROUTE,),
    ),
    _property(
        "authority.before_unconfirmed_switch",
        "AUT-02",
        "001 §3.2",
        "The end of authority never lies past the start of a switch ahead that the object controller has not "
        "reported locked in the route's direction.",
        _before_unconfirmed_switch,
        (ROUTE,),
    ),
    _property(
        "authority.before_protection_zone",
        "AUT-03",
        "000 §2.5, 002 §4.2",
        "The end of authority never lies past the start of an active protection zone.",
        lambda o, p, s, i, out, nxt: o.implies(i.zone_active, out.eoa_m <= i.zone_start_m),
    ),
    _property(
        "authority.within_line_and_max_ma",
        "AUT-04",
        "001 §3.2, 002 §4.2",
        "The end of authority never lies past the end of line, nor more than MAX_MA ahead of the max safe front.",
        lambda o, p, s, i, out, nxt: o.and_(out.eoa_m <= p.line_end_m, out.eoa_m <= i.front_max_m + p.max_ma_m),
    ),
    _property(
        "authority.behind_leader",
        "AUT-05",
        "001 §3.2 (Fig. 6), 000 §2.2",
        "Once the preceding train has reported, the end of authority plus the safety margin is behind the "
        "largest earliest stopping point reported, and behind the largest rear reported in brick-wall mode "
        "or once no report has arrived for the timeout.",
        _behind_leader,
        (LEADER_DATA,),
        ("authority.rear_bound_behind_stop_bound",),
    ),
    _property(
        "authority.rear_bound_behind_stop_bound",
        "AUT-07",
        "001 §3.2",
        "The largest rear reported is never ahead of the largest earliest stopping point reported.",
        lambda o, p, s, i, out, nxt: s.best_rear_m <= s.best_stop_m,
        (LEADER_DATA,),
    ),
    _property(
        "authority.leader_bounds_from_reports",
        "AUT-06",
        "001 §3.2 (Fig. 6)",
        "The leader's rear and earliest stopping point the train keeps are never more than a report gives: "
        "the rear reported, and that rear plus the stopping distance from the speed reported at the "
        "leader's highest deceleration.",
        _bounds_from_reports,
        (LEADER_DATA,),
    ),
    # not over-restrictive, and the bookkeeping the limits rest on (each kills survivors of atcs mutate)
    _property(
        "authority.locked_end_is_first_blocked",
        "AUT-08",
        "001 §3.2",
        "dLockedResource is the start of the first resource ahead that is not held or is a switch not locked "
        "in the route's direction, and the route's end if there is none.",
        _locked_end,
    ),
    _property(
        "authority.leader_bounds_never_lowered",
        "AUT-09",
        "001 §3.2 (Fig. 6)",
        "Once a report has arrived the leader stays known and its kept rear and earliest stopping point are "
        "never lowered; each is at least what this cycle's report gives.",
        _bounds_never_lowered,
        (LEADER_DATA,),
    ),
    _property(
        "authority.report_age",
        "AUT-10",
        "001 §3.2",
        "The time since the last report is 0 in a cycle a report arrives and one cycle more in any other.",
        _report_age,
    ),
    _property(
        "authority.stop_credit_while_fresh",
        "AUT-11",
        "001 §3.2 (Fig. 6), 000 §2.2",
        "In relative braking, while the last report is no older than the timeout, the leader's limit is its "
        "largest earliest stopping point less the safety margin.",
        _credit_while_fresh,
    ),
)

__all__ = ["LEADER_DATA", "PROPERTIES", "ROUTE", "resource_ahead", "route_resources"]
