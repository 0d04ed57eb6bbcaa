"""The simulated plant: a train's nominal traction and brakes each cycle, checked against the proofs' plant
(:func:`~atcs.model.plant.plant_admits`), and what its tag reader and tachometer see of the motion."""

from __future__ import annotations

import bisect
from typing import TYPE_CHECKING

from atcs.model.ops.floating import FLOAT
from atcs.model.plant import PlantState, gradient_braking_mps2, plant_admits
from atcs.model.profile import KMH_PER_MPS, value_at
from atcs.sim.monitor import run
from atcs.sim.train_run import SafetyViolation, TrainRun

if TYPE_CHECKING:
    from atcs.sim.simulator import Simulation

KMH = float(KMH_PER_MPS)
FLOAT_MARGIN = 1e-9
"""Traction runs this fraction under the plant's bound, so that IEEE rounding never takes a motion past it."""


def move(
    sim: Simulation, train: TrainRun, emergency_brake: bool, traction: bool, service_mps2: float, t: float
) -> None:
    """The plant: nominal traction and brakes (scaled under a ``brake_fade`` fault), checked against the proofs'
    plant bounds (a brake weaker than they admit stops the run, naming the broken assumption); the tachometer reads
    the distance (scaled under a ``tacho_drift`` fault, or a ``tacho_slide`` one while braking), and the tag
    reader a tag passed with the distance since its passage."""
    p, dt = train.plant, sim.dt
    data = train.spec.data
    brake_on = emergency_brake and train.brake_cycles >= p.brake_build_up_cycles
    grade = value_at(FLOAT, train.gradient, train.front_m)
    a = -float(gradient_braking_mps2(FLOAT, p, grade))
    fade = train.spec.fault("brake_fade", t)
    brake_factor = float(fade.value) if fade is not None else 1.0
    if brake_on:
        a -= float(data.emergency_decelerations_mps2[0]) * brake_factor
    elif traction and not emergency_brake:
        a += float(p.max_acceleration_mps2) * (1 - FLOAT_MARGIN)
    else:
        a -= service_mps2 * brake_factor
    v = train.speed_mps
    v_next = max(0.0, v + a * dt)
    distance = v * v / (-2 * a) if v_next == 0.0 and a < 0 else (v + v_next) / 2 * dt
    state = PlantState(front_m=train.front_m, speed_mps=v, brake_cycles=train.brake_cycles)
    if not run(sim.traces, plant_admits, FLOAT, p, state, bool(emergency_brake), v_next, distance):
        raise SafetyViolation(
            f"the motion ({v:.3f} -> {v_next:.3f} m/s over {distance:.3f} m) leaves the proofs' plant bounds",
            train.spec.name,
            sim.step_count,
            sim.time_s,
        )
    tags = sim.tag_positions_m
    passed = range(bisect.bisect_right(tags, train.front_m), bisect.bisect_right(tags, train.front_m + distance))
    if len(passed) > 1:
        raise SafetyViolation(
            f"ran {distance:.3f} m in a cycle, past {len(passed)} tags (from {tags[passed[0]]:g} m): the position "
            "node reads at most one tag a cycle (reader_complete)",
            train.spec.name,
            sim.step_count,
            sim.time_s,
        )
    drift, slide = train.spec.fault("tacho_drift", t), train.spec.fault("tacho_slide", t)
    braking = a < 0 and v > 0
    factor = float(drift.value if drift is not None else (slide.value if slide is not None and braking else 1))
    train.last_tag = passed[0] if passed else None
    since_m = min(distance, train.front_m + distance - tags[passed[0]]) if passed else 0.0
    train.since_tag_m = (since_m, since_m * factor)
    train.front_m += distance
    train.speed_mps = v_next
    train.last_distance_m = distance
    train.last_tacho_m = distance * factor
    train.brake_cycles = min(train.brake_cycles + 1, p.brake_build_up_cycles) if emergency_brake else 0.0
    _detached_wagons(train, dt, t)
    stats = train.stats
    stats.distance_m += distance
    stats.running_s += dt if distance > 0 else 0.0
    stats.max_speed_kmh = max(stats.max_speed_kmh, v_next * KMH)


def _detached_wagons(train: TrainRun, dt: float, t: float) -> None:
    """Under an ``integrity_lost`` fault the rear half of the train parts at the fault's start and brakes at the
    train's emergency deceleration to a stop (its brake pipe broken): :attr:`TrainRun.detached`."""
    if train.detached is None:
        if train.spec.fault("integrity_lost", t) is not None:
            train.detached = (train.front_m - float(train.spec.data.train_length_m), train.speed_mps)
        return
    rear_m, v = train.detached
    decel = float(train.spec.data.emergency_decelerations_mps2[0])
    v_next = max(0.0, v - decel * dt)
    run_m = v * v / (2 * decel) if v_next == 0.0 else (v + v_next) / 2 * dt
    train.detached = (rear_m + run_m, v_next)
