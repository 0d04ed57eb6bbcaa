"""``atcs bench cycle``: one supervision cycle on a 1.5 km horizon as the profiles grow from 5 to 320 segments,
measured side by side in one run:

- *preprocessed*, the simulator's way (:mod:`atcs.model.prepared_curves`): each target's EBD tabled once per
  horizon, the envelopes of the targets ahead built once each time the train passes a target (both costs
  reported apart), each cycle a bisection in a few envelopes;
- *direct*: :func:`~atcs.model.dynamic_profile.supervise_position`, every target's EBD walked twice a cycle;
- *per-metre arrays*, the strongest simple alternative: each target's EBD integrated metre by metre with
  ``np.cumsum`` once per horizon, each cycle the least over the targets ahead at the front plus each curve's
  offset.

Warm-up first, then each cycle's time is the median of repeated runs; CPU time beside wall time. The preprocessed
and direct curves must be equal to the last bit (CRV-13, CRV-16 and MRSP-08 prove what makes them so on exact
numbers); the arrays' EBI and SBI decisions must agree with them except within their 1 m rounding of a curve. Then
the closed-loop proof time.
"""

from __future__ import annotations

import bisect
import statistics
import time
from collections.abc import Callable
from dataclasses import fields, replace

import numpy as np
from rich.console import Console
from rich.table import Table

from atcs.model.curves import adhesion_factor, bec_speed_and_distance, gradient_acceleration_mps2
from atcs.model.dynamic_profile import Horizon, ceilings, supervise_position, supervised_targets
from atcs.model.ops.floating import FLOAT
from atcs.model.prepared_curves import prepare_horizon, supervise_prepared, targets_ahead
from atcs.model.profile import gradient_profile, speed_profile, value_at
from atcs.model.restrictions import as_float
from atcs.model.train_data import seed000_train, subset026_national
from atcs.proofs.bench.timing import median_seconds

CYCLE_S = 0.1
HORIZON_M = 1500
SEGMENT_COUNTS = (5, 20, 80, 320)
"""Speed segments and gradient segments (each) on the horizon."""
REPEATS = 5
"""Timed runs of each cycle: its time is their median."""


def synthetic_horizon(rng: np.random.Generator, segments: int = 20, front_m: float = 0.0) -> Horizon:
    """``segments`` speed and ``segments`` gradient segments over 1.5 km (breakpoints on a 1 m grid), limits of
    40 to 80 km/h and gradients of -10 to 10 per mille; the EoA at the horizon's end (float data)."""
    line_m = front_m + HORIZON_M + 100
    grid = np.arange(1, HORIZON_M)
    mrsp_starts = [0, *sorted(rng.choice(grid, segments - 1, replace=False).tolist())]
    gradient_starts = [0, *sorted(rng.choice(grid, segments - 1, replace=False).tolist())]
    limits = rng.choice([40, 50, 60, 70, 80], segments).tolist()
    gradients = rng.integers(-10, 11, segments).tolist()
    mrsp = speed_profile("MRSP", [front_m + s for s in mrsp_starts], limits, line_m)
    gradient = gradient_profile("gradient", [front_m + s for s in gradient_starts], gradients, line_m)
    return Horizon(as_float(mrsp), as_float(gradient), front_m + HORIZON_M, 0.0)


class PerMetreCurves:
    """The per-metre alternative, cached per horizon: the EBD's squared speed at every metre from the horizon's
    start, each target's integrated backward with ``np.cumsum`` (from its foot speed at its location; the
    deceleration of the bench train's one-step emergency brake plus the metre's gradient). A cycle takes the
    least over the targets ahead of the front at the front plus each curve's offset (1 m resolution)."""

    def __init__(self, t, n, horizon: Horizon):
        if len(t.emergency_decelerations_mps2) != 1:
            raise ValueError("the per-metre baseline integrates a one-step emergency brake")
        self.t, self.n, self.horizon = t, n, horizon
        self.targets = supervised_targets(FLOAT, n, horizon, -1.0)
        self.metres = np.arange(0.0, float(horizon.eoa_m) + 1)
        g_index = np.searchsorted(np.asarray(horizon.gradient.starts_m), self.metres, side="right") - 1
        a_gradient = np.array([gradient_acceleration_mps2(FLOAT, t, g) for g in horizon.gradient.values])[g_index]
        a_safe = adhesion_factor(FLOAT, t, n) * float(t.emergency_decelerations_mps2[0]) + a_gradient
        locations = np.array([float(g.location_m) for g in self.targets])[:, None]
        feet2 = np.array([float(g.ebd_foot_mps) ** 2 for g in self.targets])[:, None]
        rise = 2 * a_safe * np.clip(locations - self.metres, 0.0, 1.0)  # each metre's rise, behind each target
        self.ebd2 = feet2 + np.cumsum(rise[:, ::-1], axis=1)[:, ::-1]  # by target: the foot speed past it
        self.starts_m = np.array([float(g.location_m) for g in self.targets])

    def cycle(self, front_m: float, speed_mps: float, a_est_mps2: float) -> dict[str, bool]:
        """The EBI and SBI decisions at the front, over the targets ahead of it (those behind no longer bind)."""
        first = int(np.searchsorted(self.starts_m[:-1], front_m, side="right"))
        v_bec, d_bec = bec_speed_and_distance(FLOAT, self.t, self.n, self.targets[-1], speed_mps, a_est_mps2)
        last = len(self.metres) - 1

        def over(offset_m: float) -> bool:
            return bool(self.ebd2[first:, min(int(front_m + d_bec + offset_m), last)].min() < v_bec * v_bec)

        ceiling = ceilings(FLOAT, self.n, value_at(FLOAT, self.horizon.mrsp, front_m))
        return {
            "ebi": over(0.0) or speed_mps > ceiling.ebi_mps,
            "sbi": over(speed_mps * self.t.t_bs_s) or speed_mps > ceiling.sbi_mps,
        }


def bench_cycle(
    console: Console,
    cycles: int = 60,
    segment_counts: tuple[int, ...] = SEGMENT_COUNTS,
    prove_closed_loop: bool = True,
    progress: Callable[[int, int], None] = lambda done, total: None,
) -> dict[str, float]:
    """One supervision cycle, preprocessed curves against the direct walk and per-metre arrays, 5 to 320
    segments; the closed-loop proofs."""
    t, n = _floats(seed000_train()), _floats(subset026_national())
    a_est = float(t.max_acceleration_mps2)
    proofs = _closed_loop_properties() if prove_closed_loop else []
    total, done = cycles * len(segment_counts) + len(proofs), 0
    results: dict[str, float] = {"agree": 0, "compared": 0}
    rows = []
    cpu0 = time.process_time()
    wall0 = time.perf_counter()
    for segments in segment_counts:
        rng = np.random.default_rng(20261122 + segments)
        cases = [
            (synthetic_horizon(rng, segments), float(rng.uniform(0, 1200)), float(rng.uniform(0, 80 / 3.6)))
            for _ in range(cycles)
        ]
        timing = {key: [] for key in ("prepared", "direct", "per_metre", "prepare", "envelopes", "per_metre_prepare")}
        targets = []
        for horizon, front, speed in cases:
            progress(done, total)
            done += 1
            prepared = prepare_horizon(FLOAT, t, n, horizon)  # warm-up, and the tables the cycle uses
            arrays = PerMetreCurves(t, n, horizon)
            timing["prepare"].append(median_seconds(lambda h=horizon: prepare_horizon(FLOAT, t, n, h), 1))
            timing["per_metre_prepare"].append(median_seconds(lambda h=horizon: PerMetreCurves(t, n, h), 1))
            first = bisect.bisect_right(prepared.decrease_starts_m, front)
            timing["envelopes"].append(
                median_seconds(lambda p=prepared, k=first: targets_ahead(FLOAT, replace(p, envelopes={}), k), 1)
            )
            fast = supervise_prepared(FLOAT, t, n, prepared, front, speed, a_est)
            slow = supervise_position(FLOAT, t, n, horizon, front, speed, a_est)
            decisions = arrays.cycle(front, speed, a_est)
            if fast != slow:
                raise AssertionError(
                    f"bench cycle: preprocessed and direct curves differ at {segments} segments, front {front} m, "
                    f"speed {speed} m/s: {fast[1]} against {slow[1]}"
                )
            for name in ("ebi", "sbi"):
                results["compared"] += 1
                same = getattr(slow[0], f"over_{name}") == decisions[name]
                results["agree"] += same
                if not same and abs(getattr(slow[1], f"{name}_m") - front) > 1.0:
                    raise AssertionError(
                        f"bench cycle: the per-metre arrays disagree on {name} at {segments} segments, front "
                        f"{front} m, speed {speed} m/s"
                    )
            timing["prepared"].append(
                median_seconds(
                    lambda p=prepared, f=front, v=speed: supervise_prepared(FLOAT, t, n, p, f, v, a_est), REPEATS
                )
            )
            timing["direct"].append(
                median_seconds(
                    lambda h=horizon, f=front, v=speed: supervise_position(FLOAT, t, n, h, f, v, a_est), REPEATS
                )
            )
            timing["per_metre"].append(median_seconds(lambda a=arrays, f=front, v=speed: a.cycle(f, v, a_est), REPEATS))
            targets.append(len(supervised_targets(FLOAT, n, horizon, front)))
        medians = {k: statistics.median(v) for k, v in timing.items()}
        for key, value in medians.items():
            results[f"{segments}_{key}_s"] = value
        rows.append((segments, statistics.median(targets), medians))
    results["cpu_s"] = time.process_time() - cpu0
    results["wall_s"] = time.perf_counter() - wall0
    _print(console, cycles, rows, results)
    if proofs:
        results.update(_closed_loop_proofs(console, proofs, lambda k: progress(done + k, total)))
    return results


def _print(console: Console, cycles: int, rows, results) -> None:
    table = Table(
        title=f"bench cycle: one supervision cycle on a {HORIZON_M} m horizon, float backend (medians of {cycles} "
        f"random cycles, each the median of {REPEATS} runs)"
    )
    for col in (
        "segments",
        "targets ahead",
        "preprocessed (µs)",
        "direct (µs)",
        "per-metre arrays (µs)",
        "direct / preprocessed",
        "tables per MA (µs)",
        "envelopes (µs)",
        "arrays per MA (µs)",
    ):
        table.add_column(col, justify="right")
    for segments, targets, m in rows:
        table.add_row(
            f"{segments} + {segments}",
            f"{targets:g}",
            f"{m['prepared'] * 1e6:,.1f}",
            f"{m['direct'] * 1e6:,.1f}",
            f"{m['per_metre'] * 1e6:,.1f}",
            f"{m['direct'] / m['prepared']:,.1f}x",
            f"{m['prepare'] * 1e6:,.0f}",
            f"{m['envelopes'] * 1e6:,.0f}",
            f"{m['per_metre_prepare'] * 1e6:,.0f}",
        )
    console.print(table)
    console.print(
        f"preprocessed curves equal the direct walk's in every cycle, to the last bit; the per-metre arrays' EBI "
        f"and SBI decisions agree in {results['agree']} of {results['compared']} checks (any difference within their "
        f"1 m rounding of a curve); {results['cpu_s']:.1f} s CPU, {results['wall_s']:.1f} s wall"
    )


def _floats(data):
    return type(data)(**{f.name: _float(getattr(data, f.name)) for f in fields(data)})


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
