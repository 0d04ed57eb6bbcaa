"""``atcs bench cycle``: one full supervision cycle on a 1.5 km horizon, from segments as the
model computes it, against a per-metre array formulation of the same curves; and the closed-loop proof
time. Measured side by side in one run; the two formulations' decisions are checked to agree."""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np
from rich.console import Console
from rich.table import Table

from atcs.model.curves import adhesion_factor, bec_speed_and_distance, gradient_acceleration_mps2
from atcs.model.dynamic_profile import Horizon, ceilings, supervise_position, supervised_targets
from atcs.model.ops.floating import FLOAT
from atcs.model.profile import gradient_profile, speed_profile, value_at
from atcs.model.restrictions import as_float
from atcs.model.supervision import SupervisionParams, SupervisionState, supervise
from atcs.model.train_data import seed000_train, subset026_national

CYCLE_S = 0.1
HORIZON_M = 1500
SEGMENTS = 20


def synthetic_horizon(rng: np.random.Generator, front_m: float = 0.0) -> Horizon:
    """About 20 speed and 20 gradient segments over 1.5 km, the EoA at its end (float data)."""
    line_m = front_m + HORIZON_M + 100
    mrsp_starts = [0, *sorted(rng.choice(np.arange(50, HORIZON_M, 25), SEGMENTS - 1, replace=False).tolist())]
    gradient_starts = [0, *sorted(rng.choice(np.arange(50, HORIZON_M, 25), SEGMENTS - 1, replace=False).tolist())]
    limits = rng.choice([40, 50, 60, 70, 80], SEGMENTS).tolist()
    gradients = rng.integers(-10, 11, SEGMENTS).tolist()
    mrsp = speed_profile("MRSP", [front_m + s for s in mrsp_starts], limits, line_m)
    gradient = gradient_profile("gradient", [front_m + s for s in gradient_starts], gradients, line_m)
    return Horizon(as_float(mrsp), as_float(gradient), front_m + HORIZON_M, 0.0)


def segment_cycle(t, n, horizon: Horizon, front_m: float, speed_mps: float, a_est_mps2: float):
    """The model's cycle: targets, curves at the train's position and speed, ceilings, commands."""
    over, curve, _ = supervise_position(FLOAT, t, n, horizon, front_m, speed_mps, a_est_mps2)
    state = SupervisionState(eb_latched=False, sb_latched=False)
    _, commands = supervise(FLOAT, SupervisionParams(True), state, over, speed_mps == 0, False, True)
    return over, curve, commands


def per_metre_cycle(t, n, horizon: Horizon, front_m: float, speed_mps: float, a_est_mps2: float):
    """The array formulation: each target's EBD integrated backward metre by metre (all targets at
    once, numpy; the foot speed from the target on), their minimum as the EBD speed per metre, then
    each curve checked by a lookup at the distance its offsets put it ahead of the front."""
    targets = supervised_targets(FLOAT, n, horizon, front_m)
    start = int(np.floor(front_m))
    metres = np.arange(start, int(np.ceil(float(horizon.eoa_m))) + 1, dtype=float)
    g_index = np.searchsorted(np.asarray(horizon.gradient.starts_m), metres, side="right") - 1
    a_gradient = np.array([gradient_acceleration_mps2(FLOAT, t, g) for g in horizon.gradient.values])[g_index]
    k = adhesion_factor(FLOAT, t, n)
    step_speeds = np.asarray(t.emergency_speeds_mps, dtype=float)
    step_decels = k * np.asarray(t.emergency_decelerations_mps2, dtype=float)
    locations = np.array([float(g.location_m) for g in targets])
    feet2 = np.array([float(g.ebd_foot_mps) ** 2 for g in targets])
    v2 = np.empty((len(metres), len(targets)))
    current = feet2.copy()
    for i in range(len(metres) - 1, -1, -1):
        # at and past its location a target's EBD holds its foot speed (the curves stay monotone)
        step_m = np.clip(locations - metres[i], 0.0, 1.0)
        a_brake = step_decels[np.searchsorted(step_speeds, np.sqrt(current), side="right") - 1]
        current = np.where(step_m > 0, current + 2 * (a_brake + a_gradient[i]) * step_m, feet2)
        v2[i] = current
    ebd_mps = np.sqrt(v2.min(axis=1))

    v_bec, d_bec = bec_speed_and_distance(FLOAT, t, n, targets[-1], speed_mps, a_est_mps2)

    def over(offset_m):
        index = min(int(front_m + d_bec + offset_m) - start, len(metres) - 1)
        return bool(ebd_mps[index] < v_bec)

    ceiling = ceilings(FLOAT, n, value_at(FLOAT, horizon.mrsp, front_m))
    return {
        "ebi": over(0.0) or speed_mps > ceiling.ebi_mps,
        "sbi": over(speed_mps * t.t_bs_s) or speed_mps > ceiling.sbi_mps,
    }


def bench_cycle(
    console: Console,
    cycles: int = 60,
    prove_closed_loop: bool = True,
    progress: Callable[[int, int], None] = lambda done, total: None,
) -> dict[str, float]:
    """Median time of one supervision cycle, segments against per-metre arrays; the closed-loop proofs."""
    rng = np.random.default_rng(20261122)
    t, n = seed000_train(), subset026_national()
    t_f = type(t)(**{f: _float(getattr(t, f)) for f in t.__dataclass_fields__})
    n_f = type(n)(**{f: _float(getattr(n, f)) for f in n.__dataclass_fields__})
    a_est = float(t.max_acceleration_mps2)
    cases = []
    for _ in range(cycles):
        horizon = synthetic_horizon(rng)
        cases.append((horizon, float(rng.uniform(0, 1200)), float(rng.uniform(0, 80 / 3.6))))
    segment_s, metre_s, agree, compared, targets = [], [], 0, 0, []
    proofs = _closed_loop_properties() if prove_closed_loop else []
    total = cycles + len(proofs)
    for horizon, front, speed in cases:
        progress(len(segment_s), total)
        t0 = time.perf_counter()
        over, curve, _ = segment_cycle(t_f, n_f, horizon, front, speed, a_est)
        t1 = time.perf_counter()
        arrays = per_metre_cycle(t_f, n_f, horizon, front, speed, a_est)
        t2 = time.perf_counter()
        segment_s.append(t1 - t0)
        metre_s.append(t2 - t1)
        targets.append(len(supervised_targets(FLOAT, n_f, horizon, front)))
        for name in ("ebi", "sbi"):
            compared += 1
            same = getattr(over, f"over_{name}") == arrays[name]
            agree += same
            if not same and abs(getattr(curve, f"{name}_m") - front) > 1.0:  # beyond the arrays' 1 m rounding
                raise AssertionError(
                    f"bench cycle: the formulations disagree on {name} at front {front} m, speed {speed} m/s"
                )
    seg, arr = float(np.median(segment_s)), float(np.median(metre_s))
    table = Table(
        title=f"bench cycle: one supervision cycle, {HORIZON_M} m horizon, {SEGMENTS} speed and "
        f"{SEGMENTS} gradient segments, {np.median(targets):g} targets (median of {cycles})"
    )
    for col in ("formulation", "per cycle (ms)", "share of 100 ms cycle", "vs segments"):
        table.add_column(col, justify="left" if col == "formulation" else "right")
    table.add_row("segments (the model, float)", f"{seg * 1e3:.3f}", f"{seg / CYCLE_S:.2%}", "1.0x")
    table.add_row("per-metre arrays (numpy)", f"{arr * 1e3:.3f}", f"{arr / CYCLE_S:.2%}", f"{arr / seg:.1f}x")
    console.print(table)
    console.print(
        f"EBI and SBI decisions agree in {agree} of {compared} checks "
        "(any difference within the arrays' 1 m rounding of a curve)"
    )
    results = {"segments_s": seg, "per_metre_s": arr, "agree": agree, "compared": compared}
    if proofs:
        results.update(_closed_loop_proofs(console, proofs, lambda done: progress(cycles + done, total)))
    return results


def _float(value):
    if isinstance(value, tuple):
        return tuple(_float(v) for v in value)
    return value if isinstance(value, bool) else float(value)


def _closed_loop_properties() -> list:
    from atcs.properties import select

    return select("closed_loop.*")


def _closed_loop_proofs(console: Console, props: list, progress: Callable[[int], None]) -> dict[str, float]:
    from atcs.proofs.engine.suite import run

    t0 = time.perf_counter()
    results = []
    for result in run(props, timeout_s=600, jobs=1):
        results.append(result)
        progress(len(results))
    wall = time.perf_counter() - t0
    table = Table(title=f"closed-loop proofs: {len(props)} properties in {wall:.1f} s (one process)")
    for col in ("property", "status", "k", "seconds"):
        table.add_column(col, justify="left" if col in ("property", "status") else "right")
    for r in sorted(results, key=lambda r: r.name):
        table.add_row(r.name, r.status, "" if r.k is None else str(r.k), f"{r.seconds:.2f}")
    console.print(table)
    return {"closed_loop_proof_s": wall}
