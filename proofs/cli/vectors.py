"""``atcs vectors generate | verify | check``: certified test vectors of each step function.

Exit codes: ``generate`` 0 every goal settled (covered or shown infeasible), 3 some unknown (a property or a step
that could not be built among them: one line each on stderr); ``verify`` 0 every file verified, 1 a problem;
``check`` 0 every vector passed, 1 one failed or the implementation stopped; all 2 for bad input; ``generate``
130 interrupted (Ctrl-C: the functions generated so far are printed, their files written, no other).
"""

from __future__ import annotations

import sys
import time
from contextlib import nullcontext
from dataclasses import dataclass, field
from pathlib import Path

from rich.table import Table

from atcs.proofs.cli._common import (
    EXIT_FALSIFIED,
    EXIT_INTERRUPTED,
    EXIT_OK,
    EXIT_UNKNOWN,
    Parser,
    UsageError,
    add_jobs,
    check_outputs,
    positive_float,
    progress_bar,
    reraised,
    tolerance,
)


def add_parser(subparsers) -> None:
    v = subparsers.add_parser(
        "vectors", help="certified test vectors of each step function: generate, verify, check an implementation"
    )
    vsub = v.add_subparsers(dest="vectors_command", required=True, parser_class=Parser)
    g = vsub.add_parser("generate", help="find vectors covering requirements, boundaries and MC/DC with z3")
    g.add_argument(
        "--function",
        metavar="NAME",
        action="append",
        help="a function (node) of the model; repeat for several (default: every one)",
    )
    g.add_argument("--out", metavar="DIR", default="vectors", help="where the files go (default ./vectors)")
    _add_config(g, "the functions of this configuration's properties, in the environments of its trains and lines")
    g.add_argument(
        "--timeout",
        metavar="SECONDS",
        type=positive_float,
        default=10.0,
        help="per solver query; past it the goal is unknown (default 10)",
    )
    g.add_argument(
        "--budget",
        metavar="SECONDS",
        type=positive_float,
        default=1800.0,
        help="per function; goals past it are unknown (default 1800)",
    )
    add_jobs(g)
    g.set_defaults(run=generate)
    y = vsub.add_parser("verify", help="re-check vector files against the model (hashes, symbolic and exact)")
    y.add_argument("dir", metavar="DIR")
    _add_config(y, "the configuration the vectors were made for (vectors generate --config)")
    y.set_defaults(run=verify)
    k = vsub.add_parser("check", help="run an external implementation over the vectors (JSON lines)")
    k.add_argument("dir", metavar="DIR")
    k.add_argument(
        "--impl",
        metavar="COMMAND",
        required=True,
        help="the implementation's command line: one JSON request per line in, one answer per line out",
    )
    k.add_argument("--function", metavar="NAME", action="append", help="only this function's file (repeatable)")
    _add_config(k, "the configuration the vectors were made for (vectors generate --config)")
    k.add_argument(
        "--rel-tol",
        metavar="X",
        type=tolerance,
        default=1e-9,
        help="relative tolerance for numbers answered as JSON numbers (default 1e-9)",
    )
    k.add_argument(
        "--abs-tol",
        metavar="X",
        type=tolerance,
        default=1e-9,
        help="absolute tolerance for numbers answered as JSON numbers (default 1e-9)",
    )
    k.add_argument(
        "--timeout",
        metavar="SECONDS",
        type=positive_float,
        default=10.0,
        help="how long to wait for each answer (default 10)",
    )
    k.set_defaults(run=check)


def _add_config(parser, what: str) -> None:
    parser.add_argument("--config", metavar="FILE", help=f"{what} (docs/configuration.md)")


def _configured(path: str | None) -> dict | None:
    """The nodes of the configuration at ``path`` with its properties (None without one)."""
    if path is None:
        return None
    from atcs.proofs.engine.suite import configured_nodes

    return configured_nodes(path)


def _functions(command: str, names: list[str] | None, configured: dict | None = None) -> list[str]:
    from atcs.model import NODES

    known = NODES if configured is None else configured
    for name in names or ():
        if name not in known:
            what = "the model" if configured is None else "the configuration's properties"
            raise UsageError(
                f"vectors {command}: --function {name!r} is not a function of {what} (functions: {', '.join(known)})"
            )
    return list(dict.fromkeys(names)) if names else list(known)


@dataclass
class _Generated:
    """One function's outcome for the table; ``errors``: what could not be built, one line each."""

    function: str
    vectors: int = 0
    coverage: dict | None = None
    """Per kind of goal, the counts (:meth:`~atcs.proofs.vectors.generate.FunctionVectors.coverage`); None when
    the step could not be built."""
    requirements: list[str] = field(default_factory=list)
    covered: list[str] = field(default_factory=list)
    seconds: float = 0.0
    errors: list[str] = field(default_factory=list)

    @property
    def incomplete(self) -> bool:
        return self.coverage is None or any(c["unknown"] for c in self.coverage.values())

    def cells(self) -> tuple[str, ...]:
        if self.coverage is None:
            return (self.function, "0", "not built", "", "", "", f"{self.seconds:.1f}")
        cov = self.coverage
        left = {s: sum(cov[k][s] for k in cov) for s in ("infeasible", "unknown")}

        def part(kind):
            return f"{cov[kind]['covered']}/{cov[kind]['goals']}"

        return (
            self.function,
            str(self.vectors),
            f"{len(self.covered)}/{len(self.requirements)} ids, {part('requirement')}",
            part("boundary"),
            part("mcdc"),
            f"{left['infeasible']} infeasible, {left['unknown']} unknown",
            f"{self.seconds:.1f}",
        )


def _generate_one(name: str, out_dir: str, timeout_s: float, budget_s: float, config: str | None = None) -> _Generated:
    """One function's vectors, written to ``out_dir`` (module level: a worker process runs it), in the
    environments of the registered properties or of the configuration ``config``'s; none, and the reason in
    ``errors``, if its step cannot be built."""
    from atcs.model import NODES
    from atcs.proofs.engine.suite import configuration_data_sha256
    from atcs.proofs.vectors import files
    from atcs.proofs.vectors.generate import StepBuildError
    from atcs.proofs.vectors.generate import generate as generate_vectors
    from atcs.properties import PROPERTIES

    if config is None:
        node, props, made_for = NODES[name], tuple(p for p in PROPERTIES.values() if p.node is NODES[name]), None
    else:
        from atcs.model.configuration import load_configuration

        node, props = _configured(config)[name]
        made_for = {"name": load_configuration(config).name, "data_sha256": configuration_data_sha256(props)}
    start = time.monotonic()
    try:
        fv = generate_vectors(node, props, timeout_s=timeout_s, budget_s=budget_s)
    except StepBuildError as exc:
        return _Generated(name, seconds=time.monotonic() - start, errors=[str(exc)])
    fv.configuration = made_for
    files.write(out_dir, fv)
    return _Generated(
        name, len(fv.vectors), fv.coverage(), fv.requirements, fv.requirements_covered(), fv.seconds, fv.errors
    )


def generate(args, out, err) -> int:
    names = _functions("generate", args.function, _configured(args.config))
    check_outputs(dirs={"--out": args.out})
    start = time.monotonic()
    rows = _generate_all([(n, args.out, args.timeout, args.budget, args.config) for n in names], args.jobs, err)
    table = Table(
        title=f"atcs vectors generate: {len(rows)} functions in {time.monotonic() - start:.1f} s ({args.out})"
    )
    for heading in ("function", "vectors", "requirements", "boundaries", "MC/DC", "not covered", "seconds"):
        table.add_column(heading, justify="left" if heading == "function" else "right")
    for row in rows:
        table.add_row(*row.cells())
    out.print(table)
    for row in rows:
        for error in row.errors:
            print(f"atcs: vectors generate: {row.function}: {error}", file=sys.stderr)
    if len(rows) < len(names):  # interrupted: the files of the functions above are written, no other
        out.print(f"[yellow]interrupted[/] after {len(rows)} of {len(names)} functions; only their files are written")
        return EXIT_INTERRUPTED
    return EXIT_UNKNOWN if any(row.incomplete for row in rows) else EXIT_OK


def _generate_all(jobs: list[tuple], workers: int, err) -> list[_Generated]:
    """Each function's vectors, generated and written, as they finish (a line each in a log); fewer on Ctrl-C."""
    from atcs.proofs.workers import worker_pool

    rows = []
    with progress_bar(err, "generating", len(jobs)) as bar:
        try:
            with worker_pool(workers) if workers > 1 else nullcontext() as pool:
                for row in (pool.map if pool else map)(_generate_one, *zip(*jobs, strict=True)):
                    rows.append(row)
                    bar.done(f"generated {row.function}: {row.vectors} vectors")
        except KeyboardInterrupt:
            pass
    return rows


def _vector_files(command: str, directory: str, names: list[str] | None = None, configured=None) -> list:
    from atcs.proofs.vectors.files import VectorFileError, read

    root = Path(directory)
    if not root.is_dir():
        raise UsageError(f"vectors {command}: {directory} is not a directory")
    paths = sorted(root.glob("*.json"))
    if names:
        paths = [p for p in paths if p.stem in set(_functions(command, names, configured))]
    if not paths:
        raise UsageError(f"vectors {command}: {directory} holds no vector file (<function>.json)")
    if command == "verify":
        return paths
    with reraised(f"vectors {command}: ", VectorFileError):
        return [read(p, configured) for p in paths]


def verify(args, out, err) -> int:
    from atcs.proofs.vectors.files import VectorFileError
    from atcs.proofs.vectors.verify import verify_file

    configured = _configured(args.config)
    with reraised("vectors verify: ", VectorFileError):
        results = [verify_file(path, configured) for path in _vector_files("verify", args.dir)]
    table = Table(title=f"atcs vectors verify {args.dir}")
    for heading in ("file", "function", "vectors", "verdict"):
        table.add_column(heading)
    for r in results:
        table.add_row(
            r.path.name,
            r.function,
            str(r.vectors),
            "[green]verified[/]" if r.ok else f"[bold red]{len(r.problems)} problem(s)[/]",
        )
    out.print(table)
    for r in results:
        for problem in r.problems:
            out.print(f"[bold red]{r.path.name}[/]: {problem}")
    return EXIT_OK if all(r.ok for r in results) else EXIT_FALSIFIED


def check(args, out, err) -> int:
    from atcs.proofs.vectors.check import ImplementationError, ImplementationStartError
    from atcs.proofs.vectors.check import check as check_implementation
    from atcs.proofs.vectors.files import edits

    files = _vector_files("check", args.dir, args.function, _configured(args.config))
    for vf in files:
        found = edits(vf)
        if found:
            raise UsageError(
                f"vectors check: {vf.path}: {found[0]}; a vector file is checked only as generated "
                "(atcs vectors verify lists every difference)"
            )
    try:
        with reraised("vectors check: ", ImplementationStartError):
            outcomes = check_implementation(
                files, args.impl, rel_tol=args.rel_tol, abs_tol=args.abs_tol, timeout_s=args.timeout
            )
    except ImplementationError as exc:
        print(f"atcs: vectors check: {exc}", file=sys.stderr)
        return EXIT_FALSIFIED
    failed = [o for o in outcomes if not o.passed]
    table = Table(title=f"atcs vectors check {args.dir} --impl {args.impl!r}")
    for heading in ("function", "vectors", "passed", "failed"):
        table.add_column(heading, justify="left" if heading == "function" else "right")
    for vf in files:
        mine = [o for o in outcomes if o.function == vf.node.name]
        table.add_row(
            vf.node.name, str(len(mine)), str(sum(o.passed for o in mine)), str(sum(not o.passed for o in mine))
        )
    out.print(table)
    for o in failed:
        out.print(f"[bold red]FAIL[/] {o.id} ({'; '.join(o.covers)}): {o.mismatch}")
    out.print(f"{len(outcomes) - len(failed)} of {len(outcomes)} vectors passed")
    return EXIT_FALSIFIED if failed else EXIT_OK
