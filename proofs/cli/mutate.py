"""``atcs mutate``: mutate the model's step functions systematically and prove the properties about each
mutant; the kill rate per module, the survivors with their diff.

Exit code 0 every counted mutant killed (or equivalent), 1 some mutant survived, 3 some timed out and none
survived, 2 bad input, 130 interrupted (Ctrl-C: the outcomes so far are printed, no report written).
"""

from __future__ import annotations

import json
import time
from contextlib import suppress

from rich.table import Table

from atcs.proofs.cli._common import (
    EXIT_FALSIFIED,
    EXIT_INTERRUPTED,
    EXIT_OK,
    EXIT_UNKNOWN,
    UsageError,
    add_jobs,
    check_outputs,
    matching,
    positive_float,
    progress_bar,
    reraised,
)

STYLE = {"killed": "green", "survived": "bold red", "timeout": "yellow", "incompetent": "magenta", "equivalent": "cyan"}


def add_parser(subparsers) -> None:
    u = subparsers.add_parser(
        "mutate",
        help="mutate the model's step functions systematically and prove the "
        "properties about each mutant; kill rate per module, survivors with their diff",
    )
    u.add_argument(
        "--only",
        metavar="PATTERN",
        action="append",
        help="glob over mutant ids (module.function:+line:operator:...), e.g. 'doors.*'; repeatable",
    )
    u.add_argument(
        "--nodes",
        metavar="PATTERN",
        action="append",
        help="prove only the properties of the nodes matching this glob, e.g. 'door*'; repeatable "
        "(default every node whose proofs run the mutated function)",
    )
    u.add_argument(
        "--timeout",
        metavar="SECONDS",
        type=positive_float,
        default=120.0,
        help="per-mutant time limit over all its properties; past it the verdict is timeout (default 120)",
    )
    add_jobs(u)
    u.add_argument("--json", metavar="FILE", help="write the JSON report here")
    u.add_argument(
        "--equivalents",
        metavar="FILE",
        default=None,
        help="registry of equivalent mutants (default proofs/mutation/equivalent_mutants.toml)",
    )
    u.add_argument("--list", action="store_true", help="list the selected mutants and exit")
    u.set_defaults(run=run)


def run(args, out, err) -> int:
    from atcs.proofs.files import write_atomic
    from atcs.proofs.mutation import campaign
    from atcs.proofs.mutation.equivalents import REGISTRY, EquivalentsError, load_equivalents

    mutants = campaign.all_mutants()
    selected, nodes = _selected(args, mutants)
    with reraised("mutate: --equivalents ", EquivalentsError):
        equivalent = load_equivalents(args.equivalents or REGISTRY, known={m.id for m in mutants})
    check_outputs(files={"--json": args.json})
    if args.list:
        for m in selected:
            print(m.id + ("  (equivalent)" if m.id in equivalent else ""))  # one id a line, never wrapped
        return EXIT_OK

    start = time.monotonic()
    outcomes = _mutate_all(campaign, selected, equivalent, nodes, args, err)
    wall = time.monotonic() - start
    rates = campaign.kill_rates(outcomes)
    _print(out, outcomes, rates, wall)
    if len(outcomes) < len(selected):  # interrupted: the outcomes so far, and nothing written
        out.print(f"[yellow]interrupted[/] after {len(outcomes)} of {len(selected)} mutants; no report written")
        return EXIT_INTERRUPTED
    if args.json:
        doc = {
            "tool": "atcs mutate",
            "timeout_s": args.timeout,
            "nodes": list(nodes) if nodes else None,
            "only": args.only,
            "wall_seconds": round(wall, 3),
            "kill_rates": rates,
            "mutants": [o.record() for o in outcomes],
        }
        write_atomic(args.json, json.dumps(doc, indent=2) + "\n")
    verdicts = {o.verdict for o in outcomes}
    if "survived" in verdicts:
        return EXIT_FALSIFIED
    return EXIT_UNKNOWN if "timeout" in verdicts else EXIT_OK


def _mutate_all(campaign, selected: list, equivalent: dict, nodes, args, err) -> list:
    """Each mutant's outcome, as they finish (a line each in a log); fewer on Ctrl-C."""
    outcomes = []

    def done(o) -> None:
        outcomes.append(o)
        bar.done(f"{o.mutant.id}: {o.verdict}", f"{o.verdict} {o.mutant.id} ({o.seconds:.1f} s)")

    with progress_bar(err, "mutating", len(selected)) as bar, suppress(KeyboardInterrupt):
        campaign.run(selected, timeout_s=args.timeout, jobs=args.jobs, equivalent=equivalent, nodes=nodes, on_done=done)
    order = {m.id: i for i, m in enumerate(selected)}
    return sorted(outcomes, key=lambda o: order[o.mutant.id])


def _selected(args, mutants) -> tuple[list, tuple[str, ...] | None]:
    """The mutants ``--only`` and ``--nodes`` select, and the nodes (None: every node that runs the mutant)."""
    from atcs.proofs.mutation import campaign

    selected = [m for m in mutants if args.only is None or matching([m.id], args.only)]
    if not selected:
        modules = sorted({m.model_module for m in mutants})
        raise UsageError(f"mutate: --only {' '.join(args.only)!r} matches no mutant (modules: {', '.join(modules)})")
    if args.nodes is None:
        return selected, None
    known = campaign.node_names()
    nodes = tuple(matching(known, args.nodes))
    if not nodes:
        raise UsageError(f"mutate: --nodes {' '.join(args.nodes)!r} matches no node (nodes: {', '.join(known)})")
    selected = [m for m in selected if campaign.affected_properties(m, nodes)]
    if not selected:
        raise UsageError(f"mutate: no selected mutant's function is run by the --nodes {' '.join(args.nodes)!r}")
    return selected, nodes


def _print(out, outcomes, rates, wall_s: float) -> None:
    from atcs.proofs.mutation import campaign

    table = Table(title=f"atcs mutate: {len(outcomes)} mutants in {wall_s:.1f} s")
    for heading in ("module", *campaign.VERDICTS, "kill rate"):
        table.add_column(heading, justify="left" if heading == "module" else "right")
    for module, r in rates.items():
        rate = "-" if r["kill_rate"] is None else f"{100 * r['kill_rate']:.1f} %"
        table.add_row(module, *(str(r[v]) for v in campaign.VERDICTS), rate, end_section=module == [None, *rates][-2])
    out.print(table)
    for o in outcomes:
        if o.verdict in ("survived", "timeout", "incompetent"):
            out.print(
                f"[{STYLE[o.verdict]}]{o.verdict}[/] {o.mutant.id} (line {o.mutant.line}): {o.message}", highlight=False
            )
            if o.verdict == "survived":
                out.print(o.mutant.diff, markup=False, highlight=False)
