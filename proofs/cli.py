"""The ``atcs`` command line: ``prove``, ``certify``, ``replay``, ``curves``, ``platforms``, ``sim``, ``headway``,
``bench``, ``vectors``, ``mutate``.

Exit codes of ``prove`` (DESIGN.md): 0 all proved, 1 some property falsified,
2 usage or input error, 3 some property unknown or in error and none falsified
(an ``error`` verdict is never a pass). ``replay``: 0 the violation is
reproduced at the recorded step (and the float run agrees), 1 it is not (the model changed), 2 bad input,
4 reproduced but the float run diverges.
``curves``: 0, or 2 for bad train or track data. ``platforms``: 0, or 2 for bad platform data.
``sim``: 0 the run ended with no violation, 1 a property or safety check failed, 2 a bad scenario.
``bench``: 0, or 2 for an unknown benchmark name. ``vectors generate``: 0 every goal settled (covered or shown
infeasible), 3 some unknown; ``vectors verify``: 0 every file verified, 1 a problem; ``vectors check``: 0 every
vector passed, 1 one failed or the implementation stopped; all 2 for bad input.
``mutate``: 0 every counted mutant killed (or equivalent),
1 some mutant survived, 3 some timed out and none survived, 2 bad input.
"""

from __future__ import annotations

import argparse
import fnmatch
import json
import sys
import time
from collections import deque
from pathlib import Path

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table

EXIT_OK, EXIT_FALSIFIED, EXIT_USAGE, EXIT_UNKNOWN = 0, 1, 2, 3
VIOLATION_TRACE_CYCLES = 600
"""``atcs sim`` without ``--trace``: on a violation, the last this many cycles are written to
``SCENARIO_violation.csv`` in the current directory."""

_STYLE = {"proved": "green", "vacuous": "yellow", "falsified": "bold red", "unknown": "yellow",
          "error": "bold magenta"}


class UsageError(Exception):
    """Bad command-line input: printed as one line, exit code 2."""


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, not argparse's usage block
        command = self.prog.removeprefix("atcs").strip()
        raise UsageError(f"{command}: {message}" if command else message)


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number of seconds, got {text!r}") from None
    if not value > 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"must be a positive number of seconds, got {text!r}")
    return value


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {text!r}")
    return value


def _tolerance(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number, got {text!r}") from None
    if not 0 <= value < float("inf"):
        raise argparse.ArgumentTypeError(f"must be a finite number >= 0, got {text!r}")
    return value


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="atcs", description="Prove, replay and benchmark the atcs ATP model.")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    p = sub.add_parser("prove", help="prove the registered safety properties")
    p.add_argument("--only", metavar="PATTERN", action="append",
                   help="glob over property names, e.g. 'supervision.*'; repeatable (the properties any matches)")
    p.add_argument("--json", metavar="FILE", help="write the JSON report here")
    p.add_argument("--junit", metavar="FILE", help="write a JUnit XML report here")
    p.add_argument("--timeout", metavar="SECONDS", type=_positive_float, default=600.0,
                   help="per-property time limit, lemmas included; past it the verdict is unknown (default 600)")
    p.add_argument("--jobs", metavar="N", type=_positive_int, default=1, help="worker processes (default 1)")
    p.add_argument("--cex-dir", metavar="DIR", default="counterexamples",
                   help="where counterexamples are written as JSON, CSV, VCD and PNG (default ./counterexamples)")
    p.add_argument("--witness-dir", metavar="DIR", default=None,
                   help="also write each proved property's witness runs (its assumptions and every implication's "
                   "condition reached) here as JSON")
    p.add_argument("--smooth", action="store_true",
                   help="make each counterexample one with the fewest input changes (same length; the time left "
                   "within --timeout; the count before and after is in the reports)")

    f = sub.add_parser("certify", help="write each proved property's certificate (SMT-LIB 2) and check it with "
                       "z3 and cvc5")
    f.add_argument("--only", metavar="PATTERN", action="append",
                   help="glob over property names, e.g. 'supervision.*'; repeatable (the properties any matches)")
    f.add_argument("--report", metavar="FILE", help="take the proofs' depths from this atcs prove --json report "
                   "(default: prove first)")
    f.add_argument("--dir", metavar="DIR", default="certificates",
                   help="where the scripts and certificates.json are written (default ./certificates)")
    f.add_argument("--timeout", metavar="SECONDS", type=_positive_float, default=600.0,
                   help="per-property limit of the proving, and per-check limit of each solver that has no "
                   "limit of its own (default 600)")
    for solver in ("z3", "cvc5"):
        f.add_argument(f"--{solver}-timeout", metavar="SECONDS", type=_positive_float, default=None,
                       help=f"per-check time limit of {solver}; past it the check is unknown (default --timeout)")
    f.add_argument("--cvc5-rlimit", metavar="UNITS", type=_positive_int, default=None,
                   help="also bound each cvc5 check by this many of its resource units (rlimit-per): the same "
                   "verdict on any machine; past it the check is unknown (default: no bound)")
    f.add_argument("--z3-only", metavar="PATTERN[,PATTERN...]", default=None,
                   help="globs over property names: check these with z3 alone (cvc5 is not asked; they stay "
                   "unconfirmed)")
    f.add_argument("--jobs", metavar="N", type=_positive_int, default=1, help="worker processes (default 1)")

    r = sub.add_parser("replay", help="replay a counterexample exactly and show the violating step")
    r.add_argument("trace", metavar="CEX.json")

    c = sub.add_parser("curves", help="draw the braking curves of a train, track and MA (PNG and SVG)")
    c.add_argument("--train", choices=("seed000", "seed002"), default="seed000",
                   help="train and national data of a seed (default seed000)")
    c.add_argument("--mrsp", metavar="M:KMH,...", default="0:80,600:60,900:70,1200:40",
                   help="MRSP as start:limit pairs, metres and km/h (default %(default)s)")
    c.add_argument("--gradient", metavar="M:PERMILLE,...", default="0:0,500:-10,1100:5",
                   help="compensated gradient as start:per-mille pairs, uphill positive (default %(default)s)")
    c.add_argument("--eoa", metavar="M", default="1500", help="end of authority (m, default %(default)s)")
    c.add_argument("--eoa-speed", metavar="KMH", default="0", help="target speed at the EoA (km/h, default 0)")
    c.add_argument("--front", metavar="M", default="0", help="the max safe front: curves from here (m, default 0)")
    c.add_argument("--a-est", metavar="MPS2", default=None,
                   help="estimated acceleration for the EBI (m/s^2, default the train's maximum)")
    c.add_argument("--speed", metavar="KMH", default=None,
                   help="also print where each target's curves reach this speed (the ERA tool's query)")
    c.add_argument("--out", metavar="DIR", default="curves",
                   help="where curves.png and curves.svg go (default ./curves)")

    t = sub.add_parser("platforms", help="decode platform data (packet 69 / 44 hex, or a TOML table) and show it")
    t.add_argument("file", nargs="?", metavar="FILE.toml", help="a file with a [platforms] section")
    t.add_argument("--packet", metavar="HEX", help="a packet 69 or user packet 44, as hex")
    t.add_argument("--reference-m", metavar="M", default="0",
                   help="where the packet's balise group was read (m, default 0)")
    t.add_argument("--encode", choices=("69", "44"), default=None,
                   help="also print the platforms as a packet of this kind (hex, Q_SCALE 1 m)")

    m = sub.add_parser("sim", help="run a scenario in closed loop, checking the properties every cycle")
    m.add_argument("scenario", metavar="SCENARIO", help="a scenario file, or the name of a shipped one (sim/scenarios)")
    m.add_argument("--trace", metavar="FILE", help="write every cycle of every train here (.csv or .jsonl); "
                   "without it a failed run writes its last 60 s to SCENARIO_violation.csv")
    m.add_argument("--plot", metavar="DIR", help="write a speed-distance plot per train and a time-distance "
                   "diagram here (PNG)")

    h = sub.add_parser("headway", help="the least steady-state headway: measured in closed loop, the ATP's and "
                       "the separation invariant's, in both modes")
    h.add_argument("--speed", metavar="KMH", default="80", help="the steady speed (km/h, default 80)")

    u = sub.add_parser("mutate", help="mutate the model's step functions systematically and prove the properties "
                       "about each mutant; kill rate per module, survivors with their diff")
    u.add_argument("--only", metavar="PATTERN", action="append",
                   help="glob over mutant ids (module.function:+line:operator:...), e.g. 'doors.*'; repeatable")
    u.add_argument("--nodes", metavar="PATTERN", action="append",
                   help="prove only the properties of the nodes matching this glob, e.g. 'door*'; repeatable "
                   "(default every node whose proofs run the mutated function)")
    u.add_argument("--timeout", metavar="SECONDS", type=_positive_float, default=120.0,
                   help="per-mutant time limit over all its properties; past it the verdict is timeout "
                   "(default 120)")
    u.add_argument("--jobs", metavar="N", type=_positive_int, default=1, help="worker processes (default 1)")
    u.add_argument("--json", metavar="FILE", help="write the JSON report here")
    u.add_argument("--equivalents", metavar="FILE", default=None,
                   help="registry of equivalent mutants (default proofs/equivalent_mutants.toml)")
    u.add_argument("--list", action="store_true", help="list the selected mutants and exit")

    b = sub.add_parser("bench", help="run benchmarks that compare side by side and print ratios")
    b.add_argument("name", nargs="?", metavar="NAME", help="one benchmark (default: all)")

    v = sub.add_parser("vectors", help="certified test vectors of each step function: generate, verify, check "
                       "an implementation")
    vsub = v.add_subparsers(dest="vectors_command", required=True, parser_class=_Parser)
    g = vsub.add_parser("generate", help="find vectors covering requirements, boundaries and MC/DC with z3")
    g.add_argument("--function", metavar="NAME", action="append",
                   help="a function (node) of the model; repeat for several (default: every one)")
    g.add_argument("--out", metavar="DIR", default="vectors", help="where the files go (default ./vectors)")
    g.add_argument("--timeout", metavar="SECONDS", type=_positive_float, default=10.0,
                   help="per solver query; past it the goal is unknown (default 10)")
    g.add_argument("--budget", metavar="SECONDS", type=_positive_float, default=1800.0,
                   help="per function; goals past it are unknown (default 1800)")
    g.add_argument("--jobs", metavar="N", type=_positive_int, default=1, help="worker processes (default 1)")
    y = vsub.add_parser("verify", help="re-check vector files against the model (hashes, symbolic and exact)")
    y.add_argument("dir", metavar="DIR")
    k = vsub.add_parser("check", help="run an external implementation over the vectors (JSON lines)")
    k.add_argument("dir", metavar="DIR")
    k.add_argument("--impl", metavar="COMMAND", required=True,
                   help="the implementation's command line: one JSON request per line in, one answer per line out")
    k.add_argument("--function", metavar="NAME", action="append", help="only this function's file (repeatable)")
    k.add_argument("--rel-tol", metavar="X", type=_tolerance, default=1e-9,
                   help="relative tolerance for numbers answered as JSON numbers (default 1e-9)")
    k.add_argument("--abs-tol", metavar="X", type=_tolerance, default=1e-9,
                   help="absolute tolerance for numbers answered as JSON numbers (default 1e-9)")
    k.add_argument("--timeout", metavar="SECONDS", type=_positive_float, default=10.0,
                   help="how long to wait for each answer (default 10)")
    return parser


def main(argv: list[str] | None = None) -> int:
    out, err = Console(), Console(stderr=True)
    if not out.is_terminal:  # logs and pipes: do not truncate property names to 80 columns
        out = Console(width=160)
    try:
        args = build_parser().parse_args(argv)
        command = {"prove": _prove, "certify": _certify, "replay": _replay, "curves": _curves,
                   "platforms": _platforms, "sim": _sim, "headway": _headway, "bench": _bench,
                   "vectors": _vectors, "mutate": _mutate}[args.command]
        return command(args, out, err)
    except UsageError as exc:
        print(f"atcs: error: {exc}", file=sys.stderr)
        return EXIT_USAGE


# --- prove -------------------------------------------------------------------------------


def _selected(command: str, patterns: list[str] | None) -> list:
    """The registered properties any ``--only`` glob selects (all without one); a glob that matches no
    property is a usage error."""
    from atcs.properties import PROPERTIES, select

    if not patterns:
        return select()
    chosen: set[str] = set()
    for pattern in patterns:
        props = select(pattern)
        if not props:
            modules = sorted({p.module for p in PROPERTIES.values()})
            raise UsageError(f"{command}: --only {pattern!r} matches no property (modules: {', '.join(modules)})")
        chosen.update(p.name for p in props)
    return [p for name, p in PROPERTIES.items() if name in chosen]


def _prove(args, out: Console, err: Console) -> int:
    from atcs.proofs import report, suite
    from atcs.proofs.report import OutputPathError

    props = _selected("prove", args.only)
    try:
        for option, path in (("--json", args.json), ("--junit", args.junit)):
            if path is not None:
                report.check_writable_file(option, path)
        report.check_writable_dir("--cex-dir", args.cex_dir)
        if args.witness_dir is not None:
            report.check_writable_dir("--witness-dir", args.witness_dir)
    except OutputPathError as exc:
        raise UsageError(f"prove: {exc}") from None

    start = time.monotonic()
    results = {}
    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn())
    with Progress(*columns, console=err, transient=True) as progress:
        task = progress.add_task("proving", total=len(props))
        for result in suite.run(props, timeout_s=args.timeout, jobs=args.jobs, smooth=args.smooth):
            results[result.name] = result
            progress.update(task, advance=1, description=f"{result.name}: {result.status}")
    wall = time.monotonic() - start

    records = []
    for prop in props:
        result = results[prop.name]
        cex = None
        if result.trace is not None and result.replay is not None:
            cex = str(report.write_counterexample(args.cex_dir, prop, result))
        if args.witness_dir is not None and result.witnesses:
            report.write_witnesses(args.witness_dir, prop, result)
        records.append(report.result_record(prop, result, cex))

    table = Table(title=f"atcs prove: {len(props)} properties in {wall:.2f} s")
    for heading in ("property", "requirement", "status", "engine", "k", "seconds"):
        table.add_column(heading, justify="right" if heading in ("k", "seconds") else "left")
    for r in records:
        table.add_row(r["name"], r["requirement"], f"[{_STYLE[r['status']]}]{r['status']}[/]", r["engine"] or "",
                      "" if r["k"] is None else str(r["k"]), f"{r['seconds']:.3f}")
    out.print(table)
    for r in records:
        if r["status"] != "proved":
            out.print(f"[{_STYLE[r['status']]}]{r['status']}[/] {r['name']}: {r['message']}"
                      + (f" (counterexample: {r['counterexample']})" if r["counterexample"] else ""))

    if args.json:
        report.write_atomic(args.json, report.json_report(records, timeout_s=args.timeout, wall_s=wall))
    if args.junit:
        report.write_atomic(args.junit, report.junit_report(records, wall_s=wall))

    statuses = {r["status"] for r in records}
    if "falsified" in statuses:
        return EXIT_FALSIFIED
    if statuses & {"vacuous", "unknown", "error"}:
        return EXIT_UNKNOWN
    return EXIT_OK


# --- certify -----------------------------------------------------------------------------

_CERT_STYLE = {"certified": "green", "unconfirmed": "yellow", "disagreement": "bold red", "error": "bold magenta",
               "not proved": "yellow"}


def _certify(args, out: Console, err: Console) -> int:
    from atcs.proofs import certify, report, suite
    from atcs.proofs.report import OutputPathError
    from atcs.properties import PROPERTIES

    props = _selected("certify", args.only)
    try:
        report.check_writable_dir("--dir", args.dir)
    except OutputPathError as exc:
        raise UsageError(f"certify: {exc}") from None
    z3_only = _z3_only(args.z3_only, PROPERTIES)
    start = time.monotonic()
    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn())
    needed = {lemma for p in props for lemma in _lemma_closure(p, PROPERTIES)}
    wanted = [*props, *(PROPERTIES[n] for n in sorted(needed - {p.name for p in props}))]
    if args.report is not None:
        try:
            depths = certify.depths_from_report(args.report)
        except certify.ProveReportError as exc:
            raise UsageError(f"certify: --report {exc}") from None
    else:
        depths = {}
        with Progress(*columns, console=err, transient=True) as progress:
            task = progress.add_task("proving", total=len(wanted))
            for result in suite.run(wanted, timeout_s=args.timeout, jobs=args.jobs):
                if result.status == "proved":
                    depths[result.name] = result.k
                progress.update(task, advance=1, description=f"proving {result.name}: {result.status}")
    results = {}
    limits = {"z3": args.z3_timeout or args.timeout, "cvc5": args.cvc5_timeout or args.timeout}
    with Progress(*columns, console=err, transient=True) as progress:
        task = progress.add_task("certifying", total=sum(p.name in depths for p in wanted))
        for c in certify.run(wanted, depths, timeout_s=limits, jobs=args.jobs, cvc5_resource_limit=args.cvc5_rlimit,
                             z3_only=z3_only):
            results[c.name] = c
            progress.update(task, advance=1, description=f"certifying {c.name}")
    certify.settle(results, depths)
    wall = time.monotonic() - start

    directory = Path(args.dir)
    records = []
    for prop in props:
        c = results.get(prop.name)
        if c is None:
            records.append({"name": prop.name, "requirement": prop.requirement, "k": None, "lemmas": list(prop.lemmas),
                            "status": "not proved", "confirmed_by": [], "message": "no proof to certify",
                            "checks": []})
            continue
        (directory / prop.name).mkdir(parents=True, exist_ok=True)
        for ob in c.obligations:
            report.write_atomic(directory / prop.name / f"{ob.check}.smt2", ob.script)
        records.append(certify.record(c, directory))
    counts = {s: sum(r["status"] == s for r in records) for s in _CERT_STYLE}
    report.write_atomic(directory / "certificates.json", json.dumps(
        {"tool": "atcs certify", "solvers": list(certify.SOLVERS), "solver_versions": certify.solver_versions(),
         "timeout_s": args.timeout, "solver_timeout_s": limits,
         "cvc5_resource_limit": args.cvc5_rlimit,
         "z3_only": sorted(z3_only & {p.name for p in wanted}), "wall_s": round(wall, 3), "summary": counts,
         "properties": records},
        indent=2) + "\n")

    table = Table(title=f"atcs certify: {len(props)} properties in {wall:.2f} s ({directory})")
    for heading in ("property", "requirement", "k", "checks", "confirmed by", "status"):
        table.add_column(heading, justify="right" if heading == "k" else "left")
    for r in records:
        table.add_row(r["name"], r["requirement"], "" if r["k"] is None else str(r["k"]), str(len(r["checks"])),
                      ", ".join(r["confirmed_by"]) or "none", f"[{_CERT_STYLE[r['status']]}]{r['status']}[/]")
    out.print(table)
    for r in records:
        if r["status"] != "certified":
            out.print(f"[{_CERT_STYLE[r['status']]}]{r['status']}[/] {r['name']}: {r['message']}")
    if counts["disagreement"]:
        return EXIT_FALSIFIED
    if counts["certified"] != len(records):
        return EXIT_UNKNOWN
    return EXIT_OK


def _z3_only(patterns: str | None, registry) -> set[str]:
    """The properties ``--z3-only`` names; a glob that matches none is a usage error."""
    names: set[str] = set()
    for pattern in [] if patterns is None else patterns.split(","):
        matched = {n for n in registry if fnmatch.fnmatchcase(n, pattern.strip())}
        if not matched:
            raise UsageError(f"certify: --z3-only {pattern.strip()!r} matches no property")
        names |= matched
    return names


def _lemma_closure(prop, registry) -> set[str]:
    """Every lemma ``prop`` rests on, directly or through other lemmas."""
    seen: set[str] = set()
    todo = list(prop.lemmas)
    while todo:
        name = todo.pop()
        if name not in seen and name in registry:
            seen.add(name)
            todo.extend(registry[name].lemmas)
    return seen


# --- replay ------------------------------------------------------------------------------


EXIT_DIVERGED = 4
"""``atcs replay``: the exact replay reproduces the violation, but the float run diverges (a boolean differs, a
float is not finite, or the float run fails); 1 (not reproduced) takes precedence."""


def _replay(args, out: Console, err: Console) -> int:
    from atcs.model.node import flatten
    from atcs.proofs.float_replay import float_replay
    from atcs.proofs.trace import TraceFileError, format_value, from_json, replay
    from atcs.properties import PROPERTIES

    try:
        prop, trace = from_json(args.trace, PROPERTIES)
    except TraceFileError as exc:
        raise UsageError(f"replay: {exc}") from None
    result = replay(prop, trace)

    out.print(f"{prop.name} ({prop.requirement}, seed {prop.seed}): {prop.text}")
    if trace.params:
        out.print("parameters: " + ", ".join(f"{n}={format_value(v)}" for n, v in trace.params.items()))
    first = result.first_violation
    steps = range(len(trace.inputs))
    table = Table(title=f"replay of {Path(args.trace).name} (exact arithmetic; one column per step)")
    table.add_column("variable")
    for k in steps:
        table.add_column(f"{k} VIOLATED" if k == first else str(k), justify="right",
                         style="bold red" if k == first else None)
    for prefix, values in (("state", result.states), ("input", trace.inputs), ("output", result.outputs)):
        for n in flatten(values[0]):
            table.add_row(f"{prefix}.{n}", *(str(format_value(flatten(values[k])[n])) for k in steps))
    table.add_row("holds", *("no" if not ok else "yes" for ok in result.holds))
    out.print(table)
    for problem in result.problems:
        out.print(f"[yellow]not a run of the current model:[/] {problem}")
    if first is None:
        out.print(f"[yellow]the property holds at every step on the current model[/] "
                  f"(the trace recorded a violation at step {trace.violation_step})")
    else:
        out.print(f"[bold red]violated at step {first}[/]"
                  + ("" if first == trace.violation_step else f" (the trace recorded step {trace.violation_step})"))

    floats = float_replay(prop, trace, result)
    if floats.largest:
        gaps = Table(title="float run (IEEE doubles) against the exact run: the largest difference per field")
        for heading in ("field", "|float - exact|", "step", "exact", "float"):
            gaps.add_column(heading, justify="left" if heading == "field" else "right")
        for name in sorted(floats.largest, key=floats.gap, reverse=True):
            d = floats.largest[name]
            gaps.add_row(name, f"{float(floats.gap(name)):.3g}", str(d.step), str(format_value(d.exact)), repr(d.float))
        out.print(gaps)
    for what, d in (("a boolean differs", floats.first_boolean), ("a number is not finite", floats.non_finite)):
        if d is not None:
            out.print(f"[bold red]the float run diverges: {what} first at {d.describe()}[/]")
    if floats.error is not None:
        out.print(f"[bold red]the float run fails at {floats.error}[/]")
    if not floats.diverged:
        out.print(f"the float run agrees with the exact run on every boolean over {floats.steps} steps"
                  + ("" if floats.largest else ", and on every number"))
    if not result.reproduced:
        return EXIT_FALSIFIED
    return EXIT_DIVERGED if floats.diverged else EXIT_OK


# --- platforms ---------------------------------------------------------------------------


def _platforms(args, out: Console, err: Console) -> int:
    from atcs.model.bits import PacketError, hex_bytes
    from atcs.model.platform_packets import Q_DIR, decode_platform_packet, encode_platform_packet
    from atcs.model.platforms import PlatformDataError, packet_for_platforms, platforms_from_packet, read_platform_data
    from atcs.model.profile import parse_number

    if (args.file is None) == (args.packet is None):
        raise UsageError("platforms: give either FILE.toml or --packet HEX")
    try:
        reference_m = parse_number("--reference-m", "metres", args.reference_m, PlatformDataError)
        if args.file is not None:
            platforms = read_platform_data(args.file)
        else:
            packet = decode_platform_packet(hex_bytes(args.packet))
            platforms = platforms_from_packet(packet, reference_m)
            if packet.elements and not platforms:
                out.print(f"the packet's Q_DIR is {packet.q_dir} ({Q_DIR[packet.q_dir]}): no platforms for a train "
                          "running in the nominal direction")
    except PlatformDataError as exc:
        raise UsageError(f"platforms: {exc}") from None
    except PacketError as exc:
        raise UsageError(f"platforms: --packet: {exc}") from None
    table = Table(title=f"{len(platforms)} platforms")
    for column in ("start (m)", "end (m)", "length (m)", "side", "height (mm)"):
        table.add_column(column, justify="left" if column == "side" else "right")
    for p in platforms:
        table.add_row(str(p.start_m), str(p.end_m), str(p.end_m - p.start_m), p.side,
                      "" if p.height_mm is None else str(p.height_mm))
    out.print(table)
    if args.encode:
        try:
            packet = packet_for_platforms(platforms, reference_m, nid_packet=int(args.encode))
            out.print(f"packet {args.encode}: {encode_platform_packet(packet).hex()}")
        except (ValueError, PacketError) as exc:
            raise UsageError(f"platforms: --encode {args.encode}: {exc}") from None
    return EXIT_OK


# --- sim ---------------------------------------------------------------------------------


def _sim(args, out: Console, err: Console) -> int:
    from atcs.proofs.report import OutputPathError, check_writable_dir, check_writable_file, write_atomic
    from atcs.sim.monitor import PropertyViolation
    from atcs.sim.scenario import ScenarioError, load_scenario, resolve
    from atcs.sim.simulator import SafetyViolation, Simulation, trace_text

    try:
        scenario = load_scenario(resolve(args.scenario))
    except ScenarioError as exc:
        raise UsageError(f"sim: {exc}") from None
    if args.trace is not None:
        if Path(args.trace).suffix not in (".csv", ".jsonl"):
            raise UsageError(f"sim: --trace {args.trace}: the file must end in .csv or .jsonl")
        try:
            check_writable_file("--trace", args.trace)
        except OutputPathError as exc:
            raise UsageError(f"sim: {exc}") from None
    if args.plot is not None:
        try:
            check_writable_dir("--plot", args.plot)
        except OutputPathError as exc:
            raise UsageError(f"sim: {exc}") from None
    rows: list[dict] = []
    records: list[list[dict]] = []
    recent: deque[list[dict]] = deque(maxlen=VIOLATION_TRACE_CYCLES)
    cycles = int(scenario.duration_s / scenario.cycle_s)
    out.print(f"{scenario.name} (seed {scenario.seed}): {scenario.description}")
    failure = None
    with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                  console=out, transient=True) as progress:
        task = progress.add_task("cycles", total=cycles)

        def record(sim):
            if args.trace is not None:
                rows.extend({"train": t.spec.name, **t.last} for t in sim.trains)
            else:  # the last cycles, written out if the run fails
                recent.append([{"train": t.spec.name, **t.last} for t in sim.trains])
            if args.plot is not None:
                records.append([dict(t.last) for t in sim.trains])
            if sim.step_count % 50 == 0:
                progress.update(task, completed=sim.step_count)

        sim = Simulation(scenario, on_cycle=record)
        try:
            sim.run()
        except (PropertyViolation, SafetyViolation) as exc:
            failure = exc
    table = Table(title=f"{scenario.name}: {sim.time_s:.1f} s simulated")
    for column in ("train", "distance (m)", "running (s)", "max speed (km/h)", "EB", "SB", "stops",
                   "min gap (m)", "front at end (m)"):
        table.add_column(column, justify="left" if column == "train" else "right")
    for t in sim.trains:
        s = t.stats
        table.add_row(t.spec.name, f"{s.distance_m:.1f}", f"{s.running_s:.1f}", f"{s.max_speed_kmh:.1f}",
                      str(s.emergency_brakes), str(s.service_brakes), str(s.station_stops),
                      "-" if s.min_gap_m == float("inf") else f"{s.min_gap_m:.1f}", f"{t.front_m:.1f}")
    out.print(table)
    if args.trace is not None:
        write_atomic(args.trace, trace_text(rows, Path(args.trace).suffix))
        out.print(f"trace: {args.trace} ({len(rows)} rows)")
    if args.plot is not None and records:
        from atcs.sim.plots import run_plots

        for path in run_plots(sim, records, Path(args.plot)):
            out.print(f"plot: {path}")
    if failure is not None:
        out.print(f"[bold red]violation:[/] {failure}")
        if args.trace is None:
            path = Path(f"{scenario.name}_violation.csv")
            write_atomic(path, trace_text([row for cycle in recent for row in cycle], ".csv"))
            out.print(f"trace of the last {len(recent)} cycles: {path}")
        return EXIT_FALSIFIED
    out.print("[green]no violation[/]: every checked property held at every cycle")
    return EXIT_OK


# --- curves ------------------------------------------------------------------------------


def _pairs(option: str, text: str) -> tuple[list[str], list[str]]:
    starts, values = [], []
    for item in text.split(","):
        start, sep, value = item.strip().partition(":")
        if not sep or not start or not value:
            raise UsageError(f"curves: {option}: {item.strip()!r} is not START:VALUE (in {text!r})")
        starts.append(start)
        values.append(value)
    return starts, values


def _curves(args, out: Console, err: Console) -> int:
    from fractions import Fraction

    from atcs.model import train_data
    from atcs.model.curves import check_braking_capability, curve_locations
    from atcs.model.dynamic_profile import CURVE_NAMES, Horizon, sampled_curves, supervised_targets
    from atcs.model.ops.exact import EXACT
    from atcs.model.profile import KMH_PER_MPS, ProfileError, gradient_profile, parse_number, speed_profile
    from atcs.model.restrictions import as_float
    from atcs.sim.plots import planning_area

    train, national = {
        "seed000": (train_data.seed000_train, train_data.subset026_national),
        "seed002": (train_data.seed002_train, train_data.seed002_national),
    }[args.train]
    train, national = train(), national()
    try:
        eoa_m = parse_number("--eoa", "metres", args.eoa)
        eoa_speed = parse_number("--eoa-speed", "km/h", args.eoa_speed) / KMH_PER_MPS
        front_m = parse_number("--front", "metres", args.front)
        a_est = train.max_acceleration_mps2 if args.a_est is None else parse_number("--a-est", "m/s^2", args.a_est)
        speed = None if args.speed is None else parse_number("--speed", "km/h", args.speed) / KMH_PER_MPS
        mrsp_starts, limits = _pairs("--mrsp", args.mrsp)
        gradient_starts, gradients = _pairs("--gradient", args.gradient)
        starts = [parse_number("--mrsp", "start", s) for s in mrsp_starts]
        end_m = max(eoa_m, *starts, *(parse_number("--gradient", "start", s) for s in gradient_starts)) + 100
        mrsp = speed_profile("--mrsp", mrsp_starts, limits, end_m)
        gradient = gradient_profile("--gradient", gradient_starts, gradients, end_m)
    except ProfileError as exc:
        raise UsageError(f"curves: {exc}") from None
    for option, value, ok in (("--eoa", eoa_m, eoa_m > 0), ("--eoa-speed", eoa_speed, eoa_speed >= 0),
                              ("--front", front_m, 0 <= front_m < eoa_m), ("--a-est", a_est, a_est >= 0),
                              ("--speed", speed, speed is None or speed > 0)):
        if not ok:
            shown = float(value * KMH_PER_MPS) if option in ("--eoa-speed", "--speed") else float(value)
            raise UsageError(f"curves: {option} = {shown:g} is out of range"
                             + (" (the front must lie before the EoA, from 0)" if option == "--front" else ""))
    try:
        train_data.validate(train, national)
        check_braking_capability(train, national, gradient)
    except train_data.TrainDataError as exc:
        raise UsageError(f"curves: {exc}") from None

    horizon = Horizon(mrsp, gradient, eoa_m, eoa_speed)
    sampled = sampled_curves(train, national, Horizon(as_float(mrsp), as_float(gradient), float(eoa_m),
                                                      float(eoa_speed)), float(front_m), float(a_est))
    directory = Path(args.out)
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise UsageError(f"curves: --out {args.out!r}: {exc.strerror}") from None
    title = f"{args.train}: braking curves to the EoA at {float(eoa_m):g} m (A_est {float(a_est):.2f} m/s²)"
    paths = planning_area(sampled, float(eoa_m), title, [directory / "curves.png", directory / "curves.svg"])
    out.print("wrote " + ", ".join(str(p) for p in paths))

    if speed is not None:
        table = Table(title=f"where each curve reaches {float(speed * KMH_PER_MPS):g} km/h (m; '-' never)")
        table.add_column("target (m @ km/h)")
        for name in CURVE_NAMES:
            table.add_column(name, justify="right")
        for target in supervised_targets(EXACT, national, horizon, front_m):
            at = curve_locations(EXACT, train, national, gradient, target, speed, a_est)
            cells = [getattr(at, f"{name}_m") for name in CURVE_NAMES]
            table.add_row(f"{float(target.location_m):g} @ {float(target.speed_mps * KMH_PER_MPS):g}",
                          *("-" if c > Fraction(10**6) else f"{float(c):.2f}" for c in cells))
        out.print(table)
    return EXIT_OK


# --- headway -----------------------------------------------------------------------------


def _headway(args, out: Console, err: Console) -> int:
    from atcs.model.profile import ProfileError, parse_number
    from atcs.sim.headway import HeadwayError, headway_report

    try:
        speed = parse_number("headway", "--speed", args.speed, ProfileError)
    except ProfileError as exc:
        raise UsageError(str(exc)) from None
    if not 0 < speed <= 120:
        raise UsageError(f"headway: --speed = {args.speed!r} must be in (0, 120] km/h")
    try:
        rows = headway_report(speed)
    except HeadwayError as exc:
        raise UsageError(f"headway: {exc}") from None
    table = Table(title=f"headway at a steady {float(speed):g} km/h: gap from the follower's front to the leader's "
                        "rear, and (gap + train length) / speed")
    for column in ("mode", "measured (sim)", "ATP-limited", "invariant bound"):
        table.add_column(column, justify="left" if column == "mode" else "right")
    for row in rows:
        table.add_row(row["mode"], *(f"{float(row[f'{k}_gap_m']):.1f} m, {float(row[f'{k}_headway_s']):.1f} s"
                                     for k in ("measured", "atp", "invariant")))
    out.print(table)
    out.print(f"measured with {float(rows[0]['resource_length_m']):g} m resources (sim/headway.py explains the "
              "three figures)")
    return EXIT_OK


# --- mutate ------------------------------------------------------------------------------

_MUTANT_STYLE = {"killed": "green", "survived": "bold red", "timeout": "yellow", "incompetent": "magenta",
                 "equivalent": "cyan"}


def _mutate(args, out: Console, err: Console) -> int:
    """``atcs mutate``: exit 0 every counted mutant killed, 1 some survived, 3 some timed out and none survived."""
    import fnmatch

    from atcs.proofs import mutation, report
    from atcs.proofs.equivalents import REGISTRY, EquivalentsError, load_equivalents

    mutants = mutation.all_mutants()
    selected = [m for m in mutants if args.only is None or any(fnmatch.fnmatchcase(m.id, p) for p in args.only)]
    if not selected:
        modules = sorted({m.model_module for m in mutants})
        raise UsageError(f"mutate: --only {' '.join(args.only)!r} matches no mutant (modules: {', '.join(modules)})")
    nodes = None
    if args.nodes is not None:
        known = mutation.node_names()
        nodes = tuple(n for n in known if any(fnmatch.fnmatchcase(n, p) for p in args.nodes))
        if not nodes:
            raise UsageError(f"mutate: --nodes {' '.join(args.nodes)!r} matches no node (nodes: {', '.join(known)})")
        selected = [m for m in selected if mutation.affected_properties(m, nodes)]
        if not selected:
            raise UsageError(f"mutate: no selected mutant's function is run by the --nodes {' '.join(args.nodes)!r}")
    try:
        equivalent = load_equivalents(args.equivalents or REGISTRY, known={m.id for m in mutants})
        if args.json is not None:
            report.check_writable_file("--json", args.json)
    except EquivalentsError as exc:
        raise UsageError(f"mutate: --equivalents {exc}") from None
    except report.OutputPathError as exc:
        raise UsageError(f"mutate: {exc}") from None
    if args.list:
        for m in selected:
            print(m.id + ("  (equivalent)" if m.id in equivalent else ""))  # one id a line, never wrapped
        return EXIT_OK

    start = time.monotonic()
    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn())
    with Progress(*columns, console=err, transient=True) as progress:
        task = progress.add_task("mutating", total=len(selected))
        def done(o):
            progress.update(task, advance=1, description=f"{o.mutant.id}: {o.verdict}")
            if not err.is_terminal:  # a log: one line per mutant instead of the progress bar
                print(f"{o.verdict} {o.mutant.id} ({o.seconds:.1f} s)", file=sys.stderr, flush=True)

        outcomes = mutation.run(selected, timeout_s=args.timeout, jobs=args.jobs, equivalent=equivalent, nodes=nodes,
                                on_done=done)
    wall = time.monotonic() - start
    rates = mutation.kill_rates(outcomes)

    table = Table(title=f"atcs mutate: {len(selected)} mutants in {wall:.1f} s")
    for heading in ("module", *mutation.VERDICTS, "kill rate"):
        table.add_column(heading, justify="left" if heading == "module" else "right")
    for module, r in rates.items():
        rate = "-" if r["kill_rate"] is None else f"{100 * r['kill_rate']:.1f} %"
        table.add_row(module, *(str(r[v]) for v in mutation.VERDICTS), rate, end_section=module == list(rates)[-2])
    out.print(table)
    for o in outcomes:
        if o.verdict in ("survived", "timeout", "incompetent"):
            out.print(f"[{_MUTANT_STYLE[o.verdict]}]{o.verdict}[/] {o.mutant.id} (line {o.mutant.line}): "
                      f"{o.message}", highlight=False)
            if o.verdict == "survived":
                out.print(o.mutant.diff, markup=False, highlight=False)
    if args.json:
        doc = {"tool": "atcs mutate", "timeout_s": args.timeout, "nodes": list(nodes) if nodes else None,
               "only": args.only, "wall_seconds": round(wall, 3), "kill_rates": rates,
               "mutants": [o.record() for o in outcomes]}
        report.write_atomic(args.json, json.dumps(doc, indent=2) + "\n")
    verdicts = {o.verdict for o in outcomes}
    if "survived" in verdicts:
        return EXIT_FALSIFIED
    if "timeout" in verdicts:
        return EXIT_UNKNOWN
    return EXIT_OK


# --- bench -------------------------------------------------------------------------------


def _bench(args, out: Console, err: Console) -> int:
    from atcs.proofs.bench import BENCHMARKS

    if args.name is not None and args.name not in BENCHMARKS:
        raise UsageError(f"bench: unknown benchmark {args.name!r} (known: {', '.join(BENCHMARKS)})")
    for name in [args.name] if args.name else list(BENCHMARKS):
        BENCHMARKS[name](out)
    return EXIT_OK


# --- vectors -----------------------------------------------------------------------------


def _vectors(args, out: Console, err: Console) -> int:
    return {"generate": _vectors_generate, "verify": _vectors_verify,
            "check": _vectors_check}[args.vectors_command](args, out, err)


def _functions(command: str, names: list[str] | None) -> list[str]:
    from atcs.model import NODES

    for name in names or ():
        if name not in NODES:
            raise UsageError(f"vectors {command}: --function {name!r} is not a function of the model "
                             f"(functions: {', '.join(NODES)})")
    return list(dict.fromkeys(names)) if names else list(NODES)


def _generate_one(name: str, out_dir: str, timeout_s: float, budget_s: float):
    from atcs.model import NODES
    from atcs.proofs import vector_files
    from atcs.proofs.vectors import generate
    from atcs.properties import PROPERTIES

    node = NODES[name]
    fv = generate(node, tuple(p for p in PROPERTIES.values() if p.node is node), timeout_s=timeout_s,
                  budget_s=budget_s)
    vector_files.write(out_dir, fv)
    return name, len(fv.vectors), fv.coverage(), fv.requirements, fv.requirements_covered(), fv.seconds


def _vectors_generate(args, out: Console, err: Console) -> int:
    from concurrent.futures import ProcessPoolExecutor

    from atcs.proofs import report

    names = _functions("generate", args.function)
    try:
        report.check_writable_dir("--out", args.out)
    except report.OutputPathError as exc:
        raise UsageError(f"vectors generate: {exc}") from None
    start = time.monotonic()
    jobs = [(n, args.out, args.timeout, args.budget) for n in names]
    if args.jobs == 1:
        rows = [_generate_one(*job) for job in jobs]
    else:
        with ProcessPoolExecutor(args.jobs) as pool:
            rows = list(pool.map(_generate_one, *zip(*jobs, strict=True)))
    table = Table(title=f"atcs vectors generate: {len(names)} functions in {time.monotonic() - start:.1f} s "
                  f"({args.out})")
    for heading in ("function", "vectors", "requirements", "boundaries", "MC/DC", "not covered", "seconds"):
        table.add_column(heading, justify="left" if heading == "function" else "right")
    incomplete = False
    for name, count, cov, reqs, covered, seconds in rows:
        def part(kind, cov=cov):
            return f"{cov[kind]['covered']}/{cov[kind]['goals']}"
        left = {s: sum(cov[k][s] for k in cov) for s in ("infeasible", "unknown")}
        incomplete = incomplete or left["unknown"] > 0
        table.add_row(name, str(count), f"{len(covered)}/{len(reqs)} ids, {part('requirement')}", part("boundary"),
                      part("mcdc"), f"{left['infeasible']} infeasible, {left['unknown']} unknown", f"{seconds:.1f}")
    out.print(table)
    return EXIT_UNKNOWN if incomplete else EXIT_OK


def _vector_files(command: str, directory: str, names: list[str] | None = None) -> list:
    from atcs.proofs.vector_files import VectorFileError, read

    root = Path(directory)
    if not root.is_dir():
        raise UsageError(f"vectors {command}: {directory} is not a directory")
    paths = sorted(root.glob("*.json"))
    if names:
        paths = [p for p in paths if p.stem in set(_functions(command, names))]
    if not paths:
        raise UsageError(f"vectors {command}: {directory} holds no vector file (<function>.json)")
    if command == "verify":
        return paths
    try:
        return [read(p) for p in paths]
    except VectorFileError as exc:
        raise UsageError(f"vectors {command}: {exc}") from None


def _vectors_verify(args, out: Console, err: Console) -> int:
    from atcs.proofs.vector_files import VectorFileError
    from atcs.proofs.vector_verify import verify_file

    results = []
    for path in _vector_files("verify", args.dir):
        try:
            results.append(verify_file(path))
        except VectorFileError as exc:
            raise UsageError(f"vectors verify: {exc}") from None
    table = Table(title=f"atcs vectors verify {args.dir}")
    for heading in ("file", "function", "vectors", "verdict"):
        table.add_column(heading)
    for r in results:
        table.add_row(r.path.name, r.function, str(r.vectors),
                      "[green]verified[/]" if r.ok else f"[bold red]{len(r.problems)} problem(s)[/]")
    out.print(table)
    for r in results:
        for problem in r.problems:
            out.print(f"[bold red]{r.path.name}[/]: {problem}")
    return EXIT_OK if all(r.ok for r in results) else EXIT_FALSIFIED


def _vectors_check(args, out: Console, err: Console) -> int:
    from atcs.proofs.vector_check import ImplementationError, ImplementationStartError, check

    files = _vector_files("check", args.dir, args.function)
    try:
        outcomes = check(files, args.impl, rel_tol=args.rel_tol, abs_tol=args.abs_tol, timeout_s=args.timeout)
    except ImplementationStartError as exc:
        raise UsageError(f"vectors check: {exc}") from None
    except ImplementationError as exc:
        print(f"atcs: vectors check: {exc}", file=sys.stderr)
        return EXIT_FALSIFIED
    failed = [o for o in outcomes if not o.passed]
    table = Table(title=f"atcs vectors check {args.dir} --impl {args.impl!r}")
    for heading in ("function", "vectors", "passed", "failed"):
        table.add_column(heading, justify="left" if heading == "function" else "right")
    for vf in files:
        mine = [o for o in outcomes if o.function == vf.node.name]
        table.add_row(vf.node.name, str(len(mine)), str(sum(o.passed for o in mine)),
                      str(sum(not o.passed for o in mine)))
    out.print(table)
    for o in failed:
        out.print(f"[bold red]FAIL[/] {o.id} ({'; '.join(o.covers)}): {o.mismatch}")
    out.print(f"{len(outcomes) - len(failed)} of {len(outcomes)} vectors passed")
    return EXIT_FALSIFIED if failed else EXIT_OK


if __name__ == "__main__":
    sys.exit(main())
