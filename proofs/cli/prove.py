"""``atcs prove``: prove the registered properties, or with ``--config`` a configuration's train- and
line-dependent ones; a table, the JSON and JUnit reports, counterexample files.

Exit code 0 all proved, 1 some property falsified, 3 some vacuous, unknown or in error and none falsified (an
``error`` verdict is never a pass), or a configuration's property not made ("not covered"), 2 bad input, 130
interrupted (Ctrl-C: the verdicts so far are printed, no report is written).
"""

from __future__ import annotations

import itertools
import time

from rich.table import Table

from atcs.proofs.cli._common import (
    EXIT_INTERRUPTED,
    UsageError,
    add_jobs,
    add_only,
    check_outputs,
    exit_code,
    positive_float,
    progress_bar,
    selected_properties,
)

SCOPE = (
    "the closed-loop theorems hold on the line's own gradient profile for an end of authority (of target speed 0, "
    "or any up to the top limit) anywhere on it under any MRSP up to the line's top speed limit, and for each speed "
    "decrease of the line's MRSP as a target, in windows of the line (docs/configuration.md)"
)
"""What ``--config``'s closed-loop theorems cover, printed before the verdicts."""

STYLE = {"proved": "green", "vacuous": "yellow", "falsified": "bold red", "unknown": "yellow", "error": "bold magenta"}


def add_parser(subparsers) -> None:
    p = subparsers.add_parser("prove", help="prove the registered safety properties")
    add_only(p)
    p.add_argument(
        "--config",
        metavar="FILE",
        help="prove the train- and line-dependent properties of this configuration (TOML: trains, national "
        "values, lines, docs/configuration.md) instead of the registered ones",
    )
    p.add_argument(
        "--cache",
        metavar="DIR",
        help="keep proved verdicts here and reuse those whose property, data and imported sources are unchanged "
        "(docs/commands.md)",
    )
    p.add_argument(
        "--map",
        metavar="DIR",
        help="with --config and a train with ranges: write the envelope's map there (map.json, and a PNG of each "
        "2-D slice, docs/configuration.md)",
    )
    p.add_argument(
        "--ray",
        metavar="ADDRESS",
        help="prove the cells of ranges on Ray: 'auto' starts a local cluster of --jobs CPUs, an address joins a "
        "running one (needs pip install 'atcs[cluster]'); without it, local worker processes",
    )
    p.add_argument("--json", metavar="FILE", help="write the JSON report here")
    p.add_argument("--junit", metavar="FILE", help="write a JUnit XML report here")
    p.add_argument(
        "--catalogue",
        metavar="FILE",
        help="write the property catalogue (Markdown: each property as registered, with this run's verdict) here",
    )
    p.add_argument(
        "--timeout",
        metavar="SECONDS",
        type=positive_float,
        default=600.0,
        help="per-property time limit, lemmas included; past it the verdict is unknown (default 600)",
    )
    add_jobs(p)
    p.add_argument(
        "--cex-dir",
        metavar="DIR",
        default="counterexamples",
        help="where counterexamples are written as JSON, CSV, VCD and PNG (default ./counterexamples)",
    )
    p.add_argument(
        "--witness-dir",
        metavar="DIR",
        default=None,
        help="also write each proved property's witness runs (its assumptions and every implication's "
        "condition reached) here as JSON",
    )
    p.add_argument(
        "--cores",
        action="store_true",
        help="also give each property proved by k-induction its validity core: the state equations, assumptions "
        "and lemmas the proof needs, and those it does not (in the table, the JSON and the catalogue)",
    )
    p.add_argument(
        "--core-timeout",
        metavar="SECONDS",
        type=positive_float,
        default=60.0,
        help="per-property time limit of --cores; past it the core is sufficient but not minimal (default 60)",
    )
    refine = p.add_mutually_exclusive_group()
    refine.add_argument(
        "--smooth",
        action="store_true",
        help="make each counterexample one with the fewest input changes (same length; the time left "
        "within --timeout; the count before and after is in the reports)",
    )
    refine.add_argument(
        "--nominal",
        action="store_true",
        help="make each counterexample one whose measured inputs equal the true values, and whose other inputs "
        "are nearest 0, as far as the violation allows (same length; the time left within --timeout; the "
        "distances before and after are in the reports)",
    )
    p.set_defaults(run=run)


def run(args, out, err) -> int:
    from atcs.proofs import report
    from atcs.proofs.engine.suite import configured_registry
    from atcs.proofs.files import write_atomic

    configured, gaps = _configured(args.config, out)
    props = selected_properties("prove", args.only, configured)
    check_outputs(
        files={"--json": args.json, "--junit": args.junit, "--catalogue": args.catalogue},
        dirs={"--cex-dir": args.cex_dir, "--witness-dir": args.witness_dir, "--cache": args.cache, "--map": args.map},
    )
    ranged = _ranged(args)
    start = time.monotonic()
    plain = [p for p in props if p.name not in ranged]
    registry = configured_registry(args.config)
    results = _prove_or_reuse(plain, registry, args, out, err)
    maps = {}
    if len(results) == len(plain):  # not interrupted: the properties over ranges next
        maps, envelope_results = _envelopes([p.name for p in props if p.name in ranged], args, err)
        results |= envelope_results
    wall = time.monotonic() - start
    if len(results) < len(props):  # interrupted: what was proved so far, and nothing written
        _print(out, [report.result_record(p, results[p.name], None) for p in props if p.name in results], wall)
        out.print(f"[yellow]interrupted[/] after {len(results)} of {len(props)} properties; no report written")
        return EXIT_INTERRUPTED

    records = [r for prop in props for r in _records(prop, results[prop.name], registry, args)]
    if args.cores:
        _add_cores(records, registry, args, out, err)
    _print(out, records, wall)
    envelopes = _write_maps(maps, args, out) if maps else None
    if args.json:
        write_atomic(
            args.json,
            report.json_report(
                records,
                timeout_s=args.timeout,
                wall_s=wall,
                configuration=args.config,
                not_covered=gaps,
                envelopes=envelopes,
            ),
        )
    records = [r for r in records if r["part_of"] is None]  # the parts are in the JSON report and the table
    if args.junit:
        write_atomic(args.junit, report.junit_report(records, wall_s=wall))
    if args.catalogue:
        from atcs.proofs.catalogue import catalogue_markdown

        write_atomic(args.catalogue, catalogue_markdown(props, {r["name"]: r for r in records}))
    statuses = {r["status"] for r in records}
    incomplete = bool(statuses & {"vacuous", "unknown", "error"} or gaps)  # a configuration not wholly covered
    return exit_code(against="falsified" in statuses, incomplete=incomplete)


def _add_cores(records: list[dict], registry, args, out, err) -> None:
    """Each record proved by k-induction gets its validity core (``core``); those with parts no proof needs are
    listed."""
    from atcs.proofs.engine.cores import validity_core

    proved = [r for r in records if r["status"] == "proved" and r["engine"] == "k-induction" and r["k"] is not None]
    with progress_bar(err, "validity cores", len(proved)) as bar:
        for record in proved:
            prop = registry[record["name"]]
            lemmas = tuple(registry[name] for name in prop.lemmas)
            try:
                core = validity_core(prop, lemmas, record["k"], args.core_timeout)
            except ValueError as exc:  # the checks disagree with the proof: say so, keep the verdict as it is
                record["core"] = None
                bar.done(record["name"], f"no core {record['name']}: {exc}")
                out.print(f"[red]{record['name']}: no validity core[/]: {exc}", highlight=False)
                continue
            record["core"] = core.record()
            bar.done(record["name"], f"core {record['name']}: {len(core.needs)} needed ({core.seconds:.1f} s)")
    for record in proved:  # the flags: an assumption or a lemma no proof needs
        if record["core"] is None:
            continue
        unneeded = [part for part in record["core"]["unneeded"] if not part.startswith("equation ")]
        if unneeded:
            out.print(f"{record['name']}: the proof does not need {', '.join(unneeded)}", highlight=False)


def _records(prop, result, registry, args, part_of: str | None = None) -> list[dict]:
    """The report records of ``prop`` and, if it was proved in parts, of each part after it (each naming the
    property it is part of); counterexample and witness files written. A property falsified in parts points to its
    falsified part's counterexample."""
    from atcs.proofs import report

    parts = [r for part in result.parts for r in _records(registry[part.name], part, registry, args, prop.name)]
    cex = None
    if result.parts:
        cex = next((r["counterexample"] for r in parts if r["status"] == "falsified" and r["counterexample"]), None)
    elif result.trace is not None and result.replay is not None:
        cex = str(report.write_counterexample(args.cex_dir, prop, result))
    if args.witness_dir is not None and result.witnesses:
        report.write_witnesses(args.witness_dir, prop, result)
    record = report.result_record(prop, result, cex) | {"part_of": part_of}
    return [record, *parts]


def _configured(path: str | None, out) -> tuple[dict | None, tuple[str, ...]]:
    """The properties of the configuration at ``path`` by name (None without one), and what they leave out,
    printed first."""
    if path is None:
        return None, ()
    from atcs.model.configuration import load_configuration
    from atcs.properties.configured import configuration_gaps, configuration_properties

    config = load_configuration(path)
    gaps = configuration_gaps(config)
    out.print(f"[bold]scope[/] {SCOPE}")
    for gap in gaps:
        out.print(f"[yellow]not covered[/] {gap}")
    return {p.name: p for p in configuration_properties(config)}, gaps


def _prove_or_reuse(props: list, registry, args, out, err) -> dict:
    """The verdict of each property by name, those that come back ``unknown`` and can be split proved in parts
    (:mod:`atcs.proofs.engine.split`); with ``--cache``, the kept verdicts reused (said in a line) and the proved
    ones kept, parts included (:mod:`atcs.proofs.engine.cache`)."""
    if args.cache is None:
        return _prove_all(props, args, err, registry, None)
    from atcs.proofs.engine.cache import VerdictCache

    cache = VerdictCache(args.cache, registry)
    reused = {p.name: r for p in props if (r := cache.get(p)) is not None}
    if reused:
        out.print(f"reused {len(reused)} proved verdicts from {args.cache}: " + ", ".join(sorted(reused)))
    results = _prove_all([p for p in props if p.name not in reused], args, err, registry, cache)
    return {**reused, **results}


def _ranged(args) -> set[str]:
    """The names of the configuration's properties proved over ranges of train data (none without one)."""
    if args.config is None:
        if args.map or args.ray:
            raise UsageError(f"{'--map' if args.map else '--ray'} needs --config (a configuration with ranges)")
        return set()
    from atcs.model.configuration import load_configuration
    from atcs.proofs.envelope import envelope_properties

    ranged = set(envelope_properties(load_configuration(args.config)))
    if not ranged and (args.map or args.ray):
        raise UsageError(f"{'--map' if args.map else '--ray'}: {args.config} gives no train a range of train data")
    return ranged


def _envelopes(names: list[str], args, err) -> tuple[dict, dict]:
    """The map of each property proved over ranges, and its verdict as a result (the worst cell's)."""
    from atcs.proofs.engine.prove import Result
    from atcs.proofs.envelope import sweep
    from atcs.proofs.envelope.executors import RayUnavailable, local_executor, ray_executor

    if not names:
        return {}, {}
    executor = ray_executor(args.ray, args.jobs) if args.ray else local_executor(args.jobs)
    maps = {}
    with progress_bar(err, "proving cells", None) as bar:
        try:
            with executor as tasks:
                maps = sweep(
                    args.config,
                    names,
                    timeout_s=args.timeout,
                    executor=tasks,
                    cache_dir=args.cache,
                    on_cell=lambda name, c: bar.done(
                        f"{name} [{c.cell.describe()}]: {c.status}",
                        f"{c.status} {name} [{c.cell.describe()}] ({c.seconds:.1f} s)",
                    ),
                )
        except KeyboardInterrupt:
            return {}, {}
        except RayUnavailable as exc:
            raise UsageError(str(exc)) from None
    results = {}
    for name, m in maps.items():
        failing = next((c.failing for c in m.cells if c.status == m.status and c.failing is not None), None)
        message = m.describe() + (f"; {failing.name}: {failing.message}" if failing is not None else "")
        results[name] = Result(name, m.requirement, m.status, "envelope", None, m.seconds, message)
    return maps, results


def _write_maps(maps: dict, args, out) -> list[dict]:
    """Counterexample files of the falsified cells, the map's JSON and plots (with ``--map``); the JSON entries."""
    from atcs.model.configuration import load_configuration
    from atcs.proofs import report
    from atcs.proofs.envelope import map_json, write_map
    from atcs.proofs.envelope.sweep import cell_proofs

    config = load_configuration(args.config)
    counterexamples = {}
    for name, m in maps.items():
        for c in m.cells:
            failing = c.failing
            if c.status == "falsified" and failing is not None and failing.replay is not None:
                prop = next(p for p, _ in cell_proofs(config, name, c.cell) if p.name == failing.name)
                counterexamples[(name, c.cell.id)] = str(report.write_counterexample(args.cex_dir, prop, failing))
    entries = map_json(maps, counterexamples)
    reused = [f"{m.name} [{c.cell.describe()}]" for m in maps.values() for c in m.cells if c.reused]
    if reused:
        out.print(f"reused proved cell proofs from {args.cache}: " + ", ".join(reused))
    for m in maps.values():
        out.print(f"envelope {m.name}: [{STYLE[m.status]}]{m.status}[/] ({m.describe()})")
    if args.map:
        for path in write_map(maps, counterexamples, args.map):
            out.print(f"map: {path}")
    return entries


def _prove_all(props: list, args, err, registry, cache) -> dict:
    """The verdict of each property by name, as they finish (a line each in a log, parts included); fewer on
    Ctrl-C."""
    from atcs.proofs.engine import suite
    from atcs.proofs.engine.split import prove_in_parts

    results = {}
    wanted = {p.name for p in props}
    with progress_bar(err, "proving", len(props)) as bar:

        def prove_round(level: list):
            parts = [p for p in level if p.name not in wanted]
            bar.more(len(parts))
            kept = {p.name: r for p in parts if cache is not None and (r := cache.get(p)) is not None}
            rest = [p for p in level if p.name not in kept]
            proved = suite.run(
                rest,
                timeout_s=args.timeout,
                jobs=args.jobs,
                smooth=args.smooth,
                nominal=args.nominal,
                configuration=args.config,
            )
            for result in itertools.chain(kept.values(), proved if rest else ()):
                if cache is not None:
                    cache.put(registry[result.name], result)
                again = result.status == "unknown" and registry[result.name].split is not None
                line = f"{result.status} {result.name} ({result.seconds:.1f} s)" + (", in parts next" if again else "")
                bar.done(f"{result.name}: {result.status}", line + (" (reused)" if result.name in kept else ""))
                yield result

        try:
            for result in prove_in_parts(props, prove_round):
                if cache is not None:
                    cache.put(registry[result.name], result)
                results[result.name] = result
        except KeyboardInterrupt:
            pass
    return results


def _print(out, records: list[dict], wall_s: float) -> None:
    wholes = [r for r in records if r.get("part_of") is None]
    parts = f" ({len(records) - len(wholes)} parts)" if len(records) > len(wholes) else ""
    table = Table(title=f"atcs prove: {len(wholes)} properties{parts} in {wall_s:.2f} s")
    for heading in ("property", "requirement", "status", "engine", "k", "seconds"):
        table.add_column(heading, justify="right" if heading in ("k", "seconds") else "left")
    for r in records:
        table.add_row(
            r["name"],
            r["requirement"],
            f"[{STYLE[r['status']]}]{r['status']}[/]",
            r["engine"] or "",
            "" if r["k"] is None else str(r["k"]),
            f"{r['seconds']:.3f}",
        )
    out.print(table)
    for r in records:
        if r["status"] != "proved":
            out.print(
                f"[{STYLE[r['status']]}]{r['status']}[/] {r['name']}: {r['message']}"
                + (f" (counterexample: {r['counterexample']})" if r["counterexample"] else "")
            )
