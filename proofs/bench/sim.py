"""``atcs bench sim``: the simulator's cost as the fleet grows, measured side by side in one run.

The seed 002 timetable's double track (56.8 km with a turn-back at each end, a loop of 114.4 km; tags every
200 m, 100 m resources, ten stations a track) with 2, 20 and 100 trains spaced 400 m apart from the loop's
origin, all departing at once. Each fleet runs a warm-up (the
power-up EB and the first grants), then a timed stretch of cycles; every cycle runs every train's nodes
and checks every property, as a scenario run does. The real-time factor is simulated time over wall time
(above 1: faster than real time); the per-train cost, relative to the smallest fleet's, shows how the cost
grows with the fleet.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable
from fractions import Fraction

from rich.console import Console
from rich.table import Table

from atcs.sim.scenario import load_scenario, resolve
from atcs.sim.simulator import Simulation

FLEETS = (2, 20, 100)
SPACING_M = 400
WARM_UP_CYCLES = 100
TIMED_CYCLES = 200


def fleet_scenario(trains: int):
    """The seed 002 timetable with ``trains`` trains, front to back every 400 m from the loop's origin (the up
    track's start), all departing at 0 s; the front train's leader is the last, round the near turn-back."""
    base = load_scenario(resolve("seed002_timetable"))
    most = (int(base.line_m) - 1) // SPACING_M  # every front short of the loop's end
    if not 1 <= trains <= most:
        raise ValueError(f"trains must be from 1 to {most}, got {trains!r}")
    template = base.trains[0]
    specs = tuple(
        dataclasses.replace(
            template, name=f"T{k + 1}", front_m=Fraction(SPACING_M * (trains - k)), depart_s=Fraction(0)
        )
        for k in range(trains)
    )
    return dataclasses.replace(base, name=f"{base.name}_{trains}_trains", trains=specs)


def bench_sim(
    console: Console,
    fleets: tuple[int, ...] = FLEETS,
    warm_up: int = WARM_UP_CYCLES,
    cycles: int = TIMED_CYCLES,
    progress: Callable[[int, int], None] = lambda done, total: None,
) -> dict[str, float]:
    """Wall time per cycle and per train-cycle, and the real-time factor, for each fleet size."""
    results: dict[str, float] = {}
    rows = []
    total, done = (warm_up + cycles) * sum(fleets), 0  # in train-cycles
    for trains in fleets:
        sim = Simulation(fleet_scenario(trains))
        for _ in range(warm_up):
            sim.step()
            done += trains
            progress(done, total)
        wall_s = 0.0
        for _ in range(cycles):
            t0 = time.perf_counter()
            sim.step()
            wall_s += time.perf_counter() - t0
            done += trains
            progress(done, total)
        per_cycle_s = wall_s / cycles
        rows.append((trains, per_cycle_s, sim.dt / per_cycle_s))
        console.print(f"bench sim: {trains} trains, {per_cycle_s * 1e3:.1f} ms a cycle")
        results[f"{trains}_trains_cycle_s"] = per_cycle_s
        results[f"{trains}_trains_real_time_factor"] = sim.dt / per_cycle_s
    table = Table(
        title=f"bench sim: seed 002 double track, trains every {SPACING_M} m, {cycles} cycles timed after "
        f"{warm_up} of warm-up, every property checked every cycle"
    )
    for column in ("trains", "ms / cycle", "ms / train-cycle", "/ smallest fleet's per train", "real-time factor"):
        table.add_column(column, justify="right")
    base = rows[0][1] / rows[0][0]
    for trains, per_cycle_s, factor in rows:
        per_train = per_cycle_s / trains
        table.add_row(
            str(trains),
            f"{per_cycle_s * 1e3:.1f}",
            f"{per_train * 1e3:.2f}",
            f"{per_train / base:.2f}x",
            f"{factor:.2f}",
        )
    console.print(table)
    return results
