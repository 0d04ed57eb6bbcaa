"""``atcs prove``: prove the registered properties, or with ``--config`` a configuration's train- and
line-dependent ones; a table, the JSON and JUnit reports, counterexample files.

Exit code 0 all proved, 1 some property falsified, 3 some vacuous, unknown or in error and none falsified (an
``error`` verdict is never a pass), or a configuration's property not made ("not covered"), 2 bad input, 130
interrupted (Ctrl-C: the verdicts so far are printed, no report is written).
"""

from __future__ import annotations

import time

from rich.table import Table

from atcs.proofs.cli._common import (
    EXIT_INTERRUPTED,
    add_jobs,
    add_only,
    check_outputs,
    exit_code,
    positive_float,
    progress_bar,
    selected_properties,
)

SCOPE = (
    "each closed-loop theorem holds on one gradient transition of the line (two segments) under any constant MRSP, "
    "not yet across three or more segments nor with the MRSP's decreases as targets (docs/configuration.md)"
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
    from atcs.proofs.files import write_atomic

    configured, gaps = _configured(args.config, out)
    props = selected_properties("prove", args.only, configured)
    check_outputs(
        files={"--json": args.json, "--junit": args.junit, "--catalogue": args.catalogue},
        dirs={"--cex-dir": args.cex_dir, "--witness-dir": args.witness_dir, "--cache": args.cache},
    )
    start = time.monotonic()
    results = _prove_or_reuse(props, configured, args, out, err)
    wall = time.monotonic() - start
    if len(results) < len(props):  # interrupted: what was proved so far, and nothing written
        _print(out, [report.result_record(p, results[p.name], None) for p in props if p.name in results], wall)
        out.print(f"[yellow]interrupted[/] after {len(results)} of {len(props)} properties; no report written")
        return EXIT_INTERRUPTED

    records = []
    for prop in props:
        result = results[prop.name]
        cex = None
        if result.trace is not None and result.replay is not None:
            cex = str(report.write_counterexample(args.cex_dir, prop, result))
        if args.witness_dir is not None and result.witnesses:
            report.write_witnesses(args.witness_dir, prop, result)
        records.append(report.result_record(prop, result, cex))
    _print(out, records, wall)
    if args.json:
        write_atomic(
            args.json,
            report.json_report(
                records, timeout_s=args.timeout, wall_s=wall, configuration=args.config, not_covered=gaps
            ),
        )
    if args.junit:
        write_atomic(args.junit, report.junit_report(records, wall_s=wall))
    if args.catalogue:
        from atcs.proofs.catalogue import catalogue_markdown

        write_atomic(args.catalogue, catalogue_markdown(props, {r["name"]: r for r in records}))
    statuses = {r["status"] for r in records}
    incomplete = bool(statuses & {"vacuous", "unknown", "error"} or gaps)  # a configuration not wholly covered
    return exit_code(against="falsified" in statuses, incomplete=incomplete)


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


def _prove_or_reuse(props: list, configured: dict | None, args, out, err) -> dict:
    """The verdict of each property by name: with ``--cache``, the kept ones reused (said in a line) and the
    others proved and kept (:mod:`atcs.proofs.engine.cache`)."""
    if args.cache is None:
        return _prove_all(props, args, err)
    from atcs.proofs.engine.cache import VerdictCache
    from atcs.properties import PROPERTIES

    cache = VerdictCache(args.cache, {**PROPERTIES, **(configured or {})})
    reused = {p.name: r for p in props if (r := cache.get(p)) is not None}
    if reused:
        out.print(f"reused {len(reused)} proved verdicts from {args.cache}: " + ", ".join(sorted(reused)))
    results = _prove_all([p for p in props if p.name not in reused], args, err)
    for prop in props:
        if prop.name in results:
            cache.put(prop, results[prop.name])
    return {**reused, **results}


def _prove_all(props: list, args, err) -> dict:
    """The verdict of each property by name, as they finish (a line each in a log); fewer on Ctrl-C."""
    from atcs.proofs.engine import suite

    results = {}
    with progress_bar(err, "proving", len(props)) as bar:
        try:
            for result in suite.run(
                props,
                timeout_s=args.timeout,
                jobs=args.jobs,
                smooth=args.smooth,
                nominal=args.nominal,
                configuration=args.config,
            ):
                results[result.name] = result
                bar.done(f"{result.name}: {result.status}", f"{result.status} {result.name} ({result.seconds:.1f} s)")
        except KeyboardInterrupt:
            pass
    return results


def _print(out, records: list[dict], wall_s: float) -> None:
    table = Table(title=f"atcs prove: {len(records)} properties in {wall_s:.2f} s")
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
