"""The station stop's doors (seed 004 §2.1): the door loop run each cycle with its properties checked, and the
ATO's door cycle at a stop (open on the platform's side, dwell, close, depart once closed and locked)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from atcs.model.doors import DOOR_LOOP, DoorLoopInputs
from atcs.sim.monitor import check_step, registered_properties
from atcs.sim.scenario import TrainSpec
from atcs.sim.train_run import TrainRun

if TYPE_CHECKING:
    from atcs.sim.simulator import Simulation

DOOR_PROPERTIES = registered_properties(DOOR_LOOP)


def station_doors(
    sim: Simulation,
    train: TrainRun,
    pos,
    station,
    t: float,
    *,
    immobilised: bool,
    traction_request: bool,
    supervision_cut: bool,
):
    """The door loop (:data:`~atcs.model.doors.DOOR_LOOP`, its properties checked each cycle) and the ATO's
    door cycle at a station stop: open on the platform's side, wait the dwell time from the doors opening,
    close, and depart once the DCU reports every door closed and locked."""
    left, right = station_sides(sim.platforms, station, train.spec) if station is not None else (False, False)
    opening = station is not None and not train.dwell_done
    obstructed = train.spec.fault("stuck_door", t) is not None
    inputs = DoorLoopInputs(
        position_valid=pos.position_valid,
        front_min_m=pos.front_min_m,
        front_max_m=pos.front_max_m,
        speed_mps=pos.speed_est_mps,
        standstill=pos.standstill,
        immobilised=immobilised,
        stopping_point_m=float(station.stop_m) if station is not None else 0.0,
        stop_tolerance_m=float(sim.scenario.stop_tolerance_m),
        **platforms_ahead(sim, train),
        request_left=opening and left,
        request_right=opening and right,
        probe_front_m=pos.front_min_m,
        probe_door_m=train.door_params.last_door_m,
        open_left=opening and left,
        open_right=opening and right,
        close=train.dwell_done,
        obstructed_left=obstructed,
        obstructed_right=obstructed,
        loop_a_stuck_closed=train.spec.fault("lying_door_sensor", t) is not None,
        loop_b_stuck_closed=False,
        traction_request=traction_request,
        supervision_traction_cut=supervision_cut,
    )
    train.dcu, out = check_step(
        DOOR_LOOP, train.door_params, train.dcu, inputs, DOOR_PROPERTIES, sim.step_count, traces=sim.traces
    )
    if station is not None:
        if train.doors_opened_s is None and (train.dcu.door_open_left or train.dcu.door_open_right):
            train.doors_opened_s = t
        if train.doors_opened_s is not None and t >= train.doors_opened_s + float(station.dwell_s):
            train.dwell_done = True
        if train.dwell_done and out.closed_locked:
            train.next_station += 1
            train.reference = None
            train.stats.station_stops += 1
            train.doors_opened_s, train.dwell_done = None, False
    return out


def platforms_ahead(sim: Simulation, train: TrainRun) -> dict:
    """The door loop's platform table: the platforms at the train's next station stop (none past the last)."""
    return sim.door_tables[train.next_station] if train.next_station < len(sim.stops) else sim.no_platforms


def station_sides(platforms, station, spec: TrainSpec) -> tuple[bool, bool]:
    """The sides (left, right) of the platforms that span the train's doors at the station's stopping point: the
    sides the ATO asks to open."""
    spans = [
        p
        for p in platforms
        if p.start_m <= station.stop_m - spec.last_door_m and station.stop_m - spec.first_door_m <= p.end_m
    ]
    return any(p.left for p in spans), any(p.right for p in spans)
