"""Train kinematics with bounded nondeterminism: the plant the closed-loop proofs drive (docs/design.md, the
closed-loop argument in discrete time).

One step is one ATP cycle of ``cycle_s``. The plant does not choose its motion: each
cycle's end speed and distance are inputs, and :func:`plant_admits` says whether
they are physically possible for a train with these bounds:

- traction (any driver or ATO command) accelerates at most ``max_acceleration_mps2``
  plus the steepest downhill's gradient acceleration, until the traction cut-off
  takes effect ``traction_cut_cycles`` cycles after the emergency-brake command
  (the command's own cycle counted);
- after the cut-off the train coasts, accelerating at most by the gradient;
- the emergency brake is effective ``brake_build_up_cycles`` cycles after the
  command; from then on the squared speed falls at least by twice the work of the
  guaranteed deceleration over the distance run
  (``v'^2 <= v^2 - 2 * integral of (guaranteed_deceleration_mps2 + A_gradient)``,
  the gradient taken from the compensated profile, which is the lowest under the
  train), so a gradient change within the cycle is accounted exactly;
- no cycle decelerates by more than ``max_deceleration_mps2``; the train never
  moves backward.

An acceleration bound ``a`` over a cycle bounds both ``v' <= v + a * dt`` and the
distance ``<= v * dt + a * dt^2 / 2``, whatever the acceleration does within the cycle.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Generic

from atcs.model.deceleration import gradient_deceleration_mps2
from atcs.model.node import Node, Stateless, stateless_node
from atcs.model.ops import B, N, Ops
from atcs.model.profile import Profile


@dataclass(frozen=True)
class PlantParams(Generic[N, B]):
    gradient_starts_m: tuple[N, ...]
    """The compensated gradient profile (per mille, positive uphill)."""
    gradient_permille: tuple[N, ...]
    line_end_m: N
    rotating_mass_uphill_percent: N
    rotating_mass_downhill_percent: N
    max_acceleration_mps2: N
    """The highest acceleration traction gives on level track."""
    guaranteed_deceleration_mps2: N
    """The emergency brake's deceleration on level track in the worst adhesion (the lowest the brake gives)."""
    max_deceleration_mps2: N
    """The highest deceleration of any cycle (brakes and gradient together)."""
    cycle_s: N
    """One ATP cycle (seed 001: 100 ms)."""
    traction_cut_cycles: N
    """Whole cycles from an emergency-brake command until traction is cut (the command's own cycle counted)."""
    brake_build_up_cycles: N
    """Whole cycles from an emergency-brake command until the brake is effective (the command's cycle counted)."""


@dataclass(frozen=True)
class PlantState(Generic[N, B]):
    front_m: N
    """The true position of the train's front."""
    speed_mps: N
    """The true speed (>= 0)."""
    brake_cycles: N
    """Cycles the emergency-brake command has been given without a break (0: not commanded), at most
    ``brake_build_up_cycles``."""


@dataclass(frozen=True)
class PlantInputs(Generic[N, B]):
    emergency_brake: B
    """The ATP's emergency-brake command this cycle."""
    next_speed_mps: N
    """The speed at the end of the cycle (chosen by the environment, within the plant's bounds)."""
    distance_m: N
    """The distance run during the cycle (chosen by the environment, within the plant's bounds)."""


@dataclass(frozen=True)
class PlantOutputs(Generic[N, B]):
    admissible: B
    """The cycle's motion is within the plant's bounds."""


def plant_gradient(p: PlantParams) -> Profile:
    return Profile(p.gradient_starts_m, p.gradient_permille, p.line_end_m)


def gradient_braking_mps2(o: Ops, p: PlantParams, gradient_permille):
    """The gradient's share of the deceleration (seed 000 §2.3), computed here from the physics, apart from the
    ATP's braking curves, so a fault in those is not mirrored in the plant."""
    uphill = gradient_permille >= o.const(0)
    mass = o.ite(uphill, p.rotating_mass_uphill_percent, p.rotating_mass_downhill_percent)
    return gradient_deceleration_mps2(o, gradient_permille, mass)


def max_gradient_acceleration_mps2(o: Ops, p: PlantParams):
    """The steepest downhill's acceleration (0 if the line has none)."""
    return o.max(o.const(0), *(-gradient_braking_mps2(o, p, g) for g in p.gradient_permille))


def braking_work(o: Ops, p: PlantParams, from_m, to_m):
    """``integral from from_m to to_m of (guaranteed_deceleration + A_gradient(x)) dx`` (``from_m <= to_m``)."""
    g = plant_gradient(p)
    work = p.guaranteed_deceleration_mps2 * (to_m - from_m)
    for j, start in enumerate(g.starts_m):
        low = from_m if j == 0 else o.max(from_m, start)
        high = to_m if j + 1 == len(g.starts_m) else o.min(to_m, g.starts_m[j + 1])
        work = work + gradient_braking_mps2(o, p, g.values[j]) * o.max(o.const(0), high - low)
    return work


def traction_available(o: Ops, p: PlantParams, s: PlantState, emergency_brake):
    return o.not_(o.and_(emergency_brake, s.brake_cycles >= p.traction_cut_cycles))


def brake_effective(o: Ops, p: PlantParams, s: PlantState, emergency_brake):
    return o.and_(emergency_brake, s.brake_cycles >= p.brake_build_up_cycles)


def plant_admits(o: Ops, p: PlantParams, s: PlantState, emergency_brake, next_speed_mps, distance_m):
    """The cycle from ``s`` to ``(next_speed_mps, front + distance_m)`` is possible (module docstring)."""
    zero, dt = o.const(0), p.cycle_s
    a_gradient = max_gradient_acceleration_mps2(o, p)
    a_high = o.ite(traction_available(o, p, s, emergency_brake), p.max_acceleration_mps2 + a_gradient, a_gradient)
    v, v_next = s.speed_mps, next_speed_mps
    free = o.and_(v_next <= v + a_high * dt, distance_m <= v * dt + a_high * dt * dt / o.const(2))
    braked = o.and_(
        v_next * v_next <= v * v - o.const(2) * braking_work(o, p, s.front_m, s.front_m + distance_m),
        distance_m <= v * dt,
    )
    return o.and_(
        v_next >= zero,
        distance_m >= zero,
        v_next >= v - p.max_deceleration_mps2 * dt,
        o.ite(brake_effective(o, p, s, emergency_brake), braked, free),
    )


def plant_next(o: Ops, p: PlantParams, s: PlantState, emergency_brake, next_speed_mps, distance_m) -> PlantState:
    return PlantState(
        front_m=s.front_m + distance_m,
        speed_mps=next_speed_mps,
        brake_cycles=o.ite(emergency_brake, o.min(s.brake_cycles + o.const(1), p.brake_build_up_cycles), o.const(0)),
    )


def plant_init(o: Ops, p: PlantParams, s: PlantState):
    """At standstill with the emergency brake applied (the ATP's power-up state)."""
    return o.and_(o.eq(s.speed_mps, o.const(0)), o.eq(s.brake_cycles, p.brake_build_up_cycles))


def plant_step(o: Ops, p: PlantParams, s: PlantState, i: PlantInputs):
    admissible = plant_admits(o, p, s, i.emergency_brake, i.next_speed_mps, i.distance_m)
    return plant_next(o, p, s, i.emergency_brake, i.next_speed_mps, i.distance_m), PlantOutputs(admissible)


PLANT = Node(
    name="plant",
    params=PlantParams,
    state=PlantState,
    inputs=PlantInputs,
    outputs=PlantOutputs,
    init=plant_init,
    step=plant_step,
    seed="000 §2.5, docs/design.md closed loop",
    sizes={"gradient_starts_m": 2, "gradient_permille": 2},
)


# --- one cycle's motion judged under two emergency-brake histories -------------------------------------------------


@dataclass(frozen=True)
class PlantPairInputs(Generic[N, B]):
    """A state and a cycle's motion, with two emergency-brake commands and counters: the ATP's of one closed loop
    and of another (docs/configuration.md "Windows": a line's ATP brakes at least whenever a window's does)."""

    front_m: N
    speed_mps: N
    brake_cycles: N
    emergency_brake: B
    other_brake_cycles: N
    other_emergency_brake: B
    next_speed_mps: N
    distance_m: N


@dataclass(frozen=True)
class PlantPairOutputs(Generic[N, B]):
    admissible: B
    """The motion is within the plant's bounds under the first command and counter."""
    other_admissible: B
    """The motion is within the plant's bounds under the other command and counter."""
    next_brake_cycles: N
    other_next_brake_cycles: N


def plant_pair_step(o: Ops, p: PlantParams, s: Stateless, i: PlantPairInputs):
    state = PlantState(i.front_m, i.speed_mps, i.brake_cycles)
    other = PlantState(i.front_m, i.speed_mps, i.other_brake_cycles)
    motion = (i.next_speed_mps, i.distance_m)
    return s, PlantPairOutputs(
        admissible=plant_admits(o, p, state, i.emergency_brake, *motion),
        other_admissible=plant_admits(o, p, other, i.other_emergency_brake, *motion),
        next_brake_cycles=plant_next(o, p, state, i.emergency_brake, *motion).brake_cycles,
        other_next_brake_cycles=plant_next(o, p, other, i.other_emergency_brake, *motion).brake_cycles,
    )


PLANT_PAIR = stateless_node(
    name="plant_pair",
    params=PlantParams,
    inputs=PlantPairInputs,
    outputs=PlantPairOutputs,
    step=plant_pair_step,
    seed="000 §2.5, docs/configuration.md windows",
    sizes={"gradient_starts_m": 2, "gradient_permille": 2},
)
""":func:`plant_admits` and the brake counter of one cycle under two emergency-brake histories, for the side
condition of the line's windows (more braking commanded admits fewer motions)."""
