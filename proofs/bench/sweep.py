"""``atcs bench sweep``: cells of an envelope proved per minute, in this process, on local worker processes and on
a local Ray cluster, measured side by side in one run on the same cells, with the verdicts checked equal.

The cells are those of ``model/configurations/envelope.toml`` (the Gamma train, its emergency brake scale and
T_be as ranges): its curve properties but CRV-01 (which takes minutes on the whole box) on each cell of the
ranges split twice (a 2 x 2 grid), every cell proved for all of its values. Ray's start-up (its local cluster)
is timed apart from the cells; spawned worker processes start with their first cell, so theirs is in the
cells' time.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from concurrent.futures import FIRST_COMPLETED, wait
from pathlib import Path

from rich.console import Console
from rich.table import Table

from atcs.model.configuration import load_configuration
from atcs.proofs.envelope.cells import split, whole_range
from atcs.proofs.envelope.executors import RAY_INSTALL, RayUnavailable, local_executor, ray_executor
from atcs.proofs.envelope.sweep import envelope_properties, prove_cell

CONFIG = Path(__file__).parents[2] / "model" / "configurations" / "envelope.toml"
JOBS = 2
TIMEOUT_S = 300.0


def sweep_tasks() -> list[tuple[str, tuple]]:
    """The (property, cell bounds) pairs the benchmark proves."""
    config = load_configuration(CONFIG)
    (train,) = config.trains
    cells = [whole_range(train.ranges)]
    for _ in range(2):
        cells = [half for cell in cells for half in split(cell, train.ranges)]
    names = [n for n in envelope_properties(config) if n.startswith("curves.") and not n.startswith("curves.order")]
    return [(name, cell.bounds) for name in names for cell in cells]


def _run(executor_factory, tasks, progress: Callable[[], None]) -> tuple[float, float, dict]:
    """Start-up and cell wall times, and the verdict of each task."""
    start = time.perf_counter()
    with executor_factory() as executor:
        started = time.perf_counter()
        futures = {
            executor.submit(prove_cell, str(CONFIG), name, bounds, TIMEOUT_S): (name, bounds) for name, bounds in tasks
        }
        verdicts = {}
        pending = set(futures)
        while pending:
            done, pending = wait(pending, return_when=FIRST_COMPLETED)
            for future in done:
                verdicts[futures[future]] = future.result().status
                progress()
        finished = time.perf_counter()
    return started - start, finished - started, verdicts


def bench_sweep(
    console: Console, tasks: list | None = None, progress: Callable[[int, int], None] = lambda done, total: None
) -> dict[str, float]:
    """Envelope cells proved per minute: this process, local worker processes and Ray, the same cells."""
    tasks = sweep_tasks() if tasks is None else tasks
    ways = [
        ("this process", lambda: local_executor(1)),
        (f"local worker processes ({JOBS})", lambda: local_executor(JOBS)),
        (f"Ray, local cluster ({JOBS} CPUs)", lambda: ray_executor("auto", JOBS)),
    ]
    total = len(tasks) * len(ways)
    done = [0]

    def tick():
        done[0] += 1
        progress(done[0], total)

    rows, results, reference = [], {}, None
    for label, factory in ways:
        try:
            startup_s, cells_s, verdicts = _run(factory, tasks, tick)
        except RayUnavailable:
            rows.append((label, None, None, f"not run: Ray is not installed ({RAY_INSTALL})"))
            continue
        reference = verdicts if reference is None else reference
        if verdicts != reference:
            raise AssertionError(f"bench sweep: {label} gave other verdicts than this process")
        rows.append((label, startup_s, cells_s, "same verdicts"))
        results[f"{label} cells_per_minute"] = len(tasks) / cells_s * 60
        results[f"{label} startup_s"] = startup_s
    table = Table(
        title=f"bench sweep: {len(tasks)} cells ({len({n for n, _ in tasks})} properties x "
        f"{len({b for _, b in tasks})} cells of {CONFIG.name}), each proved for all of its values"
    )
    for heading in ("how", "start-up (s)", "cells (s)", "cells per minute", "vs this process", "verdicts"):
        table.add_column(heading, justify="left" if heading in ("how", "verdicts") else "right")
    base = next((cells_s for _, _, cells_s, _ in rows if cells_s), None)
    for label, startup_s, cells_s, note in rows:
        if cells_s is None:
            table.add_row(label, "", "", "", "", note)
            continue
        table.add_row(
            label,
            f"{startup_s:.1f}",
            f"{cells_s:.1f}",
            f"{len(tasks) / cells_s * 60:.0f}",
            f"{base / cells_s:.2f}x",
            note,
        )
    console.print(table)
    return results
