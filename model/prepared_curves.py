"""Braking curves preprocessed per authority, as seed 002 §3.2 preprocesses the PSL: each target's EBD walked once,
each cycle only a lookup.

A target's EBD is a walk backward from its foot through cells, a gradient segment and a speed step of the brake
each (:func:`~atcs.model.curves.braking_cells`), in which the squared speed rises linearly as the position falls.
:func:`braking_table` records the walk once, when the MA, the MRSP or the train data change: where it enters each
cell, the squared speed there, the cell's deceleration, and the squared speed where it leaves (rising: the search
keys, CRV-14). Where the curve reaches a speed (:func:`table_location_m`) is then the first cell the walk leaves
above that speed, as far into it as the rise takes: a bisection (``Ops.first_above``; in the symbolic backend the tree
of ``ite`` over every path of the search). CRV-13 proves every curve's location from the table
equal to the direct walk's (:func:`~atcs.model.curves.curve_locations`), for every target, speed and gradient
breakpoints, for the presets' trains.

:func:`prepare_horizon` tables every target of a horizon; :func:`supervise_prepared` is
:func:`~atcs.model.dynamic_profile.supervise_position` on it (concrete data, as that one).
"""

from __future__ import annotations

import bisect
import dataclasses
from dataclasses import dataclass
from typing import Generic

from atcs.model.curves import (
    CONVERTED_CURVES,
    DESIGN_CASE_SIZES,
    FAR_M,
    HUGE_SPEED2,
    MIN_SPAN,
    STEPPED_CURVES,
    CurveLocations,
    CurveParams,
    CurveQuery,
    Target,
    above_foot,
    bec_speed_and_distance,
    bec_train_speed_mps,
    braking_cells,
    curve_gradient,
    curve_target,
    curves_from_ebd,
    curves_from_ebd_and_ebi,
    safe_brake,
)
from atcs.model.dynamic_profile import Ceilings, Horizon, ceilings, exceedances, supervised_targets
from atcs.model.node import Stateless, stateless_node
from atcs.model.ops import B, N, Ops
from atcs.model.profile import Profile, value_at_bisected
from atcs.model.supervision import Exceedances
from atcs.model.train_data import NationalData, TrainData


@dataclass(frozen=True)
class BrakingTable(Generic[N]):
    """A braking curve walked once from its foot backward: per cell, in the walk's order, where the walk enters it
    and the squared speed there, the cell's deceleration (as the walk divides by it), and the squared speed where
    the walk leaves it; and where the walk ends."""

    entry_m: tuple[N, ...]
    entry_speed2: tuple[N, ...]
    decel_mps2: tuple[N, ...]
    exit_speed2: tuple[N, ...]
    end_m: N


def braking_table(o: Ops, t: TrainData, n: NationalData, gradient_c: Profile, target: Target) -> BrakingTable:
    """The target's EBD as a table: its walk from the foot (``ebd_foot_mps`` at the target) to the line's start or
    :data:`~atcs.model.curves.HUGE_SPEED2`, whichever comes first."""
    foot2 = target.ebd_foot_mps * target.ebd_foot_mps
    cells, (end_m, end_speed2) = braking_cells(
        o, t, safe_brake(o, t, n), gradient_c, target.location_m, foot2, o.const(-FAR_M), o.const(HUGE_SPEED2)
    )
    entry_m, entry_speed2, decel = zip(*cells, strict=True)
    return BrakingTable(
        entry_m=entry_m,
        entry_speed2=entry_speed2,
        decel_mps2=tuple(o.max(a, o.const(MIN_SPAN)) for a in decel),
        exit_speed2=(*entry_speed2[1:], end_speed2),
        end_m=end_m,
    )


def table_location_m(o: Ops, table: BrakingTable, speed2):
    """Where the tabled curve reaches the squared speed ``speed2`` (below ``HUGE_SPEED2``): in the first cell the
    walk leaves above it, ``(speed2 - entry) / (2 * deceleration)`` before the cell's entry (the walk's own last
    step); where the walk ends if it never leaves a cell above it."""
    cell = o.first_above(table.exit_speed2, speed2)
    entry_m = o.select(table.entry_m, cell)
    rise2 = o.max(o.const(0), speed2 - o.select(table.entry_speed2, cell))
    inside_m = entry_m - rise2 / (o.const(2) * o.select(table.decel_mps2, cell))
    return o.ite(cell >= o.const(len(table.exit_speed2)), table.end_m, inside_m)


def tabled_ebd_location_m(o: Ops, target: Target, table: BrakingTable, speed_mps):
    """Where ``target``'s EBD reaches ``speed_mps``, looked up in its table; FAR_M at or below its foot."""
    return above_foot(o, target, speed_mps, table_location_m(o, table, speed_mps * speed_mps))


def prepared_curve_locations(
    o: Ops, t: TrainData, n: NationalData, target: Target, table: BrakingTable, speed_mps, a_est_mps2
) -> CurveLocations:
    """:func:`~atcs.model.curves.curve_locations` with the EBD looked up in the target's table."""
    return curves_from_ebd(o, t, n, target, speed_mps, a_est_mps2, lambda v: tabled_ebd_location_m(o, target, table, v))


# --- the node the proofs compare with the direct walk -------------------------------------------------------------


def prepared_curves_step(o: Ops, p: CurveParams, s: Stateless, i: CurveQuery):
    target = curve_target(p)
    table = braking_table(o, p, p, curve_gradient(p), target)
    return s, prepared_curve_locations(o, p, p, target, table, i.speed_mps, i.a_est_mps2)


PREPARED_CURVES = stateless_node(
    name="prepared_curves",
    params=CurveParams,
    inputs=CurveQuery,
    outputs=CurveLocations,
    step=prepared_curves_step,
    seed="000 §2.4, 002 §3.2",
    sizes=DESIGN_CASE_SIZES,
)
"""One target's curves from its table, as :data:`~atcs.model.curves.CURVES` computes them directly: the same
parameters and query, for CRV-13 and CRV-14."""

PREPARED_STEPPED_CURVES = dataclasses.replace(
    PREPARED_CURVES, name="prepared_curves_stepped", sizes=STEPPED_CURVES.sizes
)
""":data:`PREPARED_CURVES` with the three-step emergency brake of :data:`~atcs.model.curves.STEPPED_CURVES`."""

PREPARED_CONVERTED_CURVES = dataclasses.replace(
    PREPARED_CURVES, name="prepared_curves_converted", sizes=CONVERTED_CURVES.sizes
)
""":data:`PREPARED_CURVES` with the four-step brakes of :data:`~atcs.model.curves.CONVERTED_CURVES`."""


@dataclass(frozen=True)
class SpeedPair(Generic[N, B]):
    slower_mps: N
    faster_mps: N


@dataclass(frozen=True)
class TableLocationPair(Generic[N, B]):
    slower_ebd_m: N
    """Where the tabled EBD reaches the slower speed."""
    faster_ebd_m: N
    """Where it reaches the faster one."""


def table_order_step(o: Ops, p: CurveParams, s: Stateless, i: SpeedPair):
    target = curve_target(p)
    table = braking_table(o, p, p, curve_gradient(p), target)
    return s, TableLocationPair(
        slower_ebd_m=tabled_ebd_location_m(o, target, table, i.slower_mps),
        faster_ebd_m=tabled_ebd_location_m(o, target, table, i.faster_mps),
    )


TABLE_ORDER = stateless_node(
    name="table_order",
    params=CurveParams,
    inputs=SpeedPair,
    outputs=TableLocationPair,
    step=table_order_step,
    seed="002 §3.2, 000 §2.4",
    sizes=DESIGN_CASE_SIZES,
)
"""One target's tabled EBD at two speeds, for CRV-16 (the envelopes' order)."""

TABLE_ORDER_STEPPED = dataclasses.replace(TABLE_ORDER, name="table_order_stepped", sizes=STEPPED_CURVES.sizes)
TABLE_ORDER_CONVERTED = dataclasses.replace(TABLE_ORDER, name="table_order_converted", sizes=CONVERTED_CURVES.sizes)


# --- a horizon's tables and their envelopes, for supervision on concrete data ------------------------------------


ENVELOPE_STEP_MPS = "1/2"
"""The spacing of the speeds at which an envelope compares its targets' curves."""

ENVELOPE_FLOAT_SLACK_M = "1/1000000"
"""How far a float lookup may stray from the real curve's monotone order (CRV-16 holds on real numbers; a double
rounds each operation, a few ulps of positions below :data:`~atcs.model.curves.FAR_M`): an envelope keeps every
target within twice this of the least, so rounding never drops the nearest. Zero on exact backends."""


@dataclass(frozen=True)
class CurveEnvelope(Generic[N]):
    """The targets that can be nearest, speed band by speed band: the least of several targets' EBD locations
    at any speed, from only those that can be least in its band.

    Band ``i`` runs from ``grid_mps[i]`` to ``grid_mps[i + 1]``, both included; ``nearest[i]`` are the indices
    (into ``targets``) of the targets kept for it. Above the grid, every target. Each target's EBD location never
    increases with the speed (CRV-16), so a target whose location at the band's top is beyond the least at its
    bottom is beyond the least everywhere in the band: dropped (:func:`envelope_band`)."""

    targets: tuple[Target, ...]
    tables: tuple[BrakingTable, ...]
    grid_mps: tuple[N, ...]
    nearest: tuple[tuple[int, ...], ...]


def envelope_band(o: Ops, bottom_m: tuple, top_m: tuple, slack_m) -> tuple[int, ...]:
    """The targets to keep in one band, from their EBD locations at its bottom and its top speed: the nearest at
    the bottom, and every target whose location at the top is within ``2 * slack_m`` of that (one of those
    FAR_M at the top, for a band below every foot: FAR_M then, wherever each of them is)."""
    least = o.min(*bottom_m)
    first = next(k for k, m in enumerate(bottom_m) if m == least)
    near = least + o.const(2) * slack_m
    kept = [k for k, m in enumerate(top_m) if k != first and m <= near and m < o.const(FAR_M)]
    return (first, *kept)


def curve_envelope(o: Ops, targets: tuple, tables: tuple, located: tuple, grid_mps: tuple) -> CurveEnvelope:
    """The envelope of ``targets`` (``located[k][i]``: target ``k``'s EBD location at ``grid_mps[i]``)."""
    slack_m = o.const(ENVELOPE_FLOAT_SLACK_M if o.name == "float" else 0)
    nearest = tuple(
        envelope_band(o, tuple(row[i] for row in located), tuple(row[i + 1] for row in located), slack_m)
        for i in range(len(grid_mps) - 1)
    )
    return CurveEnvelope(targets=targets, tables=tables, grid_mps=grid_mps, nearest=nearest)


def envelope_location_m(o: Ops, envelope: CurveEnvelope, speed_mps):
    """The least of the envelope's targets' EBD locations at ``speed_mps`` (at or above zero): its band's targets
    looked up (:func:`tabled_ebd_location_m`), every target off the grid."""
    band = bisect.bisect_right(envelope.grid_mps, speed_mps) - 1
    kept = envelope.nearest[band] if 0 <= band < len(envelope.nearest) else range(len(envelope.targets))
    return o.min(*(tabled_ebd_location_m(o, envelope.targets[k], envelope.tables[k], speed_mps) for k in kept))


@dataclass(frozen=True)
class PreparedHorizon(Generic[N]):
    """A horizon with every target's table (the MRSP's speed decreases short of the EoA, then the EoA, by
    location) and each target's EBD location at the envelopes' speeds; the envelopes, built when first asked
    for (:func:`targets_ahead`)."""

    horizon: Horizon
    decrease_starts_m: tuple[N, ...]
    targets: tuple[Target, ...]
    tables: tuple[BrakingTable, ...]
    grid_mps: tuple[N, ...]
    located: tuple[tuple[N, ...], ...]
    envelopes: dict = dataclasses.field(default_factory=dict, compare=False, repr=False)


def envelope_grid_mps(o: Ops, horizon: Horizon, targets: tuple) -> tuple:
    """The envelopes' band edges: every :data:`ENVELOPE_STEP_MPS` from zero to 10 m/s above the highest MRSP
    limit or foot speed (above any speed or ``V_bec`` of a supervised train but a far overspeeding one)."""
    step = o.const(ENVELOPE_STEP_MPS)
    top = o.max(*horizon.mrsp.values, *(g.ebd_foot_mps for g in targets)) + o.const(10)
    grid, speed = [], o.const(0)
    while speed <= top:
        grid.append(speed)
        speed = speed + step
    return tuple(grid)


def prepare_horizon(
    o: Ops, t: TrainData, n: NationalData, horizon: Horizon, reuse: PreparedHorizon | None = None
) -> PreparedHorizon:
    """Every target's table and its EBD locations at the envelopes' speeds (concrete data): once per change of
    the MA, the MRSP or the train data. What ``reuse`` has of a target is kept when only the EoA moved (the same
    MRSP, gradient and train)."""
    targets = supervised_targets(o, n, horizon, o.const(-FAR_M))
    grid = envelope_grid_mps(o, horizon, targets)
    kept = {}
    if (
        reuse is not None
        and reuse.horizon.mrsp is horizon.mrsp
        and reuse.horizon.gradient is horizon.gradient
        and reuse.grid_mps == grid
    ):
        kept = {g: (table, row) for g, table, row in zip(reuse.targets, reuse.tables, reuse.located, strict=True)}
    tables, located = [], []
    for g in targets:
        if g in kept:
            table, row = kept[g]
        else:
            table = braking_table(o, t, n, horizon.gradient, g)
            row = tuple(tabled_ebd_location_m(o, g, table, u) for u in grid)
        tables.append(table)
        located.append(row)
    return PreparedHorizon(
        horizon=horizon,
        decrease_starts_m=tuple(g.location_m for g in targets[:-1]),
        targets=targets,
        tables=tuple(tables),
        grid_mps=grid,
        located=tuple(located),
    )


@dataclass(frozen=True)
class TargetsAhead(Generic[N]):
    """The envelopes of the targets from one on (those ahead of a max safe front): their speeds, ascending, a
    target of each speed, the envelope of them all (for the EBD), and for the EBI, for each ``j``, the envelope of
    those at the ``j`` lowest speeds (``alike[j - 1]``) and of those at the ``j``-th speed alone (``alone[j]``)."""

    speeds_mps: tuple[N, ...]
    of_speed: tuple[Target, ...]
    every: CurveEnvelope
    alike: tuple[CurveEnvelope, ...]
    alone: tuple[CurveEnvelope, ...]


def targets_ahead(o: Ops, prepared: PreparedHorizon, first: int) -> TargetsAhead:
    """The envelopes of the targets from ``first`` on, built the first time they are asked for."""
    if first not in prepared.envelopes:
        ahead = range(first, len(prepared.targets))
        speeds = tuple(sorted({prepared.targets[k].speed_mps for k in ahead}))

        def envelope(chosen):
            return curve_envelope(
                o,
                tuple(prepared.targets[k] for k in chosen),
                tuple(prepared.tables[k] for k in chosen),
                tuple(prepared.located[k] for k in chosen),
                prepared.grid_mps,
            )

        prepared.envelopes[first] = TargetsAhead(
            speeds_mps=speeds,
            of_speed=tuple(next(g for g in prepared.targets[first:] if g.speed_mps == v) for v in speeds),
            every=envelope(ahead),
            alike=tuple(envelope([k for k in ahead if prepared.targets[k].speed_mps <= v]) for v in speeds),
            alone=tuple(envelope([k for k in ahead if prepared.targets[k].speed_mps == v]) for v in speeds),
        )
    return prepared.envelopes[first]


def supervise_prepared(
    o: Ops, t: TrainData, n: NationalData, prepared: PreparedHorizon, max_safe_front_m, speed_mps, a_est_mps2
) -> tuple[Exceedances, CurveLocations, Ceilings]:
    """:func:`~atcs.model.dynamic_profile.supervise_position` on the tables: the targets ahead of the max safe
    front (a bisection), their EBD and EBI located in envelopes rather than target by target. The EBD is the
    least over all of them; the EBI groups them by speed, since ``(V_bec, D_bec)`` depends on a target only
    through its speed: one envelope for the targets at or below the speed :func:`bec_train_speed_mps` gives (all
    alike), one per faster speed. Equal to the direct computation: each envelope's least is the least over its
    targets (CRV-16), and subtracting one offset from several locations keeps their order (exactly, rounding
    included), so the least of the curves is the curve of the least; the MRSP at the front is read by bisection
    (MRSP-08)."""
    ahead = targets_ahead(o, prepared, bisect.bisect_right(prepared.decrease_starts_m, max_safe_front_m))
    ebd_m = envelope_location_m(o, ahead.every, speed_mps)
    alike = bisect.bisect_right(ahead.speeds_mps, bec_train_speed_mps(o, t, n, speed_mps, a_est_mps2))
    groups = [(ahead.of_speed[alike - 1], ahead.alike[alike - 1])] if alike else []
    groups += zip(ahead.of_speed[alike:], ahead.alone[alike:], strict=True)
    ebi_m = []
    for target, envelope in groups:
        v_bec, d_bec = bec_speed_and_distance(o, t, n, target, speed_mps, a_est_mps2)
        ebi_m.append(envelope_location_m(o, envelope, v_bec) - d_bec)
    curve = curves_from_ebd_and_ebi(o, t, n, lambda: ebd_m, o.min(*ebi_m), speed_mps)
    ceiling = ceilings(o, n, value_at_bisected(o, prepared.horizon.mrsp, max_safe_front_m))
    return exceedances(o, curve, ceiling, max_safe_front_m, speed_mps), curve, ceiling


__all__ = [
    "ENVELOPE_FLOAT_SLACK_M",
    "ENVELOPE_STEP_MPS",
    "PREPARED_CONVERTED_CURVES",
    "PREPARED_CURVES",
    "PREPARED_STEPPED_CURVES",
    "TABLE_ORDER",
    "TABLE_ORDER_CONVERTED",
    "TABLE_ORDER_STEPPED",
    "BrakingTable",
    "CurveEnvelope",
    "PreparedHorizon",
    "SpeedPair",
    "TableLocationPair",
    "TargetsAhead",
    "braking_table",
    "curve_envelope",
    "envelope_band",
    "envelope_grid_mps",
    "envelope_location_m",
    "prepare_horizon",
    "prepared_curve_locations",
    "supervise_prepared",
    "table_location_m",
    "tabled_ebd_location_m",
    "targets_ahead",
]
