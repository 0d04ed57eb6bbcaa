"""Safe deceleration with the compensated gradient (seed 000 §2.3, equations 1 and 2, Fig. 4).

``Dec_s(v, d) = Dec(v) + Dec_grad(d)`` with ``Dec(v)`` the train's speed-step
braking model and ``Dec_grad(d) = g * Grad_c(d) / (1000 + 10 * M_R)``, where
``Grad_c`` is the compensated gradient profile: on a rising edge the lower
gradient is kept for one train length (the rear is still on it), falling edges
are unchanged, i.e. the lowest gradient under the train. Gradients are per mille,
positive uphill (uphill helps braking); ``M_R`` is the rotating mass in percent.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Generic

from atcs.model.node import Stateless, stateless_node
from atcs.model.ops import B, N, Ops
from atcs.model.profile import Profile, lowest_under_train, step_lookup

GRAVITY_MPS2 = "9.81"


def braking_deceleration_mps2(o: Ops, speeds_mps: Sequence, decelerations_mps2: Sequence, speed_mps):
    """``Dec(v)``: the braking model's deceleration at ``speed_mps`` (a step table over speed)."""
    return step_lookup(o, speeds_mps, decelerations_mps2, speed_mps)


def gradient_deceleration_mps2(o: Ops, gradient_permille, rotating_mass_percent):
    """``Dec_grad = g * grad / (1000 + 10 * M_R)`` (negative downhill). A negative ``M_R`` (invalid data)
    counts as 0, so that the divisor stays positive on any input."""
    mass = o.max(rotating_mass_percent, o.const(0))
    return o.const(GRAVITY_MPS2) * gradient_permille / (o.const(1000) + o.const(10) * mass)


def compensated_gradient_permille(o: Ops, gradient: Profile, train_length_m, front_m):
    """``Grad_c`` at the front: the lowest gradient under the train (Fig. 4)."""
    return lowest_under_train(o, (gradient,), train_length_m, front_m)


def safe_deceleration_mps2(
    o: Ops, speeds_mps, decelerations_mps2, gradient: Profile, rotating_mass_percent, train_length_m, speed_mps, front_m
):
    """``Dec_s(v, d) = Dec(v) + Dec_grad(d)`` with the compensated gradient (equation 1)."""
    grad_c = compensated_gradient_permille(o, gradient, train_length_m, front_m)
    return braking_deceleration_mps2(o, speeds_mps, decelerations_mps2, speed_mps) + gradient_deceleration_mps2(
        o, grad_c, rotating_mass_percent
    )


# --- the node the proofs quantify over ------------------------------------------------------------


@dataclass(frozen=True)
class DecelerationParams(Generic[N, B]):
    line_end_m: N
    train_length_m: N
    rotating_mass_percent: N
    gradient_starts_m: tuple[N, ...]
    gradient_permille: tuple[N, ...]
    brake_speeds_mps: tuple[N, ...]
    """Speed steps of the braking model: ``brake_decelerations_mps2[j]`` from ``brake_speeds_mps[j]`` up."""
    brake_decelerations_mps2: tuple[N, ...]


@dataclass(frozen=True)
class DecelerationQuery(Generic[N, B]):
    front_m: N
    probe_m: N
    """Any position under the train (properties quantify over it)."""
    speed_mps: N


@dataclass(frozen=True)
class DecelerationOutputs(Generic[N, B]):
    compensated_gradient_permille: N
    safe_deceleration_mps2: N


def gradient_profile_of(p: DecelerationParams) -> Profile:
    return Profile(p.gradient_starts_m, p.gradient_permille, p.line_end_m)


def deceleration_step(o: Ops, p: DecelerationParams, s: Stateless, i: DecelerationQuery):
    gradient = gradient_profile_of(p)
    return s, DecelerationOutputs(
        compensated_gradient_permille=compensated_gradient_permille(o, gradient, p.train_length_m, i.front_m),
        safe_deceleration_mps2=safe_deceleration_mps2(
            o,
            p.brake_speeds_mps,
            p.brake_decelerations_mps2,
            gradient,
            p.rotating_mass_percent,
            p.train_length_m,
            i.speed_mps,
            i.front_m,
        ),
    )


DECELERATION = stateless_node(
    name="deceleration",
    params=DecelerationParams,
    inputs=DecelerationQuery,
    outputs=DecelerationOutputs,
    step=deceleration_step,
    seed="000 §2.3",
    sizes={"gradient_starts_m": 4, "gradient_permille": 4, "brake_speeds_mps": 3, "brake_decelerations_mps2": 3},
)
"""Safe deceleration as a node for proofs: up to 4 gradient segments and a 3-step braking model,
all symbolic, with the train length and the rotating mass."""
