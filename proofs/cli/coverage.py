"""``atcs coverage``: which lines and decisions of ``model/`` the terms of the properties reach.

Exit code 0 every line and decision reached by some property or allowlisted, 1 some reached by none and not
allowlisted (listed), 2 bad input.
"""

from __future__ import annotations

import json

from rich.table import Table

from atcs.proofs.cli._common import (
    EXIT_FALSIFIED,
    EXIT_OK,
    UsageError,
    add_only,
    check_outputs,
    progress_bar,
    reraised,
    selected_properties,
)


def add_parser(subparsers) -> None:
    c = subparsers.add_parser(
        "coverage",
        help="which lines and decisions of model/ the terms of the properties reach; those no property reaches",
    )
    add_only(c)
    c.add_argument(
        "--report",
        metavar="FILE",
        help="count only the properties proved in this atcs prove --json report (default every one selected)",
    )
    c.add_argument("--allowlist", metavar="FILE", help="the allowlist (default proofs/coverage/allowlist.toml)")
    c.add_argument("--json", metavar="FILE", help="write the JSON report here")
    c.add_argument(
        "--annotate",
        metavar="DIR",
        help="write each model module's source with the properties reaching each line as DIR/<module>.txt",
    )
    c.set_defaults(run=run)


def run(args, out, err) -> int:
    from atcs.proofs import coverage
    from atcs.proofs.files import write_atomic

    properties = selected_properties("coverage", args.only)
    if args.report is not None:
        proved = _proved(args.report)
        properties = [p for p in properties if p.name in proved]
        if not properties:
            raise UsageError(f"coverage: --report {args.report}: none of the selected properties is proved in it")
    check_outputs(files={"--json": args.json}, dirs={"--annotate": args.annotate})
    with reraised("coverage: --allowlist ", coverage.AllowlistError):
        allowlist = coverage.load_allowlist(args.allowlist or coverage.ALLOWLIST)
    with progress_bar(err, "tracing", len(properties)) as bar:
        reached = coverage.reach_all(properties, progress=lambda name: bar.done(name))
    result = coverage.Coverage(coverage.all_sites(), tuple(reached), allowlist)
    _print(out, result, len(properties))
    if args.json:
        write_atomic(args.json, json.dumps(result.record(), indent=2) + "\n")
    if args.annotate:
        from pathlib import Path

        Path(args.annotate).mkdir(parents=True, exist_ok=True)
        for module, path in coverage.model_modules().items():
            text = result.annotated(module, path.read_text().splitlines())
            write_atomic(Path(args.annotate) / f"{module}.txt", text)
    return EXIT_FALSIFIED if result.unreached() else EXIT_OK


def _proved(path: str) -> set[str]:
    """The properties a prove report gives as proved (a ``--report`` that is not one is bad input)."""
    from atcs.model.data_files import read_json
    from atcs.proofs.certify.campaign import ProveReportError
    from atcs.properties import PROPERTIES

    with reraised("coverage: --report ", ProveReportError):
        doc = read_json(path, ProveReportError, "the prove report")
        records = doc.get("properties") if isinstance(doc, dict) else None
        if not isinstance(records, list):
            raise ProveReportError(f"{path}: properties is missing or not a list (is it an atcs prove --json report?)")
        proved = set()
        for j, record in enumerate(records):
            name = record.get("name") if isinstance(record, dict) else None
            status = record.get("status") if isinstance(record, dict) else None
            if not isinstance(name, str) or not isinstance(status, str):
                raise ProveReportError(f"{path}: properties[{j}] = {record!r} has no name and status")
            if status == "proved" and name in PROPERTIES:
                proved.add(name)
    return proved


def _print(out, result, count: int) -> None:
    table = Table(title=f"proof coverage of model/ by {count} properties (lines and Ops decisions their terms reach)")
    for column in ("module", "lines", "decisions", "allowlisted", "of which open", "unreached"):
        table.add_column(column, justify="left" if column == "module" else "right")
    totals = [0] * 7
    for row in result.modules():
        table.add_row(
            row.module.removeprefix("atcs.model."),
            f"{row.lines_reached}/{row.lines}",
            f"{row.decisions_reached}/{row.decisions}",
            str(row.allowlisted),
            str(row.open),
            f"[bold red]{row.unreached}[/]" if row.unreached else "0",
        )
        values = (row.lines_reached, row.lines, row.decisions_reached, row.decisions, row.allowlisted, row.open)
        for k, v in enumerate((*values, row.unreached)):
            totals[k] += v
    table.add_row(
        "total",
        f"{totals[0]}/{totals[1]}",
        f"{totals[2]}/{totals[3]}",
        *(str(v) for v in totals[4:]),
        style="bold",
    )
    out.print(table)
    unreached = result.unreached()
    by_function: dict[str, list] = {}
    for site in unreached:
        by_function.setdefault(f"{site.module}.{site.function}", []).append(site)
    for function, sites in by_function.items():
        lines = sorted({s.line for s in sites})
        decisions = sum(s.kind != "line" for s in sites)
        span = f"line {lines[0]}" if len(lines) == 1 else f"lines {lines[0]}-{lines[-1]}"
        out.print(
            f"[red]unreached[/] {function} ({span}: {sum(s.kind == 'line' for s in sites)} lines, {decisions} "
            "decisions)",
            highlight=False,
            soft_wrap=True,
        )
    for allowance in result.unused_allowances():
        out.print(f"[yellow]allowlist entry covers nothing unreached[/]: {allowance.functions}", soft_wrap=True)
    if not unreached:
        out.print("every line and decision of model/ is reached by a property or allowlisted")
