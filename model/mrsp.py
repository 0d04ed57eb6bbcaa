"""Most restrictive speed profile (seed 001 §3.3, seed 002 §3.2).

The MRSP at the train's front is the lowest of the four static speed profiles:
the permanent and temporary infrastructure limits (PISL, TISL) and the permanent
and temporary train limits (PTSL, TTSL), each with its rises delayed by the
train length (:func:`~atcs.model.profile.lowest_under_train`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Generic

from atcs.model.node import Stateless, stateless_node
from atcs.model.ops import B, N, Ops
from atcs.model.profile import Profile, lowest_under_train, value_at, value_at_bisected


def mrsp_at(o: Ops, pisl: Profile, tisl: Profile, ptsl: Profile, ttsl: Profile, train_length_m, front_m):
    """The MRSP (m/s) for a train of ``train_length_m`` whose front is at ``front_m``."""
    return lowest_under_train(o, (pisl, tisl, ptsl, ttsl), train_length_m, front_m)


# --- the node the proofs quantify over: all four profiles and the train length symbolic ----------


@dataclass(frozen=True)
class MrspParams(Generic[N, B]):
    line_end_m: N
    """Where the line (and every profile) ends; every profile starts at 0."""
    train_length_m: N
    pisl_starts_m: tuple[N, ...]
    pisl_limits_mps: tuple[N, ...]
    tisl_starts_m: tuple[N, ...]
    tisl_limits_mps: tuple[N, ...]
    ptsl_starts_m: tuple[N, ...]
    ptsl_limits_mps: tuple[N, ...]
    ttsl_starts_m: tuple[N, ...]
    ttsl_limits_mps: tuple[N, ...]


PROFILE_NAMES = ("pisl", "tisl", "ptsl", "ttsl")


def mrsp_profiles(p: MrspParams) -> tuple[Profile, ...]:
    """The four profiles of the node's parameters, in the order PISL, TISL, PTSL, TTSL."""
    return tuple(
        Profile(getattr(p, f"{name}_starts_m"), getattr(p, f"{name}_limits_mps"), p.line_end_m)
        for name in PROFILE_NAMES
    )


@dataclass(frozen=True)
class MrspQuery(Generic[N, B]):
    front_m: N
    """The train's front."""
    probe_m: N
    """Any position under the train (properties use it to quantify over the train's length)."""


@dataclass(frozen=True)
class MrspOutputs(Generic[N, B]):
    mrsp_mps: N


def mrsp_step(o: Ops, p: MrspParams, s: Stateless, i: MrspQuery):
    pisl, tisl, ptsl, ttsl = mrsp_profiles(p)
    return s, MrspOutputs(mrsp_mps=mrsp_at(o, pisl, tisl, ptsl, ttsl, p.train_length_m, i.front_m))


MRSP = stateless_node(
    name="mrsp",
    params=MrspParams,
    inputs=MrspQuery,
    outputs=MrspOutputs,
    step=mrsp_step,
    seed="001 §3.3, 002 §3.2",
    sizes={
        "pisl_starts_m": 4,
        "pisl_limits_mps": 4,
        "tisl_starts_m": 2,
        "tisl_limits_mps": 2,
        "ptsl_starts_m": 2,
        "ptsl_limits_mps": 2,
        "ttsl_starts_m": 2,
        "ttsl_limits_mps": 2,
    },
)
"""The MRSP as a node for proofs: up to 4 PISL segments and 2 of each other profile (zero-length
segments allowed, so fewer segments are covered too), all breakpoints, limits and the train length
symbolic."""


@dataclass(frozen=True)
class ProfileLookupParams(Generic[N, B]):
    starts_m: tuple[N, ...]
    values: tuple[N, ...]
    end_m: N


@dataclass(frozen=True)
class ProfileLookupQuery(Generic[N, B]):
    x_m: N


@dataclass(frozen=True)
class ProfileLookupOutputs(Generic[N, B]):
    chained: N
    """:func:`~atcs.model.profile.value_at`: the chain over every breakpoint."""
    bisected: N
    """:func:`~atcs.model.profile.value_at_bisected`."""


def profile_lookup_step(o: Ops, p: ProfileLookupParams, s: Stateless, i: ProfileLookupQuery):
    profile = Profile(p.starts_m, p.values, p.end_m)
    return s, ProfileLookupOutputs(chained=value_at(o, profile, i.x_m), bisected=value_at_bisected(o, profile, i.x_m))


PROFILE_LOOKUP = stateless_node(
    name="profile_lookup",
    params=ProfileLookupParams,
    inputs=ProfileLookupQuery,
    outputs=ProfileLookupOutputs,
    step=profile_lookup_step,
    seed="002 §3.2",
    sizes={"starts_m": 9, "values": 9},
)
"""A profile's value at a position two ways, every breakpoint and value symbolic: up to 9 segments (a
bisection's every path over 8 inner breakpoints, fewer segments being the same profile split at equal values)."""
