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
    braking_cells,
    curve_gradient,
    curve_target,
    curves_from_ebd,
    safe_brake,
)
from atcs.model.dynamic_profile import Ceilings, Horizon, ceilings, exceedances, most_restrictive, supervised_targets
from atcs.model.node import Stateless, stateless_node
from atcs.model.ops import N, Ops
from atcs.model.profile import Profile, value_at
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


def prepared_curve_locations(
    o: Ops, t: TrainData, n: NationalData, target: Target, table: BrakingTable, speed_mps, a_est_mps2
) -> CurveLocations:
    """:func:`~atcs.model.curves.curve_locations` with the EBD looked up in the target's table."""
    return curves_from_ebd(
        o, t, n, target, speed_mps, a_est_mps2, lambda v: above_foot(o, target, v, table_location_m(o, table, v * v))
    )


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
parameters and query, for CRV-13 to CRV-15."""

PREPARED_STEPPED_CURVES = dataclasses.replace(
    PREPARED_CURVES, name="prepared_curves_stepped", sizes=STEPPED_CURVES.sizes
)
""":data:`PREPARED_CURVES` with the three-step emergency brake of :data:`~atcs.model.curves.STEPPED_CURVES`."""

PREPARED_CONVERTED_CURVES = dataclasses.replace(
    PREPARED_CURVES, name="prepared_curves_converted", sizes=CONVERTED_CURVES.sizes
)
""":data:`PREPARED_CURVES` with the four-step brakes of :data:`~atcs.model.curves.CONVERTED_CURVES`."""


# --- a horizon's tables, for supervision on concrete data ---------------------------------------------------------


def table_lowest_decel_mps2(o: Ops, table: BrakingTable):
    """The table's least deceleration: between two points of the curve, the squared speed rises by at least
    twice this times the distance (CRV-15)."""
    return o.min(*table.decel_mps2)


def nearest_locations_m(o: Ops, target: Target, lowest_decel_mps2, speed_mps, bec_speed_mps, bec_distance_m):
    """How near the train any curve of ``target`` can lie at ``speed_mps``: ``(EBD, EBI)`` at least ``location -
    v^2 / (2 * lowest deceleration)`` for the EBD's speed ``v`` (``V_bec`` for the EBI, less ``D_bec``), CRV-15.
    A larger ``V_bec`` or ``D_bec``, or a lower deceleration, gives a bound as true."""
    span = o.const(2) * lowest_decel_mps2
    ebd_m = target.location_m - speed_mps * speed_mps / span
    return ebd_m, target.location_m - bec_speed_mps * bec_speed_mps / span - bec_distance_m


@dataclass(frozen=True)
class PreparedHorizon(Generic[N]):
    """A horizon with every target's table: the MRSP's speed decreases short of the EoA, then the EoA (by
    location); the least deceleration of any table, and from each target on, the highest target speed."""

    horizon: Horizon
    decrease_starts_m: tuple[N, ...]
    targets: tuple[Target, ...]
    tables: tuple[BrakingTable, ...]
    lowest_decel_mps2: N
    top_speed_from_mps: tuple[N, ...]


def prepare_horizon(
    o: Ops, t: TrainData, n: NationalData, horizon: Horizon, reuse: PreparedHorizon | None = None
) -> PreparedHorizon:
    """Every target's table (concrete data): once per change of the MA, the MRSP or the train data. The tables of
    ``reuse`` whose target is unchanged are kept when only the EoA moved (the same MRSP, gradient and train)."""
    targets = supervised_targets(o, n, horizon, o.const(-FAR_M))
    kept = {}
    if reuse is not None and reuse.horizon.mrsp is horizon.mrsp and reuse.horizon.gradient is horizon.gradient:
        kept = dict(zip(reuse.targets, reuse.tables, strict=True))
    tables = tuple(kept.get(g) or braking_table(o, t, n, horizon.gradient, g) for g in targets)
    top, tops = targets[-1].speed_mps, []
    for g in reversed(targets):
        top = o.max(top, g.speed_mps)
        tops.append(top)
    return PreparedHorizon(
        horizon=horizon,
        decrease_starts_m=tuple(g.location_m for g in targets[:-1]),
        targets=targets,
        tables=tables,
        lowest_decel_mps2=o.min(*(table_lowest_decel_mps2(o, table) for table in tables)),
        top_speed_from_mps=tuple(reversed(tops)),
    )


def supervise_prepared(
    o: Ops, t: TrainData, n: NationalData, prepared: PreparedHorizon, max_safe_front_m, speed_mps, a_est_mps2
) -> tuple[Exceedances, CurveLocations, Ceilings]:
    """:func:`~atcs.model.dynamic_profile.supervise_position` on the tables: the targets ahead of the max safe
    front (a bisection), nearest first, each curve located in each one's table. Two shortcuts, each exact:

    - a target whose foot speed is at or above both the speed and the largest ``V_bec`` any target ahead gives
      constrains nothing (its curves lie at FAR_M, less ``D_bec``): it is set aside, and looked up only if no other
      target puts a curve nearer than FAR_M less the largest ``D_bec``;
    - the walk over the targets stops once none farther on can lie nearer than the curves found
      (:func:`nearest_locations_m` with that largest ``V_bec`` and ``D_bec``, those of the highest target speed
      ahead, and the least deceleration of any table), so only the targets within a braking distance of the
      nearest constraint are looked up."""
    first = bisect.bisect_right(prepared.decrease_starts_m, max_safe_front_m)
    targets = prepared.targets
    fastest = Target(targets[first].location_m, prepared.top_speed_from_mps[first], targets[first].ebd_foot_mps)
    v_bec, d_bec = bec_speed_and_distance(o, t, n, fastest, speed_mps, a_est_mps2)
    curve, set_aside = None, []
    for k in range(first, len(targets)):
        target = targets[k]
        if speed_mps <= target.ebd_foot_mps and v_bec <= target.ebd_foot_mps:
            set_aside.append(k)
            continue
        if curve is not None:
            ebd_m, ebi_m = nearest_locations_m(o, target, prepared.lowest_decel_mps2, speed_mps, v_bec, d_bec)
            if ebd_m >= curve.ebd_m and ebi_m >= curve.ebi_m:
                break
        curve = _nearer(o, curve, prepared_curve_locations(o, t, n, target, prepared.tables[k], speed_mps, a_est_mps2))
    if curve is None or not (curve.ebd_m < o.const(FAR_M) and curve.ebi_m < o.const(FAR_M) - d_bec):
        for k in set_aside:
            found = prepared_curve_locations(o, t, n, targets[k], prepared.tables[k], speed_mps, a_est_mps2)
            curve = _nearer(o, curve, found)
    ceiling = ceilings(o, n, value_at(o, prepared.horizon.mrsp, max_safe_front_m))
    return exceedances(o, curve, ceiling, max_safe_front_m, speed_mps), curve, ceiling


def _nearer(o: Ops, curve: CurveLocations | None, found: CurveLocations) -> CurveLocations:
    return found if curve is None else most_restrictive(o, (curve, found))


__all__ = [
    "PREPARED_CONVERTED_CURVES",
    "PREPARED_CURVES",
    "PREPARED_STEPPED_CURVES",
    "BrakingTable",
    "PreparedHorizon",
    "braking_table",
    "nearest_locations_m",
    "prepare_horizon",
    "prepared_curve_locations",
    "supervise_prepared",
    "table_location_m",
    "table_lowest_decel_mps2",
]
