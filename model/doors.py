"""Door-opening protection: the ATP's door enable, the traction interlock and the door control unit (seed 004
§2.1 and Fig. 1; seed 001 Fig. 1: ATO uses the ATP's outputs for platform stops and door control).

The ATP enables a side's doors only when (seed 004 §2.1)

1. the train is stopped at its designated stopping point: the whole position interval
   ``[front_min, front_max]`` lies within the stopping tolerance;
2. a platform is on that side: one platform of the table, on that side, covers every
   door of the train wherever in the interval the front is;
3. zero speed is detected (the standstill signal, and the measured speed is 0);
4. the train is immobilised (the holding brake is applied);

and the ATO or driver asks for that side. The doors of a train lie between
``first_door_m`` and ``last_door_m`` behind its front. The door control unit (DCU)
opens a side only with the ATP's enable *and* the ATO's or driver's open command, and
closes it when the enable drops or on a close command; a door held by an obstacle
stays open. The DCU reports whether all doors are closed and locked on two
independent detection loops (the door-closed and the lock switches); the ATP cuts
traction unless *both* report closed (two out of two), so the train cannot move
under its own power with a door open even if one loop lies (a sensor stuck at
closed).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Generic

from atcs.model.node import Node, Stateless, stateless_node
from atcs.model.ops import B, N, Ops

PROOF_PLATFORMS = 3
"""The platform-table capacity the proofs cover."""


@dataclass(frozen=True)
class DoorParams(Generic[N, B]):
    first_door_m: N
    """Distance from the train's front to the front edge of its first door."""
    last_door_m: N
    """Distance from the train's front to the rear edge of its last door (>= ``first_door_m``)."""


@dataclass(frozen=True)
class DoorConditions(Generic[N, B]):
    """What the ATP's door enable reads about the train and the platform."""

    position_valid: B
    front_min_m: N
    """The min safe front (:mod:`atcs.model.position`)."""
    front_max_m: N
    """The max safe front."""
    speed_mps: N
    """The measured speed."""
    standstill: B
    """Zero speed detected (:mod:`atcs.model.position`: no tachometer distance this cycle)."""
    immobilised: B
    """The train is immobilised (holding brake applied)."""
    stopping_point_m: N
    """Where the front must stop at this platform."""
    stop_tolerance_m: N
    """How far from the stopping point the front may be."""
    platform_start_m: tuple[N, ...]
    platform_end_m: tuple[N, ...]
    platform_left: tuple[B, ...]
    """The platform is on the left (in the direction of travel); an entry on neither side is no platform."""
    platform_right: tuple[B, ...]
    request_left: B
    """The ATO or driver asks for the left doors to be released."""
    request_right: B
    probe_front_m: N
    """Any front in the position interval (the properties quantify over it; the step does not read it)."""
    probe_door_m: N
    """Any door's offset behind the front, in ``[first_door_m, last_door_m]`` (as ``probe_front_m``)."""


@dataclass(frozen=True)
class DoorEnableInputs(DoorConditions[N, B]):
    closed_loop_a: B
    """The DCU's first detection loop: every door closed and locked."""
    closed_loop_b: B
    """The second, independent one."""


@dataclass(frozen=True)
class DoorEnableOutputs(Generic[N, B]):
    enable_left: B
    """Door open enable, left side."""
    enable_right: B
    traction_cut: B
    """The door interlock's traction cut-off: a detection loop reports some door not closed and locked."""


def stopped_at_stopping_point(o: Ops, i: DoorConditions):
    """Condition 1: the whole position interval within the stopping tolerance."""
    return o.and_(
        i.position_valid,
        i.stopping_point_m - i.stop_tolerance_m <= i.front_min_m,
        i.front_max_m <= i.stopping_point_m + i.stop_tolerance_m,
    )


def platform_covers_doors(o: Ops, p: DoorParams, i: DoorConditions, side: tuple):
    """Condition 2 for one side: one platform on ``side`` spans the doors, from the rearmost door of the rearmost
    front to the foremost door of the foremost front."""
    return o.or_(
        *(
            o.and_(
                side[j],
                i.platform_start_m[j] <= i.front_min_m - p.last_door_m,
                i.front_max_m - p.first_door_m <= i.platform_end_m[j],
            )
            for j in range(len(side))
        )
    )


def door_enable(o: Ops, p: DoorParams, i: DoorConditions, closed_loop_a, closed_loop_b) -> DoorEnableOutputs:
    """The ATP's door enable per side, and the door interlock on both detection loops (seed 004 §2.1)."""
    held = o.and_(i.standstill, i.speed_mps <= o.const(0), i.immobilised, stopped_at_stopping_point(o, i))
    return DoorEnableOutputs(
        enable_left=o.and_(i.request_left, held, platform_covers_doors(o, p, i, i.platform_left)),
        enable_right=o.and_(i.request_right, held, platform_covers_doors(o, p, i, i.platform_right)),
        traction_cut=o.not_(o.and_(closed_loop_a, closed_loop_b)),
    )


def door_enable_step(o: Ops, p: DoorParams, s: Stateless, i: DoorEnableInputs):
    return s, door_enable(o, p, i, i.closed_loop_a, i.closed_loop_b)


DOOR_ENABLE = stateless_node(
    name="door_enable",
    params=DoorParams,
    inputs=DoorEnableInputs,
    outputs=DoorEnableOutputs,
    step=door_enable_step,
    seed="004 §2.1",
    sizes={name: PROOF_PLATFORMS for name in ("platform_start_m", "platform_end_m", "platform_left", "platform_right")},
)


# --- the door control unit -------------------------------------------------------------------------------


@dataclass(frozen=True)
class DcuState(Generic[N, B]):
    door_open_left: B
    """Some left door is open (not closed and locked)."""
    door_open_right: B


@dataclass(frozen=True)
class DcuInputs(Generic[N, B]):
    enable_left: B
    """The ATP's door open enable."""
    enable_right: B
    open_left: B
    """The ATO's or driver's open command."""
    open_right: B
    close: B
    """The ATO's or driver's close command (both sides)."""
    obstructed_left: B
    """An obstacle (or a stuck door) keeps a left door from closing."""
    obstructed_right: B


@dataclass(frozen=True)
class DcuOutputs(Generic[N, B]):
    closed_locked: B
    """Every door is closed and locked (the report to the ATP), at the start of the cycle."""


def dcu_init(o: Ops, p: Stateless, s: DcuState):
    """Power-up with the doors closed and locked."""
    return o.and_(o.not_(s.door_open_left), o.not_(s.door_open_right))


def door_next(o: Ops, open_now, enable, command, close, obstructed):
    """One side: opens with enable and command; closes when the enable drops or on a close command, unless
    obstructed."""
    opens = o.and_(enable, command)
    closing = o.or_(o.not_(enable), close)
    return o.or_(opens, o.and_(open_now, o.or_(o.not_(closing), obstructed)))


def closed_and_locked(o: Ops, s: DcuState):
    """The DCU's report to the ATP: no door open."""
    return o.not_(o.or_(s.door_open_left, s.door_open_right))


def dcu_step(o: Ops, p: Stateless, s: DcuState, i: DcuInputs):
    """One cycle of the DCU: report the doors, then act on the enables and commands."""
    nxt = DcuState(
        door_open_left=door_next(o, s.door_open_left, i.enable_left, i.open_left, i.close, i.obstructed_left),
        door_open_right=door_next(o, s.door_open_right, i.enable_right, i.open_right, i.close, i.obstructed_right),
    )
    return nxt, DcuOutputs(closed_locked=closed_and_locked(o, s))


DCU = Node(
    name="dcu",
    params=Stateless,
    state=DcuState,
    inputs=DcuInputs,
    outputs=DcuOutputs,
    init=dcu_init,
    step=dcu_step,
    seed="004 §2.1, Fig. 1",
)


# --- ATP, DCU and traction in one loop -------------------------------------------------------------------


@dataclass(frozen=True)
class DoorLoopInputs(DoorConditions[N, B]):
    """What the ATP reads, the DCU's commands and obstacles (as :class:`DcuInputs`), and traction."""

    open_left: B
    open_right: B
    close: B
    obstructed_left: B
    obstructed_right: B
    loop_a_stuck_closed: B
    """The first detection loop reports closed whatever the doors (a lying sensor)."""
    loop_b_stuck_closed: B
    traction_request: B
    """The ATO's or driver's traction command."""
    supervision_traction_cut: B
    """Speed supervision's traction cut-off (:mod:`atcs.model.supervision`)."""


@dataclass(frozen=True)
class DoorLoopOutputs(Generic[N, B]):
    enable_left: B
    enable_right: B
    closed_locked: B
    """Both detection loops report every door closed and locked."""
    traction_cut: B
    """The ATP's traction cut-off: supervision's or the door interlock's."""
    traction_applied: B
    """The train is driven by its own power this cycle."""


def door_loop_step(o: Ops, p: DoorParams, s: DcuState, i: DoorLoopInputs):
    """One cycle: the DCU reports its doors on both loops, the ATP decides the enables and the traction cut-off, the
    DCU acts."""
    closed = closed_and_locked(o, s)
    loop_a, loop_b = o.or_(closed, i.loop_a_stuck_closed), o.or_(closed, i.loop_b_stuck_closed)
    atp = door_enable(o, p, i, loop_a, loop_b)
    nxt, _ = dcu_step(
        o,
        Stateless(),
        s,
        DcuInputs(
            enable_left=atp.enable_left,
            enable_right=atp.enable_right,
            open_left=i.open_left,
            open_right=i.open_right,
            close=i.close,
            obstructed_left=i.obstructed_left,
            obstructed_right=i.obstructed_right,
        ),
    )
    traction_cut = o.or_(atp.traction_cut, i.supervision_traction_cut)
    return nxt, DoorLoopOutputs(
        enable_left=atp.enable_left,
        enable_right=atp.enable_right,
        closed_locked=o.and_(loop_a, loop_b),
        traction_cut=traction_cut,
        traction_applied=o.and_(i.traction_request, o.not_(traction_cut)),
    )


DOOR_LOOP = Node(
    name="door_loop",
    params=DoorParams,
    state=DcuState,
    inputs=DoorLoopInputs,
    outputs=DoorLoopOutputs,
    init=dcu_init,
    step=door_loop_step,
    seed="004 §2.1, Fig. 1",
    sizes=DOOR_ENABLE.sizes,
)
