"""Onboard resource management and the movement authority (seed 001 §3.2-3.3, Fig. 6 and 8; seed 000 §2.2;
seed 002 §4.2).

Each cycle, from the train's position interval, the resources it holds (the
protocol of :mod:`atcs.model.resources`), the object controller's switch reports,
the preceding train's T2T reports, any protection zone and the line data:

- ``dRequestResource = min(end of line, max safe front + MAX_MA)``: the resources
  overlapping ``[max safe front, dRequestResource)`` that are not held are requested;
- a held resource is released once it lies wholly behind the min safe rear, that rear confirmed (the
  position confirmed, :mod:`atcs.model.position`: one set again from one tag read may be wrong; the train's
  integrity confirmed: wagons left behind hold the track);
- a held switch not reported locked in the route's direction is commanded to it;
- ``dLockedResource``: the start of the first resource ahead of the max safe front that
  is not held, or is a switch not yet reported locked in the route's direction (seed
  001: the MA extends over a switch only once it has been turned); the route's end if
  none;
- the preceding train's T2T reports, defended as EN 50159 asks of a message over an
  open channel. A report is *usable* only if its safety code checks (corruption; the
  code covers the sender's identity, so a report from another train fails it:
  masquerade, insertion). A usable report (its min safe rear and min speed when
  sent, after any delay) bounds the leader's present from below, since it never
  moves backward and never brakes harder than ``leader_max_deceleration_mps2`` (a
  train can stop faster than its guaranteed braking, so the follower must assume
  its *highest* deceleration): the train keeps the largest rear and the largest
  earliest stopping point ``rear + v^2 / (2 * leader_max_deceleration_mps2)``
  reported (never lowered, so an old, repeated or overtaken report does no harm to
  them: an old bound stays true);
- a usable report is *accepted* as a sign the link is alive only if its sequence
  number is above the last one accepted (repetition, resequencing) and its time
  stamp not ahead of the onboard clock by more than the largest clock skew; the
  train keeps the last number and the latest time stamp accepted. The leader's
  limit is the stopping point less the safety margin; in brick-wall mode (absolute
  braking distance), or once the freshest report accepted was sent longer than
  ``report_timeout_s`` ago (by its time stamp, plus the clock skew: time-out; the
  link is presumed lost, and the leader may have stopped dead), the rear less the
  margin. A late report restores no credit, a replayed one none either;
- the end of authority (dMA) is the least of ``dLockedResource``, the leader's limit,
  the start of an active protection zone (set by the ATS), the end of line and the max
  safe front + MAX_MA; the target speed there (vMA) is 0. While the ATS's status is not fresh the zone starts
  at the max safe front (:mod:`atcs.model.ats_status`): the train stops.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Generic

from atcs.model.ats_status import message_accepted, message_age_s
from atcs.model.curves import FAR_M, MIN_SPAN
from atcs.model.node import Node, Stateless, stateless_node
from atcs.model.ops import B, N, Ops

PROOF_ROUTE_RESOURCES = 8
"""The route capacity the proofs cover (every resource's extent, kind and direction symbolic)."""


@dataclass(frozen=True)
class AuthorityParams(Generic[N, B]):
    resource_start_m: tuple[N, ...]
    resource_end_m: tuple[N, ...]
    resource_is_switch: tuple[B, ...]
    switch_needs_reverse: tuple[B, ...]
    """For a switch: the route needs it reversed (else normal)."""
    line_end_m: N
    max_ma_m: N
    """MAX_MA: how far ahead of the max safe front an MA may reach (seed 002: 1.5 km)."""
    leader_max_deceleration_mps2: N
    """The preceding train's *highest* possible deceleration (emergency brake and the steepest uphill): the
    relative-braking assumption."""
    safety_margin_m: N
    """Kept between the end of authority and the leader's stopping point (seed 001 Fig. 6)."""
    report_timeout_s: N
    """The oldest the freshest report may be for the leader's stopping point to count (by its time stamp)."""
    clock_skew_max_s: N
    """The largest difference between the leader's clock and this train's (both synchronised to one source)."""
    brick_wall: B
    """Absolute braking distance: the leader's reported rear is the target, with no credit for its speed."""


@dataclass(frozen=True)
class AuthorityState(Generic[N, B]):
    leader_known: B
    """A report from the preceding train has arrived."""
    best_rear_m: N
    """The largest min safe rear reported."""
    best_stop_m: N
    """The largest earliest stopping point reported."""
    last_seq: N
    """The sequence number of the last report accepted."""
    freshest_sent_s: N
    """The latest time stamp of a report accepted (the leader's clock)."""


@dataclass(frozen=True)
class AuthorityInputs(Generic[N, B]):
    front_max_m: N
    rear_min_m: N
    rear_confirmed: B
    """The min safe rear is confirmed: the position confirmed (:mod:`atcs.model.position`) and the train's integrity
    confirmed (no wagon left behind). Only then are resources released behind it."""
    held: tuple[B, ...]
    switch_locked: tuple[B, ...]
    """The object controller reports the switch locked in a position."""
    switch_reversed: tuple[B, ...]
    """That position is reverse (else normal)."""
    now_s: N
    """The onboard clock."""
    report_delivered: B
    """A T2T report arrives this cycle."""
    report_intact: B
    """Its safety code checks for the preceding train's identity (:mod:`atcs.model.t2t_message`)."""
    report_seq: N
    """Its sequence number."""
    report_sent_s: N
    """Its time stamp: when it was sent, by the leader's clock."""
    report_rear_m: N
    """Its min safe rear when it was sent."""
    report_speed_mps: N
    """Its min speed (estimate less accuracy) when it was sent."""
    zone_active: B
    zone_start_m: N
    """A protection zone set by the ATS (seed 000 §2.5, 002 §4.2), as the ATS's status gives it
    (:mod:`atcs.model.ats_status`: from the max safe front on while the status is stale)."""


@dataclass(frozen=True)
class AuthorityOutputs(Generic[N, B]):
    request: tuple[B, ...]
    release: tuple[B, ...]
    switch_command: tuple[B, ...]
    """Command the switch to the route's direction."""
    d_request_m: N
    d_locked_m: N
    report_accepted: B
    """This cycle's report passed every check and updated the bounds."""
    report_age_s: N
    """How long ago, at most, the freshest report accepted was sent (its time stamp and the clock skew)."""
    leader_limit_m: N
    """The end of authority the preceding train allows."""
    eoa_m: N
    """dMA. vMA, the target speed there, is always 0: each limit is a point to stop at."""


def confirmed(o: Ops, p: AuthorityParams, i: AuthorityInputs, r: int):
    """Resource ``r`` is not a switch, or is reported locked in the route's direction."""
    in_direction = o.eq(i.switch_reversed[r], p.switch_needs_reverse[r])
    return o.or_(o.not_(p.resource_is_switch[r]), o.and_(i.switch_locked[r], in_direction))


def locked_end_m(o: Ops, p: AuthorityParams, i: AuthorityInputs):
    """``dLockedResource``: the start of the first resource ahead that is not held or not confirmed."""
    locked = p.resource_end_m[-1]
    for r in reversed(range(len(p.resource_end_m))):
        blocked = o.or_(o.not_(i.held[r]), o.not_(confirmed(o, p, i, r)))
        locked = o.ite(o.and_(blocked, p.resource_end_m[r] > i.front_max_m), p.resource_start_m[r], locked)
    return locked


def stopping_point_m(o: Ops, p: AuthorityParams, rear_m, speed_mps):
    """Where a leader at ``rear_m`` and ``speed_mps`` stops at the earliest (its highest deceleration)."""
    deceleration = o.max(p.leader_max_deceleration_mps2, o.const(MIN_SPAN))  # a guard valid data never meets
    return rear_m + speed_mps * speed_mps / (o.const(2) * deceleration)


def report_usable(o: Ops, i: AuthorityInputs):
    """This cycle's report is delivered and its safety code checks: what it says of the leader is true."""
    return o.and_(i.report_delivered, i.report_intact)


def report_accepted(o: Ops, p: AuthorityParams, s: AuthorityState, i: AuthorityInputs):
    """This cycle's report is usable, numbered after the last one accepted and stamped no later than the onboard
    clock plus the skew: a sign the link is alive (module docstring)."""
    return message_accepted(
        o,
        s.leader_known,
        s.last_seq,
        i.report_delivered,
        i.report_intact,
        i.report_seq,
        i.report_sent_s,
        i.now_s,
        p.clock_skew_max_s,
    )


def leader_reports(o: Ops, p: AuthorityParams, s: AuthorityState, i: AuthorityInputs) -> AuthorityState:
    """The bounds kept after this cycle's report (module docstring): a usable report's rear and stopping point
    are merged in whatever its number and time stamp (an old bound stays true), an accepted one's number and time
    stamp kept."""
    usable, accepted = report_usable(o, i), report_accepted(o, p, s, i)
    first = o.and_(o.not_(s.leader_known), usable)
    rear = o.ite(first, i.report_rear_m, o.max(s.best_rear_m, i.report_rear_m))
    stop = stopping_point_m(o, p, i.report_rear_m, i.report_speed_mps)
    sent = o.ite(first, i.report_sent_s, o.max(s.freshest_sent_s, i.report_sent_s))
    return AuthorityState(
        leader_known=o.or_(s.leader_known, usable),
        best_rear_m=o.ite(usable, rear, s.best_rear_m),
        best_stop_m=o.ite(usable, o.ite(first, stop, o.max(s.best_stop_m, stop)), s.best_stop_m),
        last_seq=o.ite(accepted, i.report_seq, s.last_seq),
        freshest_sent_s=o.ite(accepted, sent, s.freshest_sent_s),
    )


def report_age_s(o: Ops, p: AuthorityParams, r: AuthorityState, now_s):
    """The longest time since the freshest report accepted was sent: the clocks may differ by the skew."""
    return message_age_s(now_s, r.freshest_sent_s, p.clock_skew_max_s)


def leader_limit_m(o: Ops, p: AuthorityParams, r: AuthorityState, now_s):
    """The end of authority the preceding train allows (FAR_M with no report yet)."""
    certain_only = o.or_(p.brick_wall, report_age_s(o, p, r, now_s) > p.report_timeout_s)
    limit = o.ite(certain_only, r.best_rear_m, r.best_stop_m) - p.safety_margin_m
    return o.ite(r.leader_known, limit, o.const(FAR_M))


def authority_init(o: Ops, p: AuthorityParams, s: AuthorityState):
    """No report from a preceding train yet."""
    zero = o.const(0)
    return o.and_(
        o.not_(s.leader_known),
        o.eq(s.best_rear_m, zero),
        o.eq(s.best_stop_m, zero),
        o.eq(s.last_seq, zero),
        o.eq(s.freshest_sent_s, zero),
    )


def authority_step(o: Ops, p: AuthorityParams, s: AuthorityState, i: AuthorityInputs):
    """One cycle of resource management and MA computation (module docstring)."""
    d_request = o.min(p.line_end_m, i.front_max_m + p.max_ma_m)
    resources = range(len(p.resource_end_m))
    request = tuple(
        o.and_(o.not_(i.held[r]), p.resource_end_m[r] > i.front_max_m, p.resource_start_m[r] < d_request)
        for r in resources
    )
    release = tuple(o.and_(i.rear_confirmed, i.held[r], p.resource_end_m[r] <= i.rear_min_m) for r in resources)
    switch_command = tuple(o.and_(i.held[r], o.not_(confirmed(o, p, i, r))) for r in resources)
    d_locked = locked_end_m(o, p, i)
    reports = leader_reports(o, p, s, i)
    leader = leader_limit_m(o, p, reports, i.now_s)
    zone = o.ite(i.zone_active, i.zone_start_m, o.const(FAR_M))
    eoa = o.min(d_locked, leader, zone, p.line_end_m, i.front_max_m + p.max_ma_m)
    accepted = report_accepted(o, p, s, i)
    age = report_age_s(o, p, reports, i.now_s)
    return reports, AuthorityOutputs(request, release, switch_command, d_request, d_locked, accepted, age, leader, eoa)


AUTHORITY = Node(
    name="authority",
    params=AuthorityParams,
    state=AuthorityState,
    inputs=AuthorityInputs,
    outputs=AuthorityOutputs,
    init=authority_init,
    step=authority_step,
    seed="001 §3.2-3.3 (Fig. 6, 8), 000 §2.2, 002 §4.2; EN 50159 defences",
    sizes={
        name: PROOF_ROUTE_RESOURCES
        for name in (
            "resource_start_m",
            "resource_end_m",
            "resource_is_switch",
            "switch_needs_reverse",
            "held",
            "switch_locked",
            "switch_reversed",
            "request",
            "release",
            "switch_command",
        )
    },
)


# --- the leader's stopping point as a sub-function node -------------------------------------------------------


@dataclass(frozen=True)
class StoppingPointParams(Generic[N, B]):
    leader_max_deceleration_mps2: N
    """The leader's highest deceleration (its emergency brake on a dry rail)."""


@dataclass(frozen=True)
class StoppingPointQuery(Generic[N, B]):
    rear_m: N
    """The leader's reported rear."""
    speed_mps: N
    """The leader's reported speed."""


@dataclass(frozen=True)
class StoppingPointOutputs(Generic[N, B]):
    stop_m: N
    """Where the leader's rear stops at the earliest."""


def stopping_point_step(o: Ops, p: StoppingPointParams, s: Stateless, i: StoppingPointQuery):
    return s, StoppingPointOutputs(stopping_point_m(o, p, i.rear_m, i.speed_mps))


STOPPING_POINT = stateless_node(
    name="stopping_point",
    params=StoppingPointParams,
    inputs=StoppingPointQuery,
    outputs=StoppingPointOutputs,
    step=stopping_point_step,
    seed="000 §2.2, 002 §4.2",
)
""":func:`stopping_point_m` (the relative-braking bound of a leader's report) as a sub-function of its own."""
