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
    lambda o, p, s, i: o.and_(p.leader_max_deceleration_mps2 >= o.const(MIN_SPAN),
                              p.safety_margin_m >= o.const(0)),
)


def _route(o, p, s, i):
    starts, ends = p.resource_start_m, p.resource_end_m
    return o.and_(*(starts[r] < ends[r] for r in range(len(ends))),
                  *(o.eq(starts[r + 1], ends[r]) for r in range(len(ends) - 1)))


ROUTE = Assumption(
    "route",
    "the route's resources are contiguous, each of positive length, in the order the train runs over them",
    _route,
)


def _resources(p):
    return range(len(p.resource_end_m))


def _ahead(p, i, r):
    return p.resource_end_m[r] > i.front_max_m


def _within_held(o, p, s, i, out, nxt):
    return o.and_(*(o.implies(o.and_(o.not_(i.held[r]), _ahead(p, i, r)), out.eoa_m <= p.resource_start_m[r])
                    for r in _resources(p)))


def _before_unconfirmed_switch(o, p, s, i, out, nxt):
    def unconfirmed(r):
        locked_right = o.and_(i.switch_locked[r], o.eq(i.switch_reversed[r], p.switch_needs_reverse[r]))
        return o.and_(p.resource_is_switch[r], o.not_(locked_right))

    return o.and_(*(o.implies(o.and_(unconfirmed(r), _ahead(p, i, r)), out.eoa_m <= p.resource_start_m[r])
                    for r in _resources(p)))


def _behind_leader(o, p, s, i, out, nxt):
    d, v, margin = p.leader_max_deceleration_mps2, i.leader_speed_mps, p.safety_margin_m
    certain_only = o.or_(p.brick_wall, i.report_age_s > p.report_timeout_s)
    return o.and_(
        # relative braking: 2 D (eoa + margin - rear) <= v^2, i.e. behind the leader's earliest stopping point
        o.implies(i.leader_known, o.const(2) * d * (out.eoa_m + margin - i.leader_rear_m) <= v * v),
        o.implies(o.and_(i.leader_known, certain_only), out.eoa_m + margin <= i.leader_rear_m),
    )


def _release_behind_rear(o, p, s, i, out, nxt):
    return o.and_(*(o.implies(out.release[r], o.and_(i.held[r], p.resource_end_m[r] <= i.rear_min_m))
                    for r in _resources(p)))


def _request_ahead(o, p, s, i, out, nxt):
    horizon = i.front_max_m + p.max_ma_m
    return o.and_(*(o.implies(out.request[r], o.and_(
        o.not_(i.held[r]), _ahead(p, i, r), p.resource_start_m[r] < horizon, p.resource_start_m[r] < p.line_end_m))
        for r in _resources(p)))


def _switch_command(o, p, s, i, out, nxt):
    return o.and_(*(o.implies(out.switch_command[r], o.and_(i.held[r], p.resource_is_switch[r]))
                    for r in _resources(p)))


def _property(name, requirement, seed, text, holds, assumptions=()):
    return Property(name=name, requirement=requirement, seed=seed, text=text, node=AUTHORITY, holds=holds,
                    assumptions=assumptions)


PROPERTIES = (
    _property("authority.within_held_resources", "AUT-01", "001 §3.2 (Fig. 6)",
              "The end of authority never lies past the start of a resource ahead that the train does not hold.",
              _within_held, (ROUTE,)),
    _property("authority.before_unconfirmed_switch", "AUT-02", "001 §3.2",
              "The end of authority never lies past the start of a switch ahead that the object controller has not "
              "reported locked in the route's direction.", _before_unconfirmed_switch, (ROUTE,)),
    _property("authority.before_protection_zone", "AUT-03", "000 §2.5, 002 §4.2",
              "The end of authority never lies past the start of an active protection zone.",
              lambda o, p, s, i, out, nxt: o.implies(i.zone_active, out.eoa_m <= i.zone_start_m)),
    _property("authority.within_line_and_max_ma", "AUT-04", "001 §3.2, 002 §4.2",
              "The end of authority never lies past the end of line, nor more than MAX_MA ahead of the max safe "
              "front.",
              lambda o, p, s, i, out, nxt: o.and_(out.eoa_m <= p.line_end_m,
                                                  out.eoa_m <= i.front_max_m + p.max_ma_m)),
    _property("authority.behind_leader", "AUT-05", "001 §3.2 (Fig. 6), 000 §2.2",
              "With a report from the preceding train, the end of authority plus the safety margin is behind "
              "the leader's earliest stopping point (its reported min safe rear plus its stopping distance from "
              "its reported min speed at its highest deceleration), and behind its reported rear in brick-wall "
              "mode or once the report is older than the timeout.", _behind_leader, (LEADER_DATA,)),
    _property("resources.release_behind_rear", "RES-03", "001 §3.2 (Fig. 5)",
              "A resource is released only if the train holds it and it lies wholly behind the min safe rear.",
              _release_behind_rear),
    _property("resources.request_ahead", "RES-04", "001 §3.2",
              "A resource is requested only if the train does not hold it, it reaches past the max safe front, and "
              "it starts before dRequestResource (the end of line and MAX_MA ahead).", _request_ahead),
    _property("resources.switch_commanded_only_when_held", "RES-05", "001 §3.2",
              "The train commands a switch only if it holds the switch resource.", _switch_command),
)

__all__ = ["LEADER_DATA", "PROPERTIES", "ROUTE"]
