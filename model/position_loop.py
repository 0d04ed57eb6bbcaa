"""Position determination between the true motion and speed supervision: the node the position properties are
proved over (seed 001 §3.2: a train that cannot determine its position must emergency brake).

Each cycle the train moves by ``distance_m`` to the end speed ``next_speed_mps``,
both chosen by the environment (any motion: the properties that need bounds on it
assume them); the tag reader and the tachometer report on that motion
(:mod:`atcs.model.position`), and supervision (:func:`~atcs.model.supervision.supervise`)
decides on the max safe speed (estimate plus accuracy) against the limits at the
current position, and on the position's validity.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Generic

from atcs.model.node import Node, as_dict
from atcs.model.ops import B, N, Ops
from atcs.model.position import (
    PROOF_TAGS,
    PositionInputs,
    PositionOutputs,
    PositionParams,
    PositionState,
    position_init,
    position_step,
)
from atcs.model.supervision import (
    Exceedances,
    SupervisionOutputs,
    SupervisionParams,
    SupervisionState,
    supervise,
    supervision_init,
)


@dataclass(frozen=True)
class PositionLoopParams(PositionParams[N, B], SupervisionParams[N, B]):
    pass


@dataclass(frozen=True)
class TrueMotion(Generic[N, B]):
    front_m: N
    """The true front."""
    speed_mps: N
    """The true speed."""
    last_distance_m: N
    """The true distance of the previous cycle."""
    sensor_excess_m: N
    """A ghost the ATP never reads: the sensors' error beyond their stated bounds since the position was last set
    at a tag: that tag's :func:`tag_excess_m` and the tachometer's :func:`tacho_excess_m` since its passage."""


def tacho_excess_m(o: Ops, p: PositionParams, distance_m, tacho_m):
    """How far a tachometer reading ``tacho_m`` is off the true ``distance_m`` beyond the stated error
    ``tacho_error * tacho_m``: 0 for a tachometer within its error; a drift, a slide or a standstill while moving
    beyond it."""
    allowed = p.tacho_error * tacho_m
    return o.max(o.const(0), distance_m - tacho_m - allowed, tacho_m - distance_m - allowed)


def tag_excess_m(o: Ops, p: PositionParams, passage_m, tag_m):
    """How far the true front at a tag read's reported passage ``passage_m`` is from the position ``tag_m`` of the
    tag whose id was read, beyond the tag window: 0 for a tag read within its window; a misplaced tag, a passage
    misreported or a read of the wrong id beyond it."""
    return o.max(o.const(0), passage_m - tag_m - p.tag_window_m, tag_m - passage_m - p.tag_window_m)


def sensor_excess_since_tag_m(o: Ops, p: PositionParams, excess_m, reset, cycle, since_tag, passage):
    """The ghost :attr:`TrueMotion.sensor_excess_m` after a cycle. ``cycle`` and ``since_tag`` are ``(true
    distance, tachometer distance)`` pairs, of the cycle and from the reported tag's passage to its end; ``passage``
    is ``(the true front at the reported passage, the read tag's position)``. At a tag reset (a tag read with the
    position valid: any fault invalidates it) the tag's excess and the tachometer's since the passage, else this
    cycle's :func:`tacho_excess_m` added."""
    at_tag = tacho_excess_m(o, p, *since_tag) + tag_excess_m(o, p, *passage)
    return o.ite(reset, at_tag, excess_m + tacho_excess_m(o, p, *cycle))


@dataclass(frozen=True)
class PositionLoopState(PositionState[N, B], SupervisionState[N, B], TrueMotion[N, B]):
    pass


@dataclass(frozen=True)
class PositionLoopInputs(PositionInputs[N, B]):
    distance_m: N
    """The true distance of this cycle (the environment's choice)."""
    distance_since_tag_m: N
    """The true distance from the reported tag's passage to the end of this cycle (the environment's choice)."""
    next_speed_mps: N
    """The true speed at the end of this cycle (the environment's choice)."""
    permitted_mps: N
    warning_mps: N
    sbi_mps: N
    ebi_mps: N
    """The supervision limits at the current position."""
    eb_release: B


@dataclass(frozen=True)
class PositionLoopOutputs(PositionOutputs[N, B], SupervisionOutputs[N, B]):
    pass


def position_loop_init(o: Ops, p: PositionLoopParams, s: PositionLoopState):
    """Power-up at standstill, no position, EB applied."""
    zero = o.const(0)
    return o.and_(
        position_init(o, p, s),
        supervision_init(o, p, s),
        o.eq(s.speed_mps, zero),
        o.eq(s.last_distance_m, zero),
        o.eq(s.sensor_excess_m, zero),
    )


def position_loop_step(o: Ops, p: PositionLoopParams, s: PositionLoopState, i: PositionLoopInputs):
    located, position = position_step(o, p, s, i)
    speed = position.speed_est_mps + position.speed_accuracy_mps
    over = Exceedances(
        over_permitted=speed > i.permitted_mps,
        over_warning=speed > i.warning_mps,
        over_sbi=speed > i.sbi_mps,
        over_ebi=speed > i.ebi_mps,
    )
    supervised, commands = supervise(o, p, s, over, position.standstill, i.eb_release, position.position_valid)
    state = PositionLoopState(
        **as_dict(located),
        **as_dict(supervised),
        front_m=s.front_m + i.distance_m,
        speed_mps=i.next_speed_mps,
        last_distance_m=i.distance_m,
        sensor_excess_m=sensor_excess_since_tag_m(
            o,
            p,
            s.sensor_excess_m,
            o.and_(i.tag_read, position.position_valid),
            (i.distance_m, i.tacho_m),
            (i.distance_since_tag_m, i.since_tag_m),
            (s.front_m + i.distance_m - i.distance_since_tag_m, o.select(p.tag_positions_m, located.lrt_index)),
        ),
    )
    return state, PositionLoopOutputs(**as_dict(position), **as_dict(commands))


POSITION_LOOP = Node(
    name="position_loop",
    params=PositionLoopParams,
    state=PositionLoopState,
    inputs=PositionLoopInputs,
    outputs=PositionLoopOutputs,
    init=position_loop_init,
    step=position_loop_step,
    seed="001 §3.2, 002 §3.1",
    sizes={"tag_ids": PROOF_TAGS, "tag_positions_m": PROOF_TAGS},
)
