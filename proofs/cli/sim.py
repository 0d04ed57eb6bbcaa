"""``atcs sim SCENARIO``: run a scenario in closed loop, checking the properties every cycle.

Exit code 0 the run ended with no violation, 1 a property or safety check failed, 2 a bad scenario.
"""

from __future__ import annotations

from collections import deque
from pathlib import Path

from rich.table import Table

from atcs.proofs.cli._common import EXIT_FALSIFIED, EXIT_OK, UsageError, check_outputs, progress_bar, reraised

VIOLATION_TRACE_CYCLES = 600
"""Without ``--trace``: on a violation, the last this many cycles are written to ``SCENARIO_violation.csv`` in
the current directory."""


def add_parser(subparsers) -> None:
    m = subparsers.add_parser("sim", help="run a scenario in closed loop, checking the properties every cycle")
    m.add_argument("scenario", metavar="SCENARIO", help="a scenario file, or the name of a shipped one (sim/scenarios)")
    m.add_argument(
        "--trace",
        metavar="FILE",
        help="write every cycle of every train here (.csv or .jsonl); "
        "without it a failed run writes its last 60 s to SCENARIO_violation.csv",
    )
    m.add_argument(
        "--plot", metavar="DIR", help="write a speed-distance plot per train and a time-distance diagram here (PNG)"
    )
    m.set_defaults(run=run)


def run(args, out, err) -> int:
    from atcs.proofs.files import write_atomic
    from atcs.sim.monitor import PropertyViolation
    from atcs.sim.scenario import ScenarioError, load_scenario, resolve
    from atcs.sim.simulator import Simulation
    from atcs.sim.trace_files import trace_text
    from atcs.sim.train_run import SafetyViolation

    with reraised("sim: ", ScenarioError):
        scenario = load_scenario(resolve(args.scenario))
    if args.trace is not None and Path(args.trace).suffix not in (".csv", ".jsonl"):
        raise UsageError(f"sim: --trace {args.trace}: the file must end in .csv or .jsonl")
    check_outputs(files={"--trace": args.trace}, dirs={"--plot": args.plot})
    rows: list[dict] = []
    records: list[list[dict]] = []
    recent: deque[list[dict]] = deque(maxlen=VIOLATION_TRACE_CYCLES)
    out.print(f"{scenario.name} (seed {scenario.seed}): {scenario.description}")
    failure = None
    with progress_bar(out, "cycles", int(scenario.duration_s / scenario.cycle_s)) as bar:

        def record(sim):
            if args.trace is not None:
                rows.extend({"train": t.spec.name, **t.last} for t in sim.trains)
            else:  # the last cycles, written out if the run fails
                recent.append([{"train": t.spec.name, **t.last} for t in sim.trains])
            if args.plot is not None:
                records.append([dict(t.last) for t in sim.trains])
            if sim.step_count % 50 == 0:
                bar.at(sim.step_count)

        sim = Simulation(scenario, on_cycle=record)
        try:
            sim.run()
        except (PropertyViolation, SafetyViolation) as exc:
            failure = exc
    _print(out, sim)
    _write_outputs(args, out, sim, rows, records)
    if failure is not None:
        out.print(f"[bold red]violation:[/] {failure}")
        if args.trace is None:
            path = Path(f"{scenario.name}_violation.csv")
            write_atomic(path, trace_text([row for cycle in recent for row in cycle], ".csv"))
            out.print(f"trace of the last {len(recent)} cycles: {path}")
        return EXIT_FALSIFIED
    out.print("[green]no violation[/]: every checked property held at every cycle")
    return EXIT_OK


def _write_outputs(args, out, sim, rows: list[dict], records: list[list[dict]]) -> None:
    """Write the trace asked for with ``--trace`` and the plots asked for with ``--plot``."""
    from atcs.proofs.files import write_atomic
    from atcs.sim.trace_files import trace_text

    if args.trace is not None:
        write_atomic(args.trace, trace_text(rows, Path(args.trace).suffix))
        out.print(f"trace: {args.trace} ({len(rows)} rows)")
    if args.plot is not None and records:
        from atcs.sim.plots import run_plots

        for path in run_plots(sim, records, Path(args.plot)):
            out.print(f"plot: {path}")


def _print(out, sim) -> None:
    table = Table(title=f"{sim.scenario.name}: {sim.time_s:.1f} s simulated")
    for column in (
        "train",
        "distance (m)",
        "running (s)",
        "max speed (km/h)",
        "EB",
        "SB",
        "stops",
        "min gap (m)",
        "front at end (m)",
    ):
        table.add_column(column, justify="left" if column == "train" else "right")
    for t in sim.trains:
        s = t.stats
        table.add_row(
            t.spec.name,
            f"{s.distance_m:.1f}",
            f"{s.running_s:.1f}",
            f"{s.max_speed_kmh:.1f}",
            str(s.emergency_brakes),
            str(s.service_brakes),
            str(s.station_stops),
            "-" if s.min_gap_m == float("inf") else f"{s.min_gap_m:.1f}",
            f"{t.front_m:.1f}",
        )
    out.print(table)
