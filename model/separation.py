"""Two trains in closed loop: the follower's ATP supervising the end of authority that the preceding train's
T2T reports give, the follower's plant, the leader's motion and the report channel (seed 001 §3.2 Fig. 6,
seed 000 §2.2 and §2.5).

Each report carries the leader's min safe rear and min speed at the time it was sent;
it arrives after any delay (reports may also be lost or overtaken). A report
describes a past state, so it bounds the leader's present from below:

- its rear: the leader never moves backward;
- its earliest stopping point ``rear + v^2 / (2 * leader_max_deceleration_mps2)``: the
  leader never decelerates harder than that, so this point never moves back either.

The follower keeps the largest of each bound received (``best_rear_m``,
``best_stop_m``: never lowered, so a late report overtaken by a newer one does no
harm) and supervises, with the closed loop's ATP
(:func:`~atcs.model.closed_loop.atp_cycle`), the end of authority ``best_stop_m`` less
the safety margin in relative-braking mode, ``best_rear_m`` less the margin in
brick-wall mode (absolute braking distance) or when no report has arrived for longer
than ``report_timeout_s`` (what is certain even if the leader stopped dead).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Generic

from atcs.model.closed_loop import ClosedLoopInputs, atp_cycle
from atcs.model.curves import MIN_SPAN
from atcs.model.node import Node
from atcs.model.ops import B, N, Ops
from atcs.model.plant import PlantParams, PlantState, plant_admits, plant_init, plant_next
from atcs.model.supervision import SupervisionOutputs, SupervisionState, supervision_init
from atcs.model.train_data import NationalData, TrainData


@dataclass(frozen=True)
class TwoTrainParams(PlantParams[N, B], TrainData[N, B], NationalData[N, B]):
    service_brake_fitted: B
    mrsp_mps: N
    """The follower's MRSP ceiling (one value)."""
    position_error_m: N
    """The follower's odometry bound."""
    safety_margin_m: N
    """Kept between the follower's end of authority and the leader's stopping point or rear (seed 001 Fig. 6)."""
    leader_max_deceleration_mps2: N
    """The leader's *highest* possible deceleration: a train can stop faster than its guaranteed braking."""
    report_timeout_s: N
    brick_wall: B
    """Absolute braking distance: the leader's rear is the target, with no credit for its speed."""


@dataclass(frozen=True)
class TwoTrainState(PlantState[N, B], SupervisionState[N, B]):
    """The follower's plant and supervision state, and:"""

    leader_rear_m: N
    """The leader's true rear."""
    leader_speed_mps: N
    leader_stop_m: N
    """Where the leader would stop at the earliest from its true state (a ghost for the proofs: the ATP never
    reads it)."""
    best_rear_m: N
    """The largest leader rear reported to the follower so far."""
    best_stop_m: N
    """The largest earliest stopping point of the leader reported so far."""
    since_report_s: N
    """Time since the last report arrived."""


@dataclass(frozen=True)
class TwoTrainInputs(ClosedLoopInputs[N, B]):
    """The follower's measurements and plant choice, and:"""

    leader_distance_m: N
    """How far the leader moves this cycle (the environment's choice)."""
    leader_next_speed_mps: N
    report_delivered: B
    """A T2T report from the leader arrives this cycle."""
    report_rear_m: N
    """The min safe rear it reports (at the time it was sent)."""
    report_speed_mps: N
    """The min speed it reports (at the time it was sent)."""


@dataclass(frozen=True)
class TwoTrainOutputs(SupervisionOutputs[N, B]):
    eoa_m: N
    """The follower's end of authority this cycle."""


def stopping_point_m(o: Ops, p: TwoTrainParams, rear_m, speed_mps):
    """Where a leader at ``rear_m`` and ``speed_mps`` stops at the earliest (its highest deceleration)."""
    deceleration = o.max(p.leader_max_deceleration_mps2, o.const(MIN_SPAN))  # a guard valid data never meets
    return rear_m + speed_mps * speed_mps / (o.const(2) * deceleration)


@dataclass(frozen=True)
class Reports(Generic[N]):
    best_rear_m: N
    best_stop_m: N
    since_report_s: N
    eoa_m: N


def follower_eoa_m(o: Ops, p: TwoTrainParams, s: TwoTrainState, i: TwoTrainInputs) -> Reports:
    """The bounds kept after this cycle's report, and the end of authority they give."""
    arrived = i.report_delivered
    rear = o.ite(arrived, o.max(s.best_rear_m, i.report_rear_m), s.best_rear_m)
    stop = o.ite(arrived, o.max(s.best_stop_m, stopping_point_m(o, p, i.report_rear_m, i.report_speed_mps)),
                 s.best_stop_m)
    since = o.ite(arrived, o.const(0), s.since_report_s + p.cycle_s)
    certain_only = o.or_(p.brick_wall, since > p.report_timeout_s)
    return Reports(rear, stop, since, o.ite(certain_only, rear, stop) - p.safety_margin_m)


def two_train_init(o: Ops, p: TwoTrainParams, s: TwoTrainState):
    """The follower at standstill with EB applied behind the end of authority its first report gives."""
    return o.and_(supervision_init(o, p, s), plant_init(o, p, s), s.leader_speed_mps >= o.const(0),
                  o.eq(s.leader_stop_m, stopping_point_m(o, p, s.leader_rear_m, s.leader_speed_mps)),
                  s.best_rear_m <= s.leader_rear_m, s.best_stop_m <= s.leader_stop_m,
                  s.best_rear_m <= s.best_stop_m, o.eq(s.since_report_s, o.const(0)),
                  s.front_m <= s.best_rear_m - p.safety_margin_m, s.front_m < s.leader_rear_m)


def two_train_step(o: Ops, p: TwoTrainParams, s: TwoTrainState, i: TwoTrainInputs):
    reports = follower_eoa_m(o, p, s, i)
    atp, commands, _ = atp_cycle(o, p, s, i, reports.eoa_m)
    follower = plant_next(o, p, s, commands.emergency_brake, i.next_speed_mps, i.distance_m)
    state = TwoTrainState(
        front_m=follower.front_m, speed_mps=follower.speed_mps, brake_cycles=follower.brake_cycles,
        eb_latched=atp.eb_latched, sb_latched=atp.sb_latched,
        leader_rear_m=s.leader_rear_m + i.leader_distance_m, leader_speed_mps=i.leader_next_speed_mps,
        leader_stop_m=stopping_point_m(o, p, s.leader_rear_m + i.leader_distance_m, i.leader_next_speed_mps),
        best_rear_m=reports.best_rear_m, best_stop_m=reports.best_stop_m, since_report_s=reports.since_report_s,
    )
    return state, TwoTrainOutputs(
        warning=commands.warning, service_brake=commands.service_brake, emergency_brake=commands.emergency_brake,
        traction_cut=commands.traction_cut, eoa_m=reports.eoa_m,
    )


def two_train_admits(o: Ops, p: TwoTrainParams, s: TwoTrainState, i: TwoTrainInputs):
    """The follower's plant bounds for this cycle's motion, under the command its ATP gives."""
    _, commands, _ = atp_cycle(o, p, s, i, follower_eoa_m(o, p, s, i).eoa_m)
    return plant_admits(o, p, s, commands.emergency_brake, i.next_speed_mps, i.distance_m)


TWO_TRAINS = Node(
    name="two_trains",
    params=TwoTrainParams,
    state=TwoTrainState,
    inputs=TwoTrainInputs,
    outputs=TwoTrainOutputs,
    init=two_train_init,
    step=two_train_step,
    seed="001 §3.2 (Fig. 6), 000 §2.2, §2.5",
    sizes={"gradient_starts_m": 2, "gradient_permille": 2, "emergency_speeds_mps": 1,
           "emergency_decelerations_mps2": 1, "service_speeds_mps": 1, "service_decelerations_mps2": 1},
)
"""Follower ATP + follower plant + leader + T2T channel, for proofs."""
