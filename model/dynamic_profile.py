"""The dynamic speed profile over the horizon: targets from the MRSP and the MA, the most restrictive
curve at the train's position, the ceilings, and what supervision compares each cycle (seed 000 §2.4,
002 §3.2; docs/design.md reference formulas).

- Targets: every speed *decrease* of the MRSP ahead of the max safe front (its EBD ends at
  ``V_target + dV_ebi(V_target)``, Subset-026 §3.13.8.3) and the end of authority (its EBD ends
  at the MA's target speed ``vMA``). A decrease at or behind the max safe front already binds
  the train: the ceiling supervises it.
- The most restrictive curve at a speed is the one nearest the train: each curve's location
  (:func:`~atcs.model.curves.curve_locations`) is the minimum over the targets.
- The ceilings: MRSP + dV_warning / dV_sbi / dV_ebi at the max safe front (the MRSP given
  here is the train-length compensated one that :mod:`atcs.model.mrsp` produces).

:func:`limits_at` and :func:`exceedances` are what supervision runs each cycle, computed from
segments (no per-metre arrays) and written once over the ops; the closed-loop node uses them
with its one target. The number of targets depends on the data, so :func:`supervised_targets`
takes concrete profiles. :func:`curve_speeds_at` (the speed of each curve at a location) is a
concrete query on top; :func:`atcs.sim.plots.sampled_curves` samples each curve for plotting.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Generic

from atcs.model.curves import FAR_M, CurveLocations, Target, ceiling_offset_mps, curve_locations
from atcs.model.node import Stateless, stateless_node
from atcs.model.ops import B, N, Ops
from atcs.model.ops.floating import FLOAT
from atcs.model.profile import Profile, value_at
from atcs.model.supervision import Exceedances
from atcs.model.train_data import NationalData, TrainData

CURVE_NAMES = tuple(f.name.removesuffix("_m") for f in fields(CurveLocations))
"""``ebd``, ``ebi``, ``sbi``, ``warning``, ``permitted``, ``indication``: farthest first."""


@dataclass(frozen=True)
class Ceilings(Generic[N]):
    """The speed limits of the ceiling supervision at the train's position (m/s)."""

    permitted_mps: N
    warning_mps: N
    sbi_mps: N
    ebi_mps: N


@dataclass(frozen=True)
class Horizon(Generic[N]):
    """What the ATP supervises ahead: the MRSP (train-length compensated), the compensated gradient
    profile, and the movement authority ``(eoa_m, eoa_speed_mps)`` (dMA, vMA)."""

    mrsp: Profile
    gradient: Profile
    eoa_m: N
    eoa_speed_mps: N


@dataclass(frozen=True)
class CurveSpeeds(Generic[N]):
    """The speed of each curve at one location (m/s), the ceilings included."""

    ebd_mps: N
    ebi_mps: N
    sbi_mps: N
    warning_mps: N
    permitted_mps: N
    indication_mps: N


def ebd_foot_mps(o: Ops, n: NationalData, speed_mps):
    """Where the EBD of a speed decrease to ``speed_mps`` ends: ``V_target + dV_ebi(V_target)``."""
    return speed_mps + ceiling_offset_mps(
        o, speed_mps, n.dv_ebi_min_mps, n.dv_ebi_max_mps, n.v_ebi_min_mps, n.v_ebi_max_mps
    )


def ceilings(o: Ops, n: NationalData, mrsp_mps) -> Ceilings:
    """MRSP + dV for each ceiling (dV speed-dependent between its min and max)."""

    def ceiling(dv_min, dv_max, v_min, v_max):
        return mrsp_mps + ceiling_offset_mps(o, mrsp_mps, dv_min, dv_max, v_min, v_max)

    return Ceilings(
        permitted_mps=mrsp_mps,
        warning_mps=ceiling(n.dv_warning_min_mps, n.dv_warning_max_mps, n.v_warning_min_mps, n.v_warning_max_mps),
        sbi_mps=ceiling(n.dv_sbi_min_mps, n.dv_sbi_max_mps, n.v_sbi_min_mps, n.v_sbi_max_mps),
        ebi_mps=ceiling(n.dv_ebi_min_mps, n.dv_ebi_max_mps, n.v_ebi_min_mps, n.v_ebi_max_mps),
    )


def decrease_targets(o: Ops, n: NationalData, starts_m, values_mps, eoa_m, max_safe_front_m):
    """For each MRSP segment after the first, ``(supervised, target)``: the segment's start, value and EBD foot
    speed, and whether it is a speed decrease ahead of ``max_safe_front_m`` and short of ``eoa_m`` (only those are
    supervised as targets)."""
    return tuple(
        (
            o.and_(v < before, max_safe_front_m < start, start < eoa_m),
            Target(start, v, ebd_foot_mps(o, n, v)),
        )
        for start, before, v in zip(starts_m[1:], values_mps, values_mps[1:], strict=False)
    )


def eoa_target(o: Ops, n: NationalData, eoa_m, eoa_speed_mps) -> Target:
    """The end of authority as a target: its EBD ends at standstill there (the SvL, Subset-026 §3.13.8.3.2); an
    EoA with a target speed above 0 (a limit of authority) is supervised as a speed decrease, its EBD passing
    ``V_target + dV_ebi(V_target)`` at it (§3.13.8.3.1)."""
    foot = o.ite(eoa_speed_mps > o.const(0), ebd_foot_mps(o, n, eoa_speed_mps), eoa_speed_mps)
    return Target(eoa_m, eoa_speed_mps, foot)


def supervised_targets(o: Ops, n: NationalData, horizon: Horizon, max_safe_front_m) -> tuple[Target, ...]:
    """The MRSP's speed decreases ahead of ``max_safe_front_m`` and short of the EoA
    (:func:`decrease_targets`), then the EoA (:func:`eoa_target`); concrete profiles: the number of targets
    depends on the data (the node :data:`TARGETS` proves the choice and the foot speeds for symbolic ones)."""
    mrsp = horizon.mrsp
    decreases = decrease_targets(o, n, mrsp.starts_m, mrsp.values, horizon.eoa_m, max_safe_front_m)
    return (
        *(target for supervised, target in decreases if supervised),
        eoa_target(o, n, horizon.eoa_m, horizon.eoa_speed_mps),
    )


def most_restrictive(o: Ops, per_target: tuple[CurveLocations, ...]) -> CurveLocations:
    """Each curve's nearest location over the targets."""
    return CurveLocations(**{f.name: o.min(*(getattr(c, f.name) for c in per_target)) for f in fields(CurveLocations)})


def limits_at(
    o: Ops,
    t: TrainData,
    n: NationalData,
    gradient: Profile,
    targets: tuple[Target, ...],
    mrsp_mps,
    speed_mps,
    a_est_mps2,
) -> tuple[CurveLocations, Ceilings]:
    """The curves' locations at ``speed_mps`` (the most restrictive target's) and the ceilings for
    the MRSP value ``mrsp_mps`` at the train's position."""
    curves = most_restrictive(
        o, tuple(curve_locations(o, t, n, gradient, target, speed_mps, a_est_mps2) for target in targets)
    )
    return curves, ceilings(o, n, mrsp_mps)


def exceedances(o: Ops, curve: CurveLocations, ceiling: Ceilings, front_m, speed_mps) -> Exceedances:
    """Which limits the train is over: its max safe front past a curve's location at its speed, or
    its speed over a ceiling (seed 000 §2.4: supervision at the current position)."""
    return Exceedances(
        over_permitted=o.or_(front_m > curve.permitted_m, speed_mps > ceiling.permitted_mps),
        over_warning=o.or_(front_m > curve.warning_m, speed_mps > ceiling.warning_mps),
        over_sbi=o.or_(front_m > curve.sbi_m, speed_mps > ceiling.sbi_mps),
        over_ebi=o.or_(front_m > curve.ebi_m, speed_mps > ceiling.ebi_mps),
    )


def supervise_position(
    o: Ops, t: TrainData, n: NationalData, horizon: Horizon, max_safe_front_m, speed_mps, a_est_mps2
) -> tuple[Exceedances, CurveLocations, Ceilings]:
    """One cycle's speed and distance monitoring on concrete data: targets, the curves at the train's
    speed, the ceilings at its max safe front, and the exceedances (what :func:`supervise` decides on)."""
    targets = supervised_targets(o, n, horizon, max_safe_front_m)
    mrsp_mps = value_at(o, horizon.mrsp, max_safe_front_m)
    curve, ceiling = limits_at(o, t, n, horizon.gradient, targets, mrsp_mps, speed_mps, a_est_mps2)
    return exceedances(o, curve, ceiling, max_safe_front_m, speed_mps), curve, ceiling


# --- concrete queries: the speed of each curve at a location, and the curves sampled for plots ---


def curve_ceiling(ceiling: Ceilings, name: str):
    return {"ebd": ceiling.ebi_mps, "ebi": ceiling.ebi_mps, "sbi": ceiling.sbi_mps, "warning": ceiling.warning_mps}.get(
        name, ceiling.permitted_mps
    )


def curve_speeds_at(
    t: TrainData, n: NationalData, horizon: Horizon, x_m, a_est_mps2, *, o: Ops = FLOAT, tolerance_mps=1e-6
) -> CurveSpeeds:
    """The speed of each curve at ``x_m``: the highest speed whose curve location is at or beyond
    ``x_m`` (bisection; every curve's location falls as the speed rises), capped by its ceiling
    (the EBD and EBI by MRSP + dV_ebi, permitted and indication by the MRSP itself). A target constrains only
    speeds above its own, so every curve of a target ends at the target's speed (concrete backends only)."""
    if not tolerance_mps > 0:
        raise ValueError(f"tolerance_mps must be positive, got {tolerance_mps!r}")
    targets = supervised_targets(o, n, horizon, x_m)
    ceiling = ceilings(o, n, value_at(o, horizon.mrsp, x_m))
    speeds = {}
    for name in CURVE_NAMES:
        top = curve_ceiling(ceiling, name)

        def location(v, name=name):
            per_target = [
                curve_locations(o, t, n, horizon.gradient, g, v, a_est_mps2) for g in targets if v > g.speed_mps
            ]
            return min((getattr(c, f"{name}_m") for c in per_target), default=o.const(FAR_M))

        if location(top) >= x_m:
            speeds[name] = top
            continue
        low, high = o.const(0), top
        if location(low) < x_m:  # even standstill is over the curve here (past the EoA)
            speeds[name] = low
            continue
        while high - low > tolerance_mps:
            mid = (low + high) / 2
            low, high = (mid, high) if location(mid) >= x_m else (low, mid)
        speeds[name] = low
    return CurveSpeeds(**{f"{name}_mps": v for name, v in speeds.items()})


# --- the choice of the most restrictive target as a sub-function node -------------------------------------------


@dataclass(frozen=True)
class NoData(Generic[N]):
    """No data: the sub-functions below are pure functions of their inputs."""


@dataclass(frozen=True)
class TargetCurves(Generic[N]):
    """Each curve's location, one per supervised target (the same speed)."""

    target_ebd_m: tuple[N, ...]
    target_ebi_m: tuple[N, ...]
    target_sbi_m: tuple[N, ...]
    target_warning_m: tuple[N, ...]
    target_permitted_m: tuple[N, ...]
    target_indication_m: tuple[N, ...]


@dataclass(frozen=True)
class SupervisedCurves(CurveLocations[N]):
    pass


def most_restrictive_step(o: Ops, p: NoData, s: Stateless, i: TargetCurves):
    per_target = tuple(
        CurveLocations(**{f.name: getattr(i, f"target_{f.name}")[j] for f in fields(CurveLocations)})
        for j in range(len(i.target_ebd_m))
    )
    return s, SupervisedCurves(**vars(most_restrictive(o, per_target)))


MOST_RESTRICTIVE = stateless_node(
    name="most_restrictive",
    params=NoData,
    inputs=TargetCurves,
    outputs=SupervisedCurves,
    step=most_restrictive_step,
    seed="000 §2.4, 003 §2.2",
    sizes={f"target_{f.name}": 3 for f in fields(CurveLocations)},
)
""":func:`most_restrictive` as a sub-function of its own, for three targets, every location symbolic (the
closed-loop and two-train nodes supervise one target, the end of authority)."""


# --- the limits exceeded as a sub-function node ------------------------------------------------------------------


@dataclass(frozen=True)
class LimitQuery(Generic[N]):
    """The max safe front, the measured speed, each curve's location at that speed and each ceiling."""

    max_safe_front_m: N
    measured_speed_mps: N
    permitted_location_m: N
    warning_location_m: N
    sbi_location_m: N
    ebi_location_m: N
    permitted_ceiling_mps: N
    warning_ceiling_mps: N
    sbi_ceiling_mps: N
    ebi_ceiling_mps: N


@dataclass(frozen=True)
class LimitsExceeded(Exceedances[N, B]):
    pass


def exceedances_step(o: Ops, p: NoData, s: Stateless, i: LimitQuery):
    unread = o.const(FAR_M)  # the EBD and the indication curve are not supervised limits: exceedances never reads them
    curve = CurveLocations(
        ebd_m=unread,
        ebi_m=i.ebi_location_m,
        sbi_m=i.sbi_location_m,
        warning_m=i.warning_location_m,
        permitted_m=i.permitted_location_m,
        indication_m=unread,
    )
    ceiling = Ceilings(
        permitted_mps=i.permitted_ceiling_mps,
        warning_mps=i.warning_ceiling_mps,
        sbi_mps=i.sbi_ceiling_mps,
        ebi_mps=i.ebi_ceiling_mps,
    )
    return s, LimitsExceeded(**vars(exceedances(o, curve, ceiling, i.max_safe_front_m, i.measured_speed_mps)))


EXCEEDANCES = stateless_node(
    name="exceedances",
    params=NoData,
    inputs=LimitQuery,
    outputs=LimitsExceeded,
    step=exceedances_step,
    seed="000 §2.4.3",
)
""":func:`exceedances` as a sub-function of its own, every location, ceiling, front and speed symbolic (in the closed
loop a speed at exactly a ceiling is reached only tens of cycles after power-up)."""


# --- the targets of a horizon as a sub-function node ---------------------------------------------------------------

TARGET_SEGMENTS = 4
"""The MRSP segments the proofs cover (every start and value symbolic): three boundaries, each a possible target."""


@dataclass(frozen=True)
class TargetParams(NationalData[N, B]):
    mrsp_starts_m: tuple[N, ...]
    mrsp_values_mps: tuple[N, ...]
    eoa_m: N
    eoa_speed_mps: N


@dataclass(frozen=True)
class TargetQuery(Generic[N]):
    max_safe_front_m: N


@dataclass(frozen=True)
class HorizonTargets(Generic[N, B]):
    """Per MRSP boundary (segment 1 on): supervised as a target or not, and its location, speed and EBD foot speed;
    the EoA's target."""

    supervised: tuple[B, ...]
    target_location_m: tuple[N, ...]
    target_speed_mps: tuple[N, ...]
    target_ebd_foot_mps: tuple[N, ...]
    eoa_target_location_m: N
    eoa_target_speed_mps: N
    eoa_target_ebd_foot_mps: N


def targets_step(o: Ops, p: TargetParams, s: Stateless, i: TargetQuery):
    decreases = decrease_targets(o, p, p.mrsp_starts_m, p.mrsp_values_mps, p.eoa_m, i.max_safe_front_m)
    eoa = eoa_target(o, p, p.eoa_m, p.eoa_speed_mps)
    return s, HorizonTargets(
        supervised=tuple(supervised for supervised, _ in decreases),
        target_location_m=tuple(target.location_m for _, target in decreases),
        target_speed_mps=tuple(target.speed_mps for _, target in decreases),
        target_ebd_foot_mps=tuple(target.ebd_foot_mps for _, target in decreases),
        eoa_target_location_m=eoa.location_m,
        eoa_target_speed_mps=eoa.speed_mps,
        eoa_target_ebd_foot_mps=eoa.ebd_foot_mps,
    )


TARGETS = stateless_node(
    name="targets",
    params=TargetParams,
    inputs=TargetQuery,
    outputs=HorizonTargets,
    step=targets_step,
    seed="000 §2.4, 002 §3.2; Subset-026 §3.13.8.3",
    sizes={
        "mrsp_starts_m": TARGET_SEGMENTS,
        "mrsp_values_mps": TARGET_SEGMENTS,
        **{
            name: TARGET_SEGMENTS - 1
            for name in ("supervised", "target_location_m", "target_speed_mps", "target_ebd_foot_mps")
        },
    },
)
"""The targets :func:`supervised_targets` takes from a horizon, for an MRSP of :data:`TARGET_SEGMENTS` segments
and any EoA, front and national data: each boundary supervised or not, and each target's foot speed."""
