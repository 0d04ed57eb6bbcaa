"""``atcs certify``: write each proved property's certificate (SMT-LIB 2) and check it with z3 and cvc5.

Exit code 0 every selected property certified, 1 a solver disagrees, 3 some property unconfirmed, not proved
or in error (and none disagrees), 2 bad input, 130 interrupted (Ctrl-C: each certificate checked so far is
printed, no certificates.json is written).
"""

from __future__ import annotations

import json
import time
from pathlib import Path

from rich.table import Table

from atcs.proofs.cli._common import (
    EXIT_INTERRUPTED,
    UsageError,
    add_jobs,
    add_only,
    check_outputs,
    exit_code,
    matching,
    positive_float,
    positive_int,
    progress_bar,
    reraised,
    selected_properties,
)

STYLE = {
    "certified": "green",
    "unconfirmed": "yellow",
    "disagreement": "bold red",
    "error": "bold magenta",
    "not proved": "yellow",
}


def add_parser(subparsers) -> None:
    f = subparsers.add_parser(
        "certify", help="write each proved property's certificate (SMT-LIB 2) and check it with z3 and cvc5"
    )
    add_only(f)
    f.add_argument(
        "--config",
        metavar="FILE",
        help="certify the train- and line-dependent properties of this configuration (docs/configuration.md) "
        "instead of the registered ones",
    )
    f.add_argument(
        "--report",
        metavar="FILE",
        help="take the proofs' depths from this atcs prove --json report (default: prove first)",
    )
    f.add_argument(
        "--dir",
        metavar="DIR",
        default="certificates",
        help="where the scripts and certificates.json are written (default ./certificates)",
    )
    f.add_argument(
        "--timeout",
        metavar="SECONDS",
        type=positive_float,
        default=600.0,
        help="per-property limit of the proving, and per-check limit of each solver that has no "
        "limit of its own (default 600)",
    )
    for solver in ("z3", "cvc5"):
        f.add_argument(
            f"--{solver}-timeout",
            metavar="SECONDS",
            type=positive_float,
            default=None,
            help=f"per-check time limit of {solver}; past it the check is unknown (default --timeout)",
        )
    f.add_argument(
        "--cvc5-rlimit",
        metavar="UNITS",
        type=positive_int,
        default=None,
        help="also bound each cvc5 check by this many of its resource units (rlimit-per): the same "
        "verdict on any machine; past it the check is unknown (default: no bound)",
    )
    f.add_argument(
        "--z3-only",
        metavar="PATTERN[,PATTERN...]",
        default=None,
        help="globs over property names: check these with z3 alone (cvc5 is not asked; they stay unconfirmed)",
    )
    f.add_argument(
        "--reuse",
        metavar="LISTING",
        default=None,
        help="an earlier run's certificates.json: a script byte for byte the same as one it records cvc5 finding "
        "unsat (same SHA-256, same cvc5 version) is not given to cvc5 again; z3 checks every script",
    )
    add_jobs(f)
    f.set_defaults(run=run)


def run(args, out, err) -> int:
    from atcs.proofs.certify import campaign
    from atcs.proofs.engine.split import covering_parts
    from atcs.proofs.engine.suite import configured_registry
    from atcs.proofs.files import write_atomic

    registry = configured_registry(args.config)
    props = selected_properties("certify", args.only, _configured(args.config, registry))
    check_outputs(dirs={"--dir": args.dir})
    z3_only = _z3_only(args.z3_only, registry)
    if args.reuse is not None:
        with reraised("certify: --reuse ", campaign.ListingError):
            err.print(f"certify: reusing {args.reuse}: {campaign.cvc5_unsat_scripts(args.reuse)[1]}")
    start = time.monotonic()
    needed = {lemma for p in props for lemma in _lemma_closure(p, registry)}
    wanted = [*props, *(registry[n] for n in sorted(needed - {p.name for p in props}))]
    if args.report is not None:
        with reraised("certify: --report ", campaign.ProveReportError):
            depths = campaign.depths_from_report(args.report, registry)
    else:
        depths = _prove_depths(wanted, args, err, registry)
    pieces = {p.name: covering_parts(p.name, depths) for p in wanted if p.name not in depths}
    parts = [registry[n] for names in pieces.values() if names for n in names]
    known = {p.name for p in wanted} | {p.name for p in parts}
    lemmas = sorted({n for p in parts for n in _lemma_closure(p, registry)} - known)
    if lemmas and args.report is None:  # a part's lemma that was not split with it: proved whole
        depths |= _prove_depths([registry[n] for n in lemmas], args, err, registry)
    wanted = [*wanted, *parts, *(registry[n] for n in lemmas)]
    limits = {"z3": args.z3_timeout or args.timeout, "cvc5": args.cvc5_timeout or args.timeout}
    results = _certify_all(campaign, wanted, depths, limits, z3_only, args, err)
    if len(results) < sum(p.name in depths for p in wanted):  # interrupted: each certificate checked so far
        for c in results.values():
            out.print(f"{c.own_status()} {c.name} (own checks, lemmas aside; confirmed by {', '.join(c.confirmed_by)})")
        out.print(f"[yellow]interrupted[/] after {len(results)} certificates; no certificates.json written")
        return EXIT_INTERRUPTED
    campaign.settle(results, depths)
    wall = time.monotonic() - start

    directory = Path(args.dir)
    directory.mkdir(parents=True, exist_ok=True)
    records = []
    for prop in props:
        c = results.get(prop.name)
        if c is None and pieces.get(prop.name):
            made = [_write(campaign, results[n], directory) | {"part_of": prop.name} for n in pieces[prop.name]]
            records += [_in_parts(prop, made), *made]
            continue
        if c is None:
            partial = any(n.startswith(f"{prop.name}_h") for n in depths)
            records.append(
                {
                    "name": prop.name,
                    "requirement": prop.requirement,
                    "k": None,
                    "lemmas": list(prop.lemmas),
                    "status": campaign.CertificateStatus.NOT_PROVED,
                    "confirmed_by": [],
                    "message": "no proof to certify" + (", and its proved parts do not cover it" if partial else ""),
                    "checks": [],
                }
            )
            continue
        records.append(_write(campaign, c, directory))
    wholes = [r for r in records if r.get("part_of") is None]
    counts = {s: sum(r["status"] == s for r in wholes) for s in STYLE}
    write_atomic(
        directory / "certificates.json",
        json.dumps(
            {
                "tool": "atcs certify",
                "solvers": list(campaign.SOLVERS),
                "solver_versions": campaign.solver_versions(),
                "timeout_s": args.timeout,
                "solver_timeout_s": limits,
                "cvc5_resource_limit": args.cvc5_rlimit,
                "z3_only": sorted(z3_only & {p.name for p in wanted}),
                "reused": args.reuse,
                "wall_s": round(wall, 3),
                "summary": counts,
                "properties": records,
            },
            indent=2,
        )
        + "\n",
    )
    _print(out, records, wall, directory)
    return exit_code(against=counts["disagreement"] > 0, incomplete=counts["certified"] != len(wholes))


def _write(campaign, c, directory: Path) -> dict:
    """Write the certificate's scripts under ``directory``; its record."""
    from atcs.proofs.files import write_atomic

    (directory / c.name).mkdir(parents=True, exist_ok=True)
    for ob in c.obligations:
        write_atomic(directory / c.name / f"{ob.check}.smt2", ob.script)
    return campaign.record(c, directory)


_WORST_FIRST = ("disagreement", "error", "not proved", "unconfirmed", "certified")


def _in_parts(prop, parts: list[dict]) -> dict:
    """The record of a property proved in parts (:mod:`atcs.proofs.engine.split`): certified when every part is."""
    status = min((r["status"] for r in parts), key=_WORST_FIRST.index)
    counts = {s: sum(r["status"] == s for r in parts) for s in _WORST_FIRST}
    message = f"{len(parts)} parts: " + ", ".join(f"{n} {s}" for s, n in counts.items() if n)
    if status != "certified":
        first = next(r for r in parts if r["status"] == status)
        message += f"; {first['name']}: {first['message']}"
    confirmed = set.intersection(*(set(r["confirmed_by"]) for r in parts))
    return {
        "name": prop.name,
        "requirement": prop.requirement,
        "k": None,
        "lemmas": list(prop.lemmas),
        "status": status,
        "confirmed_by": sorted(confirmed),
        "message": message,
        "checks": [],
        "parts": [r["name"] for r in parts],
    }


def _certify_all(campaign, wanted: list, depths: dict, limits: dict, z3_only: set, args, err) -> dict:
    """Each certificate by name, checked, as they finish (a line each in a log); fewer on Ctrl-C."""
    results = {}
    with progress_bar(err, "certifying", sum(p.name in depths for p in wanted)) as bar:
        try:
            for c in campaign.run(
                wanted,
                depths,
                timeout_s=limits,
                jobs=args.jobs,
                cvc5_resource_limit=args.cvc5_rlimit,
                z3_only=z3_only,
                configuration=args.config,
                reuse=args.reuse,
            ):
                results[c.name] = c
                bar.done(f"certified {c.name}", f"{c.own_status()} {c.name} (own checks, lemmas aside)")
        except KeyboardInterrupt:
            pass
    return results


def _prove_depths(wanted: list, args, err, registry) -> dict[str, int]:
    """The depth of each property ``wanted`` that the prover proves now, and of each part of those it proves in
    parts (:mod:`atcs.proofs.engine.split`)."""
    from atcs.proofs.engine import suite
    from atcs.proofs.engine.split import leaves, prove_in_parts

    depths = {}
    names = {p.name for p in wanted}
    with progress_bar(err, "proving", len(wanted)) as bar:

        def prove_round(level: list):
            bar.more(sum(p.name not in names for p in level))
            for result in suite.run(level, timeout_s=args.timeout, jobs=args.jobs, configuration=args.config):
                bar.done(f"proving {result.name}: {result.status}")
                yield result

        for result in prove_in_parts(wanted, prove_round):
            depths |= {r.name: r.k for r in leaves([result]) if r.status == "proved"}
    return depths


def _print(out, records: list[dict], wall_s: float, directory: Path) -> None:
    table = Table(title=f"atcs certify: {len(records)} properties in {wall_s:.2f} s ({directory})")
    for heading in ("property", "requirement", "k", "checks", "confirmed by", "status"):
        table.add_column(heading, justify="right" if heading == "k" else "left")
    for r in records:
        table.add_row(
            r["name"],
            r["requirement"],
            "" if r["k"] is None else str(r["k"]),
            str(len(r["checks"])),
            ", ".join(r["confirmed_by"]) or "none",
            f"[{STYLE[r['status']]}]{r['status']}[/]",
        )
    out.print(table)
    for r in records:
        if r["status"] != "certified":
            out.print(f"[{STYLE[r['status']]}]{r['status']}[/] {r['name']}: {r['message']}")


def _configured(path: str | None, registry: dict) -> dict | None:
    """The configuration's own properties by name (None without one): the registry less the registered ones."""
    from atcs.properties import PROPERTIES

    return None if path is None else {n: p for n, p in registry.items() if n not in PROPERTIES}


def _z3_only(patterns: str | None, registry) -> set[str]:
    """The properties ``--z3-only`` names; a glob that matches none is a usage error."""
    names: set[str] = set()
    for pattern in [] if patterns is None else patterns.split(","):
        matched = set(matching(registry, [pattern.strip()]))
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
