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


def _age_s(o, p, r, i):
    """How long ago, at most, the freshest report kept in ``r`` was sent: by the onboard clock, its time stamp and
    the clock skew."""
    return i.now_s - r.freshest_sent_s + p.clock_skew_max_s


def _behind_leader(o, p, s, i, out, nxt):
    stale = _age_s(o, p, nxt, i) > p.report_timeout_s
    margin = p.safety_margin_m
    return o.implies(
        nxt.leader_known,
        o.and_(
            out.eoa_m + margin <= nxt.best_stop_m,
            o.implies(o.or_(p.brick_wall, stale), out.eoa_m + margin <= nxt.best_rear_m),
        ),
    )


def _usable(o, i):
    """A report arrives and its safety code checks."""
    return o.and_(i.report_delivered, i.report_intact)


def _acceptable(o, p, s, i):
    """A report arrives intact, numbered after the last one accepted (any number for the first) and stamped no
    later than the onboard clock plus the skew."""
    return o.and_(
        _usable(o, i),
        o.or_(o.not_(s.leader_known), i.report_seq > s.last_seq),
        i.report_sent_s <= i.now_s + p.clock_skew_max_s,
    )


def _bounds_from_reports(o, p, s, i, out, nxt):
    """Each bound kept is the previous one or the one this cycle's intact report gives, never more."""
    d, v = p.leader_max_deceleration_mps2, i.report_speed_mps
    kept, arrived = s.leader_known, _usable(o, i)
    return o.implies(
        nxt.leader_known,
        o.and_(
            o.or_(
                o.and_(kept, nxt.best_rear_m <= s.best_rear_m),
                o.and_(arrived, nxt.best_rear_m <= i.report_rear_m),
            ),
            o.or_(
                o.and_(kept, nxt.best_stop_m <= s.best_stop_m),
                o.and_(arrived, o.const(2) * d * (nxt.best_stop_m - i.report_rear_m) <= v * v),
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
    claims, none_before = [], o.const_bool(True)  # none of the resources before r blocked
    for r in route_resources(p):
        blocked = _blocked_ahead(o, p, i, r)
        claims.append(o.implies(o.and_(blocked, none_before), o.eq(out.d_locked_m, p.resource_start_m[r])))
        none_before = o.and_(none_before, o.not_(blocked))
    return o.and_(*claims, o.implies(none_before, o.eq(out.d_locked_m, p.resource_end_m[-1])))


def _bounds_never_lowered(o, p, s, i, out, nxt):
    d, v = p.leader_max_deceleration_mps2, i.report_speed_mps
    return o.and_(
        o.implies(
            s.leader_known, o.and_(nxt.leader_known, s.best_rear_m <= nxt.best_rear_m, s.best_stop_m <= nxt.best_stop_m)
        ),
        o.implies(
            _usable(o, i),
            o.and_(
                nxt.leader_known,
                i.report_rear_m <= nxt.best_rear_m,
                v * v <= o.const(2) * d * (nxt.best_stop_m - i.report_rear_m),
            ),
        ),
    )


def _freshest_report(o, p, s, i, out, nxt):
    acceptable = _acceptable(o, p, s, i)
    return o.and_(
        o.implies(
            acceptable,
            o.and_(
                o.eq(nxt.last_seq, i.report_seq),
                i.report_sent_s <= nxt.freshest_sent_s,
                o.implies(s.leader_known, s.freshest_sent_s <= nxt.freshest_sent_s),
                o.or_(o.eq(nxt.freshest_sent_s, i.report_sent_s), o.eq(nxt.freshest_sent_s, s.freshest_sent_s)),
            ),
        ),
        o.eq(out.report_accepted, acceptable),
        o.eq(out.report_age_s, _age_s(o, p, nxt, i)),
    )


def _credit_while_fresh(o, p, s, i, out, nxt):
    fresh = o.and_(nxt.leader_known, o.not_(p.brick_wall), _age_s(o, p, nxt, i) <= p.report_timeout_s)
    return o.implies(fresh, o.eq(out.leader_limit_m, nxt.best_stop_m - p.safety_margin_m))


def _nothing_kept_changes(o, s, nxt):
    return o.and_(
        o.eq(nxt.leader_known, s.leader_known),
        o.eq(nxt.best_rear_m, s.best_rear_m),
        o.eq(nxt.best_stop_m, s.best_stop_m),
        o.eq(nxt.last_seq, s.last_seq),
        o.eq(nxt.freshest_sent_s, s.freshest_sent_s),
    )


def _ignored_when(condition):
    """The report is dropped whenever ``condition(o, p, s, i)`` holds: nothing the train keeps changes."""
    return lambda o, p, s, i, out, nxt: o.implies(condition(o, p, s, i), _nothing_kept_changes(o, s, nxt))


def _not_fresh_when(condition):
    """The report is no sign of life whenever ``condition(o, p, s, i)`` holds: the last number and the time stamp
    kept do not change (its bounds may be merged: never lowered, AUT-09)."""
    return lambda o, p, s, i, out, nxt: o.implies(
        condition(o, p, s, i),
        o.and_(o.eq(nxt.last_seq, s.last_seq), o.eq(nxt.freshest_sent_s, s.freshest_sent_s)),
    )


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
        "or once the freshest report accepted is older than the timeout (by its time stamp, the onboard clock "
        "and the clock skew), however late it arrived.",
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
        "The leader's rear and earliest stopping point the train keeps are never more than a usable report gives: "
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
        "Once a report has been usable (delivered, its safety code checked) the leader stays known and its kept "
        "rear and earliest stopping point are never lowered; each is at least what this cycle's usable report "
        "gives, however old, repeated or out of order.",
        _bounds_never_lowered,
        (LEADER_DATA,),
    ),
    _property(
        "authority.freshest_report_kept",
        "AUT-10",
        "001 §3.2; EN 50159 (sequence number, time stamp)",
        "An acceptable report (intact, numbered after the last one accepted, stamped no later than the onboard "
        "clock plus the skew) is accepted: its number is kept as the last one, and the time stamp kept is its own "
        "or the one kept before, never earlier than either; the age reported is the onboard clock less that time "
        "stamp plus the skew.",
        _freshest_report,
    ),
    _property(
        "authority.stop_credit_while_fresh",
        "AUT-11",
        "001 §3.2 (Fig. 6), 000 §2.2",
        "In relative braking, while the freshest report accepted is no older than the timeout (by its time stamp, "
        "the onboard clock and the skew), the leader's limit is its largest earliest stopping point less the "
        "safety margin.",
        _credit_while_fresh,
    ),
    _property(
        "authority.corrupted_report_ignored",
        "AUT-14",
        "EN 50159 (safety code, source identifier)",
        "A report whose safety code fails (corrupted, or sent by a train other than the leader: the code covers "
        "the sender's identity) changes nothing the train keeps, whatever it says.",
        _ignored_when(lambda o, p, s, i: o.not_(i.report_intact)),
    ),
    _property(
        "authority.replayed_report_not_fresh",
        "AUT-15",
        "EN 50159 (sequence number)",
        "Once the leader is known, a report numbered at most the last one accepted (replayed, repeated or "
        "overtaken by a newer one) renews nothing: the last number and the time stamp kept stay as they were, so "
        "it cannot hold off the time-out.",
        _not_fresh_when(lambda o, p, s, i: o.and_(s.leader_known, i.report_seq <= s.last_seq)),
    ),
    _property(
        "authority.future_report_not_fresh",
        "AUT-16",
        "EN 50159 (time stamp)",
        "A report stamped later than the onboard clock plus the clock skew renews nothing: the last number and "
        "the time stamp kept stay as they were.",
        _not_fresh_when(lambda o, p, s, i: i.report_sent_s > i.now_s + p.clock_skew_max_s),
    ),
)

__all__ = ["LEADER_DATA", "PROPERTIES", "ROUTE", "resource_ahead", "route_resources"]
