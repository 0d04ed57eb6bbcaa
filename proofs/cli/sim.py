"""``atcs sim SCENARIO``: run a scenario in closed loop, checking the properties every cycle.

Exit code 0 the run ended with no violation, 1 a property or safety check failed, 2 a bad scenario, 130
interrupted (Ctrl-C: the summary of the run so far is printed first).
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field
from pathlib import Path

from rich.table import Table

from atcs.proofs.cli._common import (
    EXIT_FALSIFIED,
    EXIT_INTERRUPTED,
    EXIT_OK,
    UsageError,
    check_outputs,
    progress_bar,
    reraised,
)

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
    from atcs.sim.scenario import ScenarioError, load_scenario, resolve
    from atcs.sim.trace_files import trace_text

    with reraised("sim: ", ScenarioError):
        scenario = load_scenario(resolve(args.scenario))
    if args.trace is not None and Path(args.trace).suffix not in (".csv", ".jsonl"):
        raise UsageError(f"sim: --trace {args.trace}: the file must end in .csv or .jsonl")
    check_outputs(files={"--trace": args.trace}, dirs={"--plot": args.plot})
    out.print(f"{scenario.name} (seed {scenario.seed}): {scenario.description}")
    done = _simulate(scenario, args, err)
    _print(out, done.sim)
    if done.interrupted:
        out.print(f"[yellow]interrupted[/] at {done.sim.time_s:.1f} s: no violation up to there")
        return EXIT_INTERRUPTED
    _write_outputs(args, out, done.sim, done.rows, done.records)
    if done.failure is not None:
        out.print(f"[bold red]violation:[/] {done.failure}")
        if args.trace is None:
            path = Path(f"{scenario.name}_violation.csv")
            write_atomic(path, trace_text([row for cycle in done.recent for row in cycle], ".csv"))
            out.print(f"trace of the last {len(done.recent)} cycles: {path}")
        return EXIT_FALSIFIED
    out.print("[green]no violation[/]: every checked property held at every cycle")
    return EXIT_OK


@dataclass
class _Run:
    """What a run recorded: the simulation, the trace rows (``--trace``), the plot records (``--plot``), the last
    cycles (written out on a violation), and how it ended."""

    sim: object = None
    rows: list[dict] = field(default_factory=list)
    records: list[list[dict]] = field(default_factory=list)
    recent: deque = field(default_factory=lambda: deque(maxlen=VIOLATION_TRACE_CYCLES))
    failure: Exception | None = None
    interrupted: bool = False


def _simulate(scenario, args, err) -> _Run:
    """Run ``scenario`` to its end, a violation or Ctrl-C, with a progress bar (lines with the time left in a
    log) on ``err``."""
    from atcs.sim.monitor import PropertyViolation
    from atcs.sim.simulator import Simulation
    from atcs.sim.train_run import SafetyViolation

    done = _Run()
    with progress_bar(err, "cycles", int(scenario.duration_s / scenario.cycle_s)) as bar:

        def record(sim):
            if args.trace is not None:
                done.rows.extend({"train": t.spec.name, **t.last} for t in sim.trains)
            else:  # the last cycles, written out if the run fails
                done.recent.append([{"train": t.spec.name, **t.last} for t in sim.trains])
            if args.plot is not None:
                done.records.append([dict(t.last) for t in sim.trains])
            if sim.step_count % 50 == 0:
                bar.at(sim.step_count)

        done.sim = Simulation(scenario, on_cycle=record)
        try:
            done.sim.run()
        except (PropertyViolation, SafetyViolation) as exc:
            done.failure = exc
        except KeyboardInterrupt:
            done.interrupted = True
    return done


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
