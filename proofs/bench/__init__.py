"""Benchmarks: measured side by side in one run, reported as ratios (never as timed unit tests).

``BENCHMARKS`` registers them by name for ``atcs bench [NAME]``: each takes the console its tables go to and a
keyword ``progress`` (:data:`Progress`); the first line of each one's docstring is its summary in
``atcs bench --help``.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from fractions import Fraction

import numpy as np
from rich.console import Console
from rich.table import Table

from atcs.model.node import as_dict
from atcs.model.ops.exact import EXACT
from atcs.model.ops.floating import FLOAT
from atcs.model.profile import KMH_PER_MPS, Profile, speed_profile, value_at
from atcs.model.psl import Restriction, permanent_speed_limit, restricted
from atcs.model.restrictions import SpeedRestrictions, as_float, canonical
from atcs.model.supervision import SUPERVISION, SupervisionInputs, SupervisionParams, SupervisionState
from atcs.proofs.bench.cycle import bench_cycle
from atcs.proofs.bench.sim import bench_sim
from atcs.proofs.bench.sweep import bench_sweep
from atcs.proofs.bench.timing import median_seconds

CYCLE_S = 0.1  # one ATP cycle (seed 001)

Progress = Callable[[int, int], None]
"""``progress(done, total)``: how far a benchmark is, in units of its own (``atcs bench`` shows the time left)."""


def _supervision_inputs(trains: int, rng: np.random.Generator):
    permitted = rng.uniform(0, 25, trains)
    warning = permitted + rng.uniform(0, 1.5, trains)
    sbi = warning + rng.uniform(0, 1.5, trains)
    ebi = sbi + rng.uniform(0, 1.5, trains)
    speed = rng.uniform(0, 30, trains)
    return SupervisionInputs(
        speed_mps=speed,
        permitted_mps=permitted,
        warning_mps=warning,
        sbi_mps=sbi,
        ebi_mps=ebi,
        standstill=speed < 0.1,
        eb_release=rng.random(trains) < 0.5,
        position_valid=rng.random(trains) < 0.99,
    )


def bench_supervision(
    console: Console, trains: int = 1000, repeats: int = 7, progress: Progress = lambda done, total: None
) -> dict[str, float]:
    """One supervision cycle for a fleet: numpy batch vs scalar float loop vs exact Fractions."""
    rng = np.random.default_rng(20261122)
    batch = _supervision_inputs(trains, rng)
    fields = list(SUPERVISION.sorts("inputs"))
    scalars = [SupervisionInputs(**{f: getattr(batch, f)[t].item() for f in fields}) for t in range(trains)]
    exacts = [
        SupervisionInputs(**{f: (Fraction(v) if isinstance(v, float) else v) for f, v in as_dict(x).items()})
        for x in scalars
    ]
    params_batch = SupervisionParams(service_brake_fitted=True)
    state_batch = SupervisionState(eb_latched=np.zeros(trains, bool), sb_latched=np.zeros(trains, bool))
    state_one = SupervisionState(eb_latched=False, sb_latched=False)
    step = SUPERVISION.step

    def numpy_batch():
        step(FLOAT, params_batch, state_batch, batch)

    def float_loop():
        for i in scalars:
            step(FLOAT, params_batch, state_one, i)

    def exact_loop():
        for i in exacts:
            step(EXACT, params_batch, state_one, i)

    # the three runs agree (the benchmark measures the same computation three ways)
    _, out = step(FLOAT, params_batch, state_batch, batch)
    for t in (0, trains // 2, trains - 1):
        assert bool(out.emergency_brake[t]) == step(EXACT, params_batch, state_one, exacts[t])[1].emergency_brake

    t_batch = median_seconds(numpy_batch, repeats)
    progress(1, 3)
    t_float = median_seconds(float_loop, repeats)
    progress(2, 3)
    t_exact = median_seconds(exact_loop, repeats)
    progress(3, 3)
    table = Table(title=f"bench supervision: one cycle for {trains} trains (median of {repeats})")
    for col in ("backend", "per cycle (ms)", "per train (µs)", "share of 100 ms cycle", "vs numpy batch"):
        table.add_column(col, justify="left" if col == "backend" else "right")
    rows = (("float, numpy batch", t_batch), ("float, scalar loop", t_float), ("exact, Fraction loop", t_exact))
    for name, t in rows:
        table.add_row(name, f"{t * 1e3:.3f}", f"{t / trains * 1e6:.2f}", f"{t / CYCLE_S:.2%}", f"{t / t_batch:.1f}x")
    console.print(table)
    return {"numpy_batch_s": t_batch, "float_loop_s": t_float, "exact_loop_s": t_exact}


# --- MRSP: seed 002's incremental restriction update against full recomputations ----------------

SEED002_LINE_M = 56_800
SEED002_TRAIN_M = 200.0


def synthetic_line(line_m: int, rng: np.random.Generator) -> tuple[Profile, Profile]:
    """A seed 002-like line: PISL changing every 300 to 700 m between 40 and 80 km/h, PTSL 80 km/h."""
    starts = [0]
    while starts[-1] + 700 < line_m:
        starts.append(starts[-1] + int(rng.integers(300, 701)))
    limits = [int(v) for v in rng.choice([40, 50, 60, 70, 80], size=len(starts))]
    pisl = speed_profile("PISL", starts, limits, line_m)
    ptsl = speed_profile("PTSL", [0], [80], line_m)
    return as_float(pisl), as_float(ptsl)


def _vsp(pisl: Profile, ptsl: Profile) -> np.ndarray:
    """``vSP[i]`` per metre: the lower of the two profiles."""
    metres = np.arange(int(pisl.end_m))
    vsp = np.full(len(metres), np.inf)
    for p in (pisl, ptsl):
        index = np.searchsorted(np.asarray(p.starts_m), metres, side="right") - 1
        vsp = np.minimum(vsp, np.asarray(p.values)[index])
    return vsp


def _window_min(values: np.ndarray, width: int) -> np.ndarray:
    """``out[i] = min(values[i - width + 1 .. i])`` (fewer at the start), by a sparse table (O(n log width))."""
    n = len(values)
    table = np.concatenate([np.full(width - 1, np.inf), values])
    span = 1
    while span * 2 <= width:
        table = np.minimum(table[:-span], table[span:])
        span *= 2
    return np.minimum(table[:n], table[width - span : width - span + n])


def per_metre_mrsp(pisl: Profile, ptsl: Profile, restrictions, train_m: float) -> np.ndarray:
    """Seed 001 §3.3's array formulation: ``vSP[i]`` per metre (the lowest profile), then
    ``MRSP[i] = min(vSP[i - L .. i])``, the window minimum by a sparse table (O(n log L), numpy)."""
    vsp = _vsp(pisl, ptsl)
    for r in restrictions:
        vsp[int(r.start_m) : int(r.end_m)] = np.minimum(vsp[int(r.start_m) : int(r.end_m)], r.limit_mps)
    return _window_min(vsp, int(train_m) + 1)


class PerMetreMrsp:
    """The per-metre arrays kept between updates, the strongest simple alternative to the incremental model: a
    restriction applied or withdrawn changes ``vSP`` on it and recomputes ``MRSP`` on ``[start, end + L)`` only,
    the window the model updates (one restriction at a time: withdrawing restores the permanent ``vSP``)."""

    def __init__(self, pisl: Profile, ptsl: Profile, train_m: float):
        self.permanent = _vsp(pisl, ptsl)
        self.vsp = self.permanent.copy()
        self.width = int(train_m) + 1
        self.mrsp = _window_min(self.vsp, self.width)

    def _refresh(self, start: int, end: int) -> None:
        low, high = max(start - self.width + 1, 0), min(end + self.width - 1, len(self.vsp))
        self.mrsp[start:high] = _window_min(self.vsp[low:high], self.width)[start - low :]

    def apply(self, r: Restriction) -> None:
        start, end = int(r.start_m), int(r.end_m)
        self.vsp[start:end] = np.minimum(self.vsp[start:end], r.limit_mps)
        self._refresh(start, end)

    def withdraw(self, r: Restriction) -> None:
        start, end = int(r.start_m), int(r.end_m)
        self.vsp[start:end] = self.permanent[start:end]
        self._refresh(start, end)


def _check_same_mrsp(store: SpeedRestrictions, arrays: PerMetreMrsp, pisl, ptsl, tsr, train_m: float) -> None:
    """The five methods of :func:`bench_mrsp` compute the same MRSP, compared at every metre with the restriction
    applied, and the two that keep state after it is withdrawn."""
    metres = np.arange(int(pisl.end_m), dtype=float)
    store.apply("tsr", tsr)
    arrays.apply(tsr)
    assert store.mrsp() == canonical(restricted(FLOAT, store.psl, (tsr,), train_m))
    sampled = value_at(FLOAT, store.mrsp(), metres)
    assert np.array_equal(sampled, per_metre_mrsp(pisl, ptsl, (tsr,), train_m))
    assert np.array_equal(sampled, arrays.mrsp)
    store.withdraw("tsr")
    arrays.withdraw(tsr)
    assert np.array_equal(value_at(FLOAT, store.mrsp(), metres), arrays.mrsp)


def bench_mrsp(console: Console, repeats: int = 5, progress: Progress = lambda done, total: None) -> dict[str, float]:
    """Apply and withdraw a speed restriction: the incremental window update against whole-line recomputations.

    A 30 km/h restriction on the seed 002 line and on a line 10x longer (float backend, same step functions)."""
    rng = np.random.default_rng(20261122)
    train_m = SEED002_TRAIN_M
    results: dict[str, float] = {}
    rows: dict[str, list[float]] = {}
    sizes = []
    for scale in (1, 10):
        line_m = SEED002_LINE_M * scale
        pisl, ptsl = synthetic_line(line_m, rng)
        tsr = Restriction(line_m / 2, line_m / 2 + 500.0, float(30 / KMH_PER_MPS))
        store = SpeedRestrictions(pisl, ptsl, train_m, FLOAT)
        psl = store.psl
        sizes.append((line_m, len(pisl.starts_m), len(psl.starts_m)))

        def incremental(store=store, tsr=tsr):
            store.apply("tsr", tsr)
            store.withdraw("tsr")

        def full_from_psl(psl=psl, tsr=tsr):
            canonical(restricted(FLOAT, psl, (tsr,), train_m))
            canonical(restricted(FLOAT, psl, (), train_m))

        def from_scratch(pisl=pisl, ptsl=ptsl, tsr=tsr):
            for active in ((tsr,), ()):
                canonical(restricted(FLOAT, permanent_speed_limit(FLOAT, pisl, ptsl, train_m), active, train_m))

        def per_metre(pisl=pisl, ptsl=ptsl, tsr=tsr):
            per_metre_mrsp(pisl, ptsl, (tsr,), train_m)
            per_metre_mrsp(pisl, ptsl, (), train_m)

        arrays = PerMetreMrsp(pisl, ptsl, train_m)

        def per_metre_window(arrays=arrays, tsr=tsr):
            arrays.apply(tsr)
            arrays.withdraw(tsr)

        _check_same_mrsp(store, arrays, pisl, ptsl, tsr, train_m)

        for name, fn, reps in (
            ("incremental window update (seed 002)", incremental, repeats * 20),
            ("full recomputation from the stored PSL", full_from_psl, repeats),
            ("recomputation from PISL and PTSL", from_scratch, max(1, repeats // 2)),
            ("per-metre arrays, numpy (seed 001)", per_metre, repeats),
            ("per-metre arrays, window update", per_metre_window, repeats * 20),
        ):
            seconds = median_seconds(fn, reps)
            rows.setdefault(name, []).append(seconds)
            progress(sum(map(len, rows.values())), 10)
            results[f"{name} @ {scale}x"] = seconds

    _print_mrsp(console, rows, sizes)
    return results


def _print_mrsp(console: Console, rows: dict[str, list[float]], sizes) -> None:
    title = ", ".join(f"{line_m / 1000:g} km: {pisl_n} PISL / {psl_n} PSL segments" for line_m, pisl_n, psl_n in sizes)
    table = Table(title=f"bench mrsp: apply + withdraw a 30 km/h restriction (500 m, 200 m train), median ms\n{title}")
    table.add_column("method")
    for line_m, _, _ in sizes:
        table.add_column(f"{line_m / 1000:g} km", justify="right")
    table.add_column("10x line", justify="right")
    table.add_column("/ incremental", justify="right")
    base = rows["incremental window update (seed 002)"]
    for name, (t1, t10) in rows.items():
        table.add_row(
            name,
            f"{t1 * 1e3:.3f}",
            f"{t10 * 1e3:.3f}",
            f"{t10 / t1:.1f}x",
            f"{t1 / base[0]:.0f}x / {t10 / base[1]:.0f}x",
        )
    console.print(table)


BENCHMARKS: dict[str, Callable[..., object]] = {
    "supervision": bench_supervision,
    "mrsp": bench_mrsp,
    "cycle": bench_cycle,
    "sim": bench_sim,
    "sweep": bench_sweep,
}


def summary(name: str) -> str:
    """The first line of the benchmark's docstring."""
    return inspect.getdoc(BENCHMARKS[name]).splitlines()[0]
