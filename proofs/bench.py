"""Benchmarks: measured side by side in one run, reported as ratios (never as timed unit tests).

``BENCHMARKS`` registers them by name for ``atcs bench [NAME]``.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable
from fractions import Fraction

import numpy as np
from rich.console import Console
from rich.table import Table

from atcs.model.node import as_dict
from atcs.model.ops.exact import EXACT
from atcs.model.ops.floating import FLOAT
from atcs.model.supervision import SUPERVISION, SupervisionInputs, SupervisionParams, SupervisionState

CYCLE_S = 0.1  # one ATP cycle (seed 001)


def _median_time(fn: Callable[[], object], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def _supervision_inputs(trains: int, rng: np.random.Generator):
    permitted = rng.uniform(0, 25, trains)
    warning = permitted + rng.uniform(0, 1.5, trains)
    sbi = warning + rng.uniform(0, 1.5, trains)
    ebi = sbi + rng.uniform(0, 1.5, trains)
    speed = rng.uniform(0, 30, trains)
    return SupervisionInputs(
        speed_mps=speed, permitted_mps=permitted, warning_mps=warning, sbi_mps=sbi, ebi_mps=ebi,
        standstill=speed < 0.1, eb_release=rng.random(trains) < 0.5,
    )


def bench_supervision(console: Console, trains: int = 1000, repeats: int = 7) -> dict[str, float]:
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

    t_batch = _median_time(numpy_batch, repeats)
    t_float = _median_time(float_loop, repeats)
    t_exact = _median_time(exact_loop, repeats)
    table = Table(title=f"bench supervision: one cycle for {trains} trains (median of {repeats})")
    for col in ("backend", "per cycle (ms)", "per train (µs)", "share of 100 ms cycle", "vs numpy batch"):
        table.add_column(col, justify="left" if col == "backend" else "right")
    rows = (("float, numpy batch", t_batch), ("float, scalar loop", t_float), ("exact, Fraction loop", t_exact))
    for name, t in rows:
        table.add_row(name, f"{t * 1e3:.3f}", f"{t / trains * 1e6:.2f}", f"{t / CYCLE_S:.2%}", f"{t / t_batch:.1f}x")
    console.print(table)
    return {"numpy_batch_s": t_batch, "float_loop_s": t_float, "exact_loop_s": t_exact}


BENCHMARKS: dict[str, Callable[[Console], object]] = {"supervision": bench_supervision}
