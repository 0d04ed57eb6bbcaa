"""The simulated ATO (seed 003 §2.1-2.2's target speed; seed 000: it follows the permitted curve): traction,
service braking and the station stop, optionally tracking the minimum-time reference profile to the next stop
(:mod:`atcs.sim.reference_profile`). Run by :class:`~atcs.sim.simulator.Simulation` once per train and cycle."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from atcs.model.ato import ato_target_speed as ato_target
from atcs.model.ato import limits_ahead
from atcs.model.dynamic_profile import Horizon
from atcs.model.ops.floating import FLOAT
from atcs.model.profile import KMH_PER_MPS
from atcs.sim.reference_profile import ReferenceProfile, atp_ceiling, minimum_time_profile
from atcs.sim.train_run import TrainRun

if TYPE_CHECKING:
    from atcs.sim.simulator import Simulation

KMH = float(KMH_PER_MPS)
ATO_LOOKAHEAD_S = 2.0
"""The ATO does not accelerate within this many seconds (at its speed) of the indication point."""
STATION_CREEP_M = 0.5
"""The ATO starts braking for a station stop this far before its braking distance (and, stopped short, creeps up
to the stopping point from farther than this)."""
STATION_STOP_M = 0.2
"""Within this of the stopping point the ATO stops the train with full service braking."""


def ato_commands(sim: Simulation, train: TrainRun, pos, eoa_m: float, curves, departed: bool, traction_cut: bool):
    """The ATO (seed 003's target speed; seed 000: it follows the permitted curve): traction below the target
    speed while short of the indication point for its speed, service braking above the target speed or
    past the indication point; the station stop; the reference profile if the scenario asks for it.
    Returns (the next station, whether the train stands at it, the target, traction, the service brake)."""
    o, s, spec = FLOAT, sim.scenario, train.spec
    speed = pos.speed_est_mps
    a_est = float(train.plant.max_acceleration_mps2)
    ahead = limits_ahead(train.mrsp, pos.front_max_m)
    under = float(s.ato_speed_margin_kmh) / KMH  # the ATO aims this far under the limits

    def aim(limit_mps):
        return max(limit_mps - under, limit_mps / 2)

    planning_mps2 = float(s.planning_decel_kmhps) / KMH
    target = ato_target(
        o,
        front_m=pos.front_max_m,
        speed_mps=speed,
        line_limit_mps=aim(ahead.line_limit_mps),
        train_max_mps=float(spec.max_speed_kmh) / KMH,
        next_limit_m=ahead.next_limit_m,
        next_limit_mps=aim(ahead.next_limit_mps),
        ma_end_m=eoa_m,
        ma_speed_mps=0.0,
        planning_decel_mps2=planning_mps2,
        margin_m=float(s.ato_margin_m),
    )
    service_max = float(spec.data.service_decelerations_mps2[0])
    lookahead_m = speed * ATO_LOOKAHEAD_S
    past_indication = pos.front_max_m + lookahead_m >= curves.indication_m
    station = sim.stops[train.next_station] if train.next_station < len(sim.stops) else None
    # the station stop: the estimated front brought to a stop at the stopping point
    to_stop_m = float(station.stop_m) - pos.front_est_m if station is not None else math.inf
    station_braking = to_stop_m <= speed * speed / (2 * planning_mps2) + STATION_CREEP_M
    at_station = station is not None and speed == 0.0 and station_braking
    tracking = None
    if station is not None and s.ato_reference_profile and departed:
        if train.reference is None:
            train.reference = reference_profile(sim, train, pos.front_est_m, station)
            train.references.append(train.reference)
        reach_m = speed * sim.dt + a_est * sim.dt**2 / 2  # where a cycle of full traction ends
        tracking = train.reference.speed_at(pos.front_est_m + reach_m)
    aim_mps = target.speed_mps if tracking is None else min(target.speed_mps, tracking)
    traction = (
        departed
        and speed < aim_mps - (0.3 if tracking is None else 0.02)
        and not past_indication
        and not traction_cut
        and not station_braking
    )
    ato_brake = 0.0
    if speed > 0 and (pos.front_max_m >= curves.indication_m or not departed):
        ato_brake = service_max
    elif speed > 0 and station_braking:  # at the stopping point (or a few cm from it): stop now
        wanted = speed * speed / (2 * to_stop_m) if to_stop_m > STATION_STOP_M else service_max
        ato_brake = min(service_max, wanted)
    elif tracking is not None and speed > tracking:  # down to the profile's speed at the cycle's end
        ato_brake = min(service_max, (speed - tracking) / sim.dt)
    elif speed > target.speed_mps:
        distance = max(target.location_m - pos.front_max_m - float(s.ato_margin_m) / 2, 0.5)
        wanted = (speed * speed - target.speed_mps**2) / (2 * distance)
        ato_brake = min(service_max, max(wanted, 0.05))
    elif at_station or not departed:
        ato_brake = service_max  # holding the train at standstill
    return station, at_station, target, traction, ato_brake


def reference_profile(sim: Simulation, train: TrainRun, from_m: float, station) -> ReferenceProfile:
    """The minimum-time profile from ``from_m`` to the station's stop: under the ATP's indication curve for
    the line (less the ATO's speed margin), the train's traction and the ATO's planning deceleration."""
    s = sim.scenario
    horizon = Horizon(train.mrsp, train.gradient, float(sim.route_end_m), 0.0)
    margin_mps = max(float(s.ato_speed_margin_kmh) / KMH, 0.5)
    ceiling = atp_ceiling(train.train_data, train.national, horizon, margin_mps=margin_mps)
    return minimum_time_profile(
        ceiling,
        from_m,
        float(station.stop_m),
        accel_mps2=float(train.plant.max_acceleration_mps2),
        decel_mps2=float(s.planning_decel_kmhps) / KMH,
    )
