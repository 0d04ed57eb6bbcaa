"""Two trains in closed loop: the follower's ATP supervising the end of authority its authority node computes
(:mod:`atcs.model.authority`: resources, switches, protection zone, end of line, MAX_MA and the preceding
train's T2T reports), the follower's plant, the leader's motion and the report channel (seed 001 §3.2 Fig. 6,
seed 000 §2.2 and §2.5).

Each report carries the leader's min safe rear and min speed when it was sent and
arrives after any delay, possibly out of order, repeated, or never; a report whose
safety code fails may say anything. The clocks and time stamps are any the
environment chooses: relative braking's separation rests on no timing. The leader's true state
is kept beside it, with a ghost the ATP never reads: ``leader_stop_m``, where the
leader would stop at the earliest from its true state (the target of the proofs in
relative-braking mode).
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Generic

from atcs.model.authority import (
    AuthorityInputs,
    AuthorityParams,
    AuthorityState,
    authority_step,
)
from atcs.model.closed_loop import ClosedLoopInputs, atp_cycle, eoa_target
from atcs.model.curves import DESIGN_CASE_SIZES, MIN_SPAN
from atcs.model.node import Node
from atcs.model.ops import B, N, Ops
from atcs.model.plant import PlantParams, PlantState, plant_admits, plant_init, plant_next
from atcs.model.supervision import SupervisionOutputs, SupervisionState, supervision_init
from atcs.model.t2t_message import sent_report
from atcs.model.train_data import NationalData, TrainData

PROOF_RESOURCES = 2
"""The route capacity the two-train proofs cover."""


def earliest_stop_m(o: Ops, p: TwoTrainParams, rear_m, speed_mps):
    """The physics of the leader: where it stops at the earliest, braking at its highest deceleration. Written
    apart from the ATP's :func:`~atcs.model.authority.stopping_point_m`, so a fault there is not mirrored here."""
    deceleration = o.max(p.leader_max_deceleration_mps2, o.const(MIN_SPAN))  # a guard valid data never meets
    return rear_m + speed_mps * speed_mps / (o.const(2) * deceleration)


def leader_moves(o: Ops, p: TwoTrainParams | ChannelParams, s: TwoTrainState | ChannelState, i):
    """The leader's true state after this cycle's motion (the environment's choice of distance and end speed):
    ``(rear, speed, earliest stopping point)``. One function for :data:`TWO_TRAINS` and :data:`REPORT_CHANNEL`,
    so that the leader whose reports SEP-07 and SEP-08 are about is the one the two-train proofs' REPORT_REAR and
    REPORT_STOP assume them of."""
    rear = s.leader_rear_m + i.leader_distance_m
    return rear, i.leader_next_speed_mps, earliest_stop_m(o, p, rear, i.leader_next_speed_mps)


@dataclass(frozen=True)
class TwoTrainParams(PlantParams[N, B], TrainData[N, B], NationalData[N, B], AuthorityParams[N, B]):
    service_brake_fitted: B
    mrsp_mps: N
    """The follower's MRSP ceiling (one value)."""
    position_error_m: N
    """The follower's odometry bound."""


@dataclass(frozen=True)
class TwoTrainState(PlantState[N, B], SupervisionState[N, B], AuthorityState[N, B]):
    """The follower's plant, supervision and authority state, and the leader's true state:"""

    leader_rear_m: N
    leader_speed_mps: N
    leader_stop_m: N
    """Where the leader would stop at the earliest from its true state (a ghost: the ATP never reads it)."""


@dataclass(frozen=True)
class TwoTrainInputs(ClosedLoopInputs[N, B]):
    """The follower's measurements and plant choice, what its authority node reads, and:"""

    held: tuple[B, ...]
    switch_locked: tuple[B, ...]
    switch_reversed: tuple[B, ...]
    zone_active: B
    zone_start_m: N
    now_s: N
    report_delivered: B
    report_intact: B
    report_seq: N
    report_sent_s: N
    report_rear_m: N
    report_speed_mps: N
    leader_distance_m: N
    """How far the leader moves this cycle (the environment's choice)."""
    leader_next_speed_mps: N


@dataclass(frozen=True)
class TwoTrainOutputs(SupervisionOutputs[N, B]):
    eoa_m: N
    """The follower's end of authority this cycle."""


def follower_authority(o: Ops, p: TwoTrainParams, s: TwoTrainState, i: TwoTrainInputs):
    """The follower's authority node on its measured position: ``(next authority state, its outputs)``."""
    front_max = i.measured_front_m + p.position_error_m
    inputs = AuthorityInputs(
        front_max_m=front_max,
        rear_min_m=i.measured_front_m - p.position_error_m - p.train_length_m,
        rear_confirmed=o.const_bool(True),
        held=i.held,
        switch_locked=i.switch_locked,
        switch_reversed=i.switch_reversed,
        now_s=i.now_s,
        report_delivered=i.report_delivered,
        report_intact=i.report_intact,
        report_seq=i.report_seq,
        report_sent_s=i.report_sent_s,
        report_rear_m=i.report_rear_m,
        report_speed_mps=i.report_speed_mps,
        zone_active=i.zone_active,
        zone_start_m=i.zone_start_m,
    )
    return authority_step(o, p, s, inputs)


def two_train_init(o: Ops, p: TwoTrainParams, s: TwoTrainState):
    """The follower at standstill with EB applied, holding a report of its leader, behind the limit it gives."""
    return o.and_(
        supervision_init(o, p, s),
        plant_init(o, p, s),
        s.leader_speed_mps >= o.const(0),
        o.eq(s.leader_stop_m, earliest_stop_m(o, p, s.leader_rear_m, s.leader_speed_mps)),
        s.leader_known,
        s.best_rear_m <= s.leader_rear_m,
        s.best_stop_m <= s.leader_stop_m,
        s.best_rear_m <= s.best_stop_m,
        s.front_m <= s.best_rear_m - p.safety_margin_m,
        s.front_m < s.leader_rear_m,
    )


def two_train_step(o: Ops, p: TwoTrainParams, s: TwoTrainState, i: TwoTrainInputs):
    reports, ma = follower_authority(o, p, s, i)
    atp, commands, _ = atp_cycle(o, p, s, i, eoa_target(o, ma.eoa_m), p.mrsp_mps)
    follower = plant_next(o, p, s, commands.emergency_brake, i.next_speed_mps, i.distance_m)
    leader_rear, leader_speed, leader_stop = leader_moves(o, p, s, i)
    state = TwoTrainState(
        front_m=follower.front_m,
        speed_mps=follower.speed_mps,
        brake_cycles=follower.brake_cycles,
        eb_latched=atp.eb_latched,
        sb_latched=atp.sb_latched,
        leader_known=reports.leader_known,
        best_rear_m=reports.best_rear_m,
        best_stop_m=reports.best_stop_m,
        last_seq=reports.last_seq,
        freshest_sent_s=reports.freshest_sent_s,
        leader_rear_m=leader_rear,
        leader_speed_mps=leader_speed,
        leader_stop_m=leader_stop,
    )
    return state, TwoTrainOutputs(
        warning=commands.warning,
        service_brake=commands.service_brake,
        emergency_brake=commands.emergency_brake,
        traction_cut=commands.traction_cut,
        eoa_m=ma.eoa_m,
    )


def two_train_admits(o: Ops, p: TwoTrainParams, s: TwoTrainState, i: TwoTrainInputs):
    """The follower's plant bounds for this cycle's motion, under the command its ATP gives."""
    _, commands, _ = atp_cycle(o, p, s, i, eoa_target(o, follower_authority(o, p, s, i)[1].eoa_m), p.mrsp_mps)
    return plant_admits(o, p, s, commands.emergency_brake, i.next_speed_mps, i.distance_m)


TWO_TRAINS = Node(
    name="separation",
    params=TwoTrainParams,
    state=TwoTrainState,
    inputs=TwoTrainInputs,
    outputs=TwoTrainOutputs,
    init=two_train_init,
    step=two_train_step,
    seed="001 §3.2 (Fig. 6), 000 §2.2, §2.5",
    sizes={
        **DESIGN_CASE_SIZES,
        **{
            name: PROOF_RESOURCES
            for name in (
                "resource_start_m",
                "resource_end_m",
                "resource_is_switch",
                "switch_needs_reverse",
                "held",
                "switch_locked",
                "switch_reversed",
            )
        },
    },
)
"""Follower ATP and authority + follower plant + leader + T2T channel, for proofs."""


# --- the leader's reports on their way: what TWO_TRAINS assumes of a delivered report ------------------------------


@dataclass(frozen=True)
class ChannelParams(Generic[N, B]):
    leader_length_m: N
    leader_max_deceleration_mps2: N
    cycle_s: N


@dataclass(frozen=True)
class ChannelState(Generic[N, B]):
    """The leader's true state, as in :class:`TwoTrainState`, and one report on its way: the rear and speed of a
    report the leader sent at an earlier cycle, unchanged since (``on_way`` once there is one)."""

    leader_rear_m: N
    leader_speed_mps: N
    leader_stop_m: N
    on_way: B
    on_way_rear_m: N
    on_way_speed_mps: N


@dataclass(frozen=True)
class ChannelInputs(Generic[N, B]):
    leader_distance_m: N
    leader_next_speed_mps: N
    front_min_m: N
    """The leader's position function this cycle: its min front, speed estimate and the estimate's accuracy."""
    speed_est_mps: N
    speed_accuracy_mps: N
    clock_s: N
    sent_on: B
    """The channel carries this cycle's report on, in place of the one on its way (else the new one is lost)."""


@dataclass(frozen=True)
class ChannelOutputs(Generic[N, B]):
    """The report on its way, as the follower would receive it intact this cycle."""

    delivered: B
    delivered_rear_m: N
    delivered_speed_mps: N


def report_channel_step(o: Ops, p: ChannelParams, s: ChannelState, i: ChannelInputs):
    """The leader sends a report of this cycle's position (:func:`~atcs.model.t2t_message.sent_report`, what its
    onboard unit puts in the bytes) and moves; the channel delivers the report on its way, any number of cycles
    later, again and again, or never. One report on its way stands for each of many: a report delayed, repeated or
    overtaken is one that stayed on its way while others were sent."""
    sent = sent_report(o, p.leader_length_m, i.front_min_m, i.speed_est_mps, i.speed_accuracy_mps, i.clock_s)
    leader_rear, leader_speed, leader_stop = leader_moves(o, p, s, i)
    state = ChannelState(
        leader_rear_m=leader_rear,
        leader_speed_mps=leader_speed,
        leader_stop_m=leader_stop,
        on_way=o.or_(s.on_way, i.sent_on),
        on_way_rear_m=o.ite(i.sent_on, sent.report_rear_m, s.on_way_rear_m),
        on_way_speed_mps=o.ite(i.sent_on, sent.report_speed_mps, s.on_way_speed_mps),
    )
    return state, ChannelOutputs(s.on_way, s.on_way_rear_m, s.on_way_speed_mps)


def report_channel_init(o: Ops, p: ChannelParams, s: ChannelState):
    """No report on its way yet; the leader's earliest stopping point its physics' (as in :func:`two_train_init`)."""
    return o.and_(
        o.not_(s.on_way),
        s.leader_speed_mps >= o.const(0),
        o.eq(s.leader_stop_m, earliest_stop_m(o, p, s.leader_rear_m, s.leader_speed_mps)),
    )


REPORT_CHANNEL = Node(
    name="report_channel",
    params=ChannelParams,
    state=ChannelState,
    inputs=ChannelInputs,
    outputs=ChannelOutputs,
    init=report_channel_init,
    step=report_channel_step,
    seed="001 §3.2 (Fig. 5 iii, Fig. 6); EN 50159",
)
"""The leader, its reports as its onboard unit makes them, and the channel to the follower, every value symbolic:
what :data:`TWO_TRAINS` assumes of an intact report (REPORT_REAR, REPORT_STOP) proved of the reports the leader
sends."""


# --- the two trains with the leader's reports on their way: the product of TWO_TRAINS and REPORT_CHANNEL -----------


@dataclass(frozen=True)
class ReportedParams(TwoTrainParams[N, B]):
    leader_length_m: N


@dataclass(frozen=True)
class ReportedState(TwoTrainState[N, B]):
    """The two trains' state and the leader's report on its way to the follower (as in :class:`ChannelState`)."""

    on_way: B
    on_way_rear_m: N
    on_way_speed_mps: N


@dataclass(frozen=True)
class ReportedInputs(ClosedLoopInputs[N, B]):
    """What :class:`TwoTrainInputs` holds but the report's content, which is the one on its way, and the leader's
    position function and the channel (as :class:`ChannelInputs`)."""

    held: tuple[B, ...]
    switch_locked: tuple[B, ...]
    switch_reversed: tuple[B, ...]
    zone_active: B
    zone_start_m: N
    now_s: N
    report_intact: B
    """The delivered report's safety code holds (else it may say anything, and the follower discards it)."""
    report_seq: N
    report_sent_s: N
    """Any sequence number and time stamp: relative braking rests on no timing."""
    leader_distance_m: N
    leader_next_speed_mps: N
    front_min_m: N
    speed_est_mps: N
    speed_accuracy_mps: N
    clock_s: N
    sent_on: B


def delivered_report(o: Ops, s: ReportedState, i: ReportedInputs) -> TwoTrainInputs:
    """The two-train node's inputs with the report on its way as the one delivered."""
    return TwoTrainInputs(
        **{name: getattr(i, name) for name in TWO_TRAIN_ENVIRONMENT},
        report_delivered=s.on_way,
        report_rear_m=s.on_way_rear_m,
        report_speed_mps=s.on_way_speed_mps,
    )


TWO_TRAIN_ENVIRONMENT = tuple(
    name
    for name in TwoTrainInputs.__dataclass_fields__
    if name not in ("report_delivered", "report_rear_m", "report_speed_mps")
)
"""The fields of :class:`TwoTrainInputs` a :class:`ReportedInputs` holds as they are."""


def reported_init(o: Ops, p: ReportedParams, s: ReportedState):
    """:func:`two_train_init` (the follower holding an earlier report of its leader) and no report on its way."""
    return o.and_(two_train_init(o, p, s), report_channel_init(o, p, s))


def reported_step(o: Ops, p: ReportedParams, s: ReportedState, i: ReportedInputs):
    """:func:`two_train_step` on the report on its way, and :func:`report_channel_step`: the leader's onboard unit
    sends this cycle's report, which the channel may carry on in place of the one on its way."""
    two_trains, out = two_train_step(o, p, s, delivered_report(o, s, i))
    channel, _ = report_channel_step(o, p, s, i)
    return ReportedState(
        **{name: getattr(two_trains, name) for name in (f.name for f in fields(TwoTrainState))},
        on_way=channel.on_way,
        on_way_rear_m=channel.on_way_rear_m,
        on_way_speed_mps=channel.on_way_speed_mps,
    ), out


TWO_TRAINS_REPORTED = Node(
    name="reported_separation",
    params=ReportedParams,
    state=ReportedState,
    inputs=ReportedInputs,
    outputs=TwoTrainOutputs,
    init=reported_init,
    step=reported_step,
    seed="001 §3.2 (Fig. 5 iii, Fig. 6), 000 §2.2, §2.5; EN 50159",
    sizes=TWO_TRAINS.sizes,
)
""":data:`TWO_TRAINS` fed by :data:`REPORT_CHANNEL`: the follower's authority computed from the reports the leader's
onboard unit makes, carried by a channel that delays, repeats, reorders or loses them."""
