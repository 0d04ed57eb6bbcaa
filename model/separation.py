"""Two trains in closed loop: the follower's ATP supervising the end of authority that the preceding train's
T2T reports give, the follower's plant, the leader's motion and the report channel (seed 001 §3.2 Fig. 6,
seed 000 §2.2 and §2.5).

Brick-wall mode (absolute braking distance): each report carries the leader's min safe
rear at the time it was sent; a report arrives after any delay (reports may also be
lost or overtaken). A report describes a past state, and the leader never moves
backward, so every report is a lower bound on the leader's current rear: the
follower keeps the largest one received (``best_rear_m``, never lowered, so a late
report overtaken by a newer one does no harm) and supervises the end of authority
``best_rear_m - safety_margin_m`` with the closed loop's ATP
(:func:`~atcs.model.closed_loop.atp_cycle`). The leader moves forward in any way.
"""

from __future__ import annotations

from dataclasses import dataclass

from atcs.model.closed_loop import ClosedLoopInputs, atp_cycle
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
    """Kept between the follower's end of authority and the leader's reported rear (seed 001 Fig. 6)."""


@dataclass(frozen=True)
class TwoTrainState(PlantState[N, B], SupervisionState[N, B]):
    """The follower's plant and supervision state, and:"""

    leader_rear_m: N
    """The leader's true rear."""
    leader_speed_mps: N
    best_rear_m: N
    """The largest leader rear reported to the follower so far."""


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


@dataclass(frozen=True)
class TwoTrainOutputs(SupervisionOutputs[N, B]):
    eoa_m: N
    """The follower's end of authority this cycle."""


def follower_eoa_m(o: Ops, p: TwoTrainParams, s: TwoTrainState, i: TwoTrainInputs):
    """``(best reported rear after this cycle's report, end of authority)``."""
    best = o.ite(i.report_delivered, o.max(s.best_rear_m, i.report_rear_m), s.best_rear_m)
    return best, best - p.safety_margin_m


def two_train_init(o: Ops, p: TwoTrainParams, s: TwoTrainState):
    """The follower at standstill with EB applied behind the end of authority its first report gives."""
    return o.and_(supervision_init(o, p, s), plant_init(o, p, s), s.leader_speed_mps >= o.const(0),
                  s.best_rear_m <= s.leader_rear_m, s.front_m <= s.best_rear_m - p.safety_margin_m)


def two_train_step(o: Ops, p: TwoTrainParams, s: TwoTrainState, i: TwoTrainInputs):
    best, eoa = follower_eoa_m(o, p, s, i)
    atp, commands, _ = atp_cycle(o, p, s, i, eoa)
    follower = plant_next(o, p, s, commands.emergency_brake, i.next_speed_mps, i.distance_m)
    state = TwoTrainState(
        front_m=follower.front_m, speed_mps=follower.speed_mps, brake_cycles=follower.brake_cycles,
        eb_latched=atp.eb_latched, sb_latched=atp.sb_latched,
        leader_rear_m=s.leader_rear_m + i.leader_distance_m, leader_speed_mps=i.leader_next_speed_mps,
        best_rear_m=best,
    )
    return state, TwoTrainOutputs(
        warning=commands.warning, service_brake=commands.service_brake, emergency_brake=commands.emergency_brake,
        traction_cut=commands.traction_cut, eoa_m=eoa,
    )


def two_train_admits(o: Ops, p: TwoTrainParams, s: TwoTrainState, i: TwoTrainInputs):
    """The follower's plant bounds for this cycle's motion, under the command its ATP gives."""
    _, eoa = follower_eoa_m(o, p, s, i)
    _, commands, _ = atp_cycle(o, p, s, i, eoa)
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
"""Follower ATP + follower plant + leader + T2T channel, brick-wall mode, for proofs."""
