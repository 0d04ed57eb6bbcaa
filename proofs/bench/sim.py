"""``atcs bench sim``: the simulator's cost as the fleet grows, measured side by side in one run.

The seed 002 timetable's double track (56.8 km with a turn-back at each end, a loop of 114.4 km; tags every
200 m, 100 m resources, ten stations a track) with 2, 20 and 100 trains spaced 400 m apart from the loop's
origin, all departing at once. Each fleet runs a warm-up (the
power-up EB and the first grants), then a timed stretch of cycles; every cycle runs every train's nodes
and checks every property, as a scenario run does. The real-time factor is simulated time over wall time
(above 1: faster than real time); the per-train cost, relative to the smallest fleet's, shows how the cost
grows with the fleet. Each fleet runs twice, its checked nodes and their properties run as the programs traced
from them (:mod:`atcs.model.ops.traced`, what the simulator does) and as the functions themselves, and the two
runs must end in the same state, to the bit.
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


MODES = ("traced", "direct")
"""How the checked nodes and their properties run (:func:`~atcs.sim.monitor.check_step`): as the programs traced
from them, or as the functions themselves; both on exact numbers, every property checked every cycle."""


def train_states(sim: Simulation) -> list[tuple]:
    """Every train's state after a run: what two runs of one fleet must agree on, to the bit."""
    return [
        (t.front_m, t.speed_mps, t.position.state, t.authority, t.ats_status, t.supervision, t.dcu, t.stats)
        for t in sim.trains
    ]


def bench_sim(
    console: Console,
    fleets: tuple[int, ...] = FLEETS,
    warm_up: int = WARM_UP_CYCLES,
    cycles: int = TIMED_CYCLES,
    progress: Callable[[int, int], None] = lambda done, total: None,
) -> dict[str, float]:
    """The simulator's time per cycle and real-time factor for each fleet, traced and direct side by side.

    Wall and CPU time per cycle and per train-cycle; raises AssertionError if the two runs of a fleet end in
    different states."""
    results: dict[str, float] = {}
    rows = []
    total, done = (warm_up + cycles) * sum(fleets) * len(MODES), 0  # in train-cycles
    for trains in fleets:
        ends = {}
        for mode in MODES:
            sim = Simulation(fleet_scenario(trains), traced=mode == "traced")
            for _ in range(warm_up):
                sim.step()
                done += trains
                progress(done, total)
            wall_s = cpu_s = 0.0
            for _ in range(cycles):
                t0, c0 = time.perf_counter(), time.process_time()
                sim.step()
                wall_s += time.perf_counter() - t0
                cpu_s += time.process_time() - c0
                done += trains
                progress(done, total)
            ends[mode] = train_states(sim)
            per_cycle_s = wall_s / cycles
            rows.append((trains, mode, per_cycle_s, cpu_s / cycles, sim.dt / per_cycle_s))
            console.print(f"bench sim: {trains} trains {mode}, {per_cycle_s * 1e3:.1f} ms a cycle")
            results[f"{trains}_trains_{mode}_cycle_s"] = per_cycle_s
            results[f"{trains}_trains_{mode}_cpu_s"] = cpu_s / cycles
            results[f"{trains}_trains_{mode}_real_time_factor"] = sim.dt / per_cycle_s
        assert ends["traced"] == ends["direct"], f"{trains} trains: the traced and direct runs end apart"
    table = Table(
        title=f"bench sim: seed 002 double track, trains every {SPACING_M} m, {cycles} cycles timed after "
        f"{warm_up} of warm-up, every property checked every cycle on exact numbers; the traced and direct runs "
        "end in the same state"
    )
    for column in (
        "trains",
        "nodes and checks",
        "ms / cycle",
        "CPU ms / cycle",
        "ms / train-cycle",
        "/ smallest fleet's per train",
        "real-time factor",
    ):
        table.add_column(column, justify="right")
    base = {mode: next(r[2] / r[0] for r in rows if r[1] == mode) for mode in MODES}
    for trains, mode, per_cycle_s, cpu_cycle_s, factor in rows:
        per_train = per_cycle_s / trains
        table.add_row(
            str(trains),
            mode,
            f"{per_cycle_s * 1e3:.1f}",
            f"{cpu_cycle_s * 1e3:.1f}",
            f"{per_train * 1e3:.2f}",
            f"{per_train / base[mode]:.2f}x",
            f"{factor:.2f}",
        )
    console.print(table)
    return results
