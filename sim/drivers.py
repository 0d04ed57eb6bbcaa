"""Drivers for closed-loop simulations: how a train is driven when its ATP must be put to the test.

They run on exact numbers and choose each cycle's end speed and distance within the
plant's bounds (:mod:`atcs.model.plant`), so a run stays inside the proofs'
assumptions and checks the same predicates.
"""

from __future__ import annotations

from fractions import Fraction

from atcs.model.ops.exact import EXACT
from atcs.model.plant import (
    PlantParams,
    PlantState,
    brake_effective,
    gradient_braking_mps2,
    max_gradient_acceleration_mps2,
    traction_available,
)


def gradient_braking_at(p: PlantParams, x_m) -> Fraction:
    """The gradient's share of the deceleration at ``x_m`` (the plant's own physics)."""
    j = max(j for j, start in enumerate(p.gradient_starts_m) if j == 0 or start <= x_m)
    return gradient_braking_mps2(EXACT, p, p.gradient_permille[j])


def worst_case_driver(p: PlantParams, s: PlantState, measured_speed_mps, mrsp_mps, emergency_brake):
    """``(next speed, distance)``: full traction (and the steepest downhill's help) whenever the plant allows it
    and the measured speed is under the MRSP, cruising above it (the service brake ignored); once the brake is
    effective, about the weakest braking the plant admits: the guaranteed deceleration plus the stronger
    gradient help of the cycle's two ends (a cycle that crosses onto an uphill must lose the uphill's share)."""
    o, dt = EXACT, p.cycle_s
    v = s.speed_mps
    if brake_effective(o, p, s, emergency_brake):
        decel = p.guaranteed_deceleration_mps2 + max(
            gradient_braking_at(p, s.front_m), gradient_braking_at(p, s.front_m + v * dt)
        )
        if v <= decel * dt:
            return Fraction(0), v * v / (2 * decel)
        return v - decel * dt, v * dt - decel * dt * dt / 2
    if measured_speed_mps >= mrsp_mps:
        return v, v * dt
    a = max_gradient_acceleration_mps2(o, p)
    if traction_available(o, p, s, emergency_brake):
        a += p.max_acceleration_mps2
    return v + a * dt, v * dt + a * dt * dt / 2
