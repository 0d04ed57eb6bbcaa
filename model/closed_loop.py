"""The ATP in closed loop: supervision of the end of authority and the MRSP ceiling, composed with the
braking curves and the plant (seed 000 §2.4 and §2.5; docs/design.md, the closed-loop argument).

Each cycle the ATP reads the measured front and speed, takes the max safe front
(measured + ``position_error_m``), and compares it with the location of each curve of
the end of authority (EoA, target speed 0) at the measured speed; it compares the
measured speed with the ceilings MRSP + dV (:func:`~atcs.model.curves.ceiling_offset_mps`).
The limits exceeded go to the foundation's supervision decision
(:func:`~atcs.model.supervision.supervise`): EB latched until standstill and release,
service brake, warning. The emergency-brake command then drives the plant.

:data:`DECREASE_LOOP` is the same ATP and plant against one speed decrease of the MRSP instead: a target of the
lower speed, supervised while the max safe front is short of it, then the lower ceilings (a configuration's
closed loop, docs/configuration.md "Speed decreases").

The EBI's estimated acceleration is the worst the plant allows (``A_max`` plus the
steepest downhill's gradient acceleration): a measured ``A_est`` would need a bound on
how fast the acceleration can rise, which the plant does not model. Train data's
``T_traction`` and ``T_be`` count from the last cycle whose check passed, so they
include one cycle more than the plant's delays after the command.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from fractions import Fraction
from typing import Generic

from atcs.model.curves import DESIGN_CASE_SIZES, FAR_M, CurveLocations, Target, gradient_acceleration_mps2
from atcs.model.dynamic_profile import ebd_foot_mps, exceedances, limits_at
from atcs.model.node import Node
from atcs.model.ops import B, N, Ops
from atcs.model.plant import (
    PlantParams,
    PlantState,
    max_gradient_acceleration_mps2,
    plant_admits,
    plant_gradient,
    plant_init,
    plant_next,
)
from atcs.model.supervision import (
    SupervisionOutputs,
    SupervisionParams,
    SupervisionState,
    supervise,
    supervision_init,
)
from atcs.model.train_data import NationalData, TrainData


@dataclass(frozen=True)
class ClosedLoopParams(PlantParams[N, B], TrainData[N, B], NationalData[N, B]):
    service_brake_fitted: B
    mrsp_mps: N
    """The most restrictive speed profile over the horizon (one value: the closed loop's ceiling)."""
    eoa_m: N
    """The end of authority (target speed 0)."""
    position_error_m: N
    """The odometry's bound: the measured front is within this distance of the true front."""


@dataclass(frozen=True)
class ClosedLoopState(PlantState[N, B], SupervisionState[N, B]):
    pass


@dataclass(frozen=True)
class ClosedLoopInputs(Generic[N, B]):
    measured_front_m: N
    measured_speed_mps: N
    standstill: B
    eb_release: B
    next_speed_mps: N
    """The plant's choice (see :mod:`atcs.model.plant`)."""
    distance_m: N
    """The plant's choice (see :mod:`atcs.model.plant`)."""


@dataclass(frozen=True)
class ClosedLoopOutputs(SupervisionOutputs[N, B]):
    ebi_m: N
    """Where the EoA's EBI lies at the measured speed."""


def worst_acceleration_mps2(o: Ops, p: ClosedLoopParams):
    """The EBI's estimated acceleration: the most the train can accelerate under traction (A_max plus the
    steepest downhill's gradient acceleration)."""
    downhill = (-gradient_acceleration_mps2(o, p, g) for g in p.gradient_permille)
    return p.max_acceleration_mps2 + o.max(o.const(0), *downhill)


def eoa_target(o: Ops, eoa_m) -> Target:
    """The end of authority as a target: speed 0, its EBD ending at standstill there (Subset-026 §3.13.8.3.2)."""
    zero = o.const(0)
    return Target(eoa_m, zero, zero)


def max_safe_front_m(p, i):
    """The measured front plus the odometry's bound: the max safe front the ATP supervises."""
    return i.measured_front_m + p.position_error_m


def atp_cycle(o: Ops, p, s: ClosedLoopState, i: ClosedLoopInputs, target: Target, mrsp_mps, supervised=None):
    """One ATP cycle against ``target`` (only while ``supervised`` holds, when given) and the ceilings of the MRSP
    ``mrsp_mps``: returns (next supervision state, commands, the target's curves)."""
    front = max_safe_front_m(p, i)
    speed = i.measured_speed_mps
    curve, ceiling = limits_at(o, p, p, plant_gradient(p), (target,), mrsp_mps, speed, worst_acceleration_mps2(o, p))
    if supervised is not None:
        far = o.const(FAR_M)
        curve = CurveLocations(**{f.name: o.ite(supervised, getattr(curve, f.name), far) for f in fields(curve)})
    over = exceedances(o, curve, ceiling, front, speed)
    # the measurement assumption (front within position_error_m of the truth) is what a valid position gives
    state, commands = supervise(
        o, SupervisionParams(p.service_brake_fitted), s, over, i.standstill, i.eb_release, o.const_bool(True)
    )
    return state, commands, curve


def eoa_atp_cycle(o: Ops, p: ClosedLoopParams, s: ClosedLoopState, i: ClosedLoopInputs):
    """The closed loop's ATP: the end of authority and the ceilings of the one MRSP value."""
    return atp_cycle(o, p, s, i, eoa_target(o, p.eoa_m), p.mrsp_mps)


def _loop_step(o: Ops, p, s: ClosedLoopState, i: ClosedLoopInputs, atp):
    supervision, commands, curve = atp(o, p, s, i)
    plant = plant_next(o, p, s, commands.emergency_brake, i.next_speed_mps, i.distance_m)
    state = ClosedLoopState(
        front_m=plant.front_m,
        speed_mps=plant.speed_mps,
        brake_cycles=plant.brake_cycles,
        eb_latched=supervision.eb_latched,
        sb_latched=supervision.sb_latched,
    )
    return state, ClosedLoopOutputs(
        warning=commands.warning,
        service_brake=commands.service_brake,
        emergency_brake=commands.emergency_brake,
        traction_cut=commands.traction_cut,
        ebi_m=curve.ebi_m,
    )


def _loop_admits(o: Ops, p, s: ClosedLoopState, i: ClosedLoopInputs, atp):
    _, commands, _ = atp(o, p, s, i)
    return plant_admits(o, p, s, commands.emergency_brake, i.next_speed_mps, i.distance_m)


def closed_loop_init(o: Ops, p: ClosedLoopParams, s: ClosedLoopState):
    """Power-up at standstill behind the EoA with the emergency brake applied."""
    return o.and_(supervision_init(o, p, s), plant_init(o, p, s), s.front_m <= p.eoa_m)


def closed_loop_step(o: Ops, p: ClosedLoopParams, s: ClosedLoopState, i: ClosedLoopInputs):
    return _loop_step(o, p, s, i, eoa_atp_cycle)


def closed_loop_admits(o: Ops, p: ClosedLoopParams, s: ClosedLoopState, i: ClosedLoopInputs):
    """The plant's bounds for this cycle's motion, under the command the ATP gives."""
    return _loop_admits(o, p, s, i, eoa_atp_cycle)


CLOSED_LOOP = Node(
    name="closed_loop",
    params=ClosedLoopParams,
    state=ClosedLoopState,
    inputs=ClosedLoopInputs,
    outputs=ClosedLoopOutputs,
    init=closed_loop_init,
    step=closed_loop_step,
    seed="000 §2.4, §2.5",
    sizes=DESIGN_CASE_SIZES,
)
"""ATP + plant for proofs: 2 compensated-gradient segments, one-step brake tables."""


@dataclass(frozen=True)
class DecreaseLoopParams(PlantParams[N, B], TrainData[N, B], NationalData[N, B]):
    service_brake_fitted: B
    mrsp_mps: N
    """The MRSP before the decrease."""
    decrease_m: N
    """Where the MRSP decreases: the target's location."""
    mrsp_after_mps: N
    """The MRSP from the decrease on."""
    position_error_m: N
    """The odometry's bound: the measured front is within this distance of the true front."""


def decrease_atp_cycle(o: Ops, p: DecreaseLoopParams, s: ClosedLoopState, i: ClosedLoopInputs):
    """The ATP against one speed decrease of the MRSP (Subset-026 §3.13.8.3.1, §3.13.10.3): the decrease is a target
    of the lower speed, its EBD ending at ``V_target + dV_ebi(V_target)``, supervised while the max safe front is
    short of it; the ceilings are the MRSP's at the max safe front."""
    ahead = max_safe_front_m(p, i) < p.decrease_m
    target = Target(p.decrease_m, p.mrsp_after_mps, ebd_foot_mps(o, p, p.mrsp_after_mps))
    return atp_cycle(o, p, s, i, target, o.ite(ahead, p.mrsp_mps, p.mrsp_after_mps), ahead)


def decrease_loop_init(o: Ops, p: DecreaseLoopParams, s: ClosedLoopState):
    """Power-up at standstill anywhere with the emergency brake applied."""
    return o.and_(supervision_init(o, p, s), plant_init(o, p, s))


def decrease_loop_step(o: Ops, p: DecreaseLoopParams, s: ClosedLoopState, i: ClosedLoopInputs):
    return _loop_step(o, p, s, i, decrease_atp_cycle)


def decrease_loop_admits(o: Ops, p: DecreaseLoopParams, s: ClosedLoopState, i: ClosedLoopInputs):
    """The plant's bounds for this cycle's motion, under the command the ATP gives."""
    return _loop_admits(o, p, s, i, decrease_atp_cycle)


DECREASE_LOOP = Node(
    name="decrease_loop",
    params=DecreaseLoopParams,
    state=ClosedLoopState,
    inputs=ClosedLoopInputs,
    outputs=ClosedLoopOutputs,
    init=decrease_loop_init,
    step=decrease_loop_step,
    seed="000 §2.4.2, 002 §3.2",
    sizes=DESIGN_CASE_SIZES,
)
"""ATP + plant for proofs against one speed decrease of the MRSP (no end of authority: one elsewhere only adds
braking, docs/configuration.md "Windows")."""


def worst_case_at_brake(o, p, front_m, speed_mps, cycles: int, traction_cycles: int, build_up_cycles: int):
    """The farthest front and highest speed when the brake becomes effective, from ``(front_m, speed_mps)``
    with the command given for ``cycles`` cycles so far: full traction until the cut-off, then coasting."""
    dt = p.cycle_s
    a_traction = worst_acceleration_mps2(o, p)
    a_coast = max_gradient_acceleration_mps2(o, p)
    t1 = o.const(max(0, traction_cycles - cycles)) * dt
    t2 = o.const(build_up_cycles - max(cycles, traction_cycles)) * dt
    v1 = speed_mps + a_traction * t1
    front1 = front_m + (speed_mps + v1) / o.const(2) * t1
    v2 = v1 + a_coast * t2
    return front1 + (v1 + v2) / o.const(2) * t2, v2


def whole_cycles(preset: str, fixed: dict) -> tuple[int, int]:
    """The plant's traction cut-off and brake build-up delays of a preset, in whole cycles."""
    for name in ("traction_cut_cycles", "brake_build_up_cycles"):
        if Fraction(fixed[name]).denominator != 1:
            raise ValueError(f"closed-loop preset {preset}: {name} = {fixed[name]} is not a whole number of cycles")
    return int(fixed["traction_cut_cycles"]), int(fixed["brake_build_up_cycles"])
