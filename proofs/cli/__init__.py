"""The ``atcs`` command line: one module per command, each with ``add_parser(subparsers)`` and a ``run``;
:mod:`._common` holds what they share (exit codes, progress, output checks, the property selection).

Exit codes (docs/design.md): 0 everything asked for holds, 1 a verdict against, 2 bad input, 3 incomplete;
``replay`` adds 4 (each command's module says what its codes mean).
"""

from __future__ import annotations

import sys

from rich.console import Console

from atcs.model.errors import AtcsInputError
from atcs.proofs.cli import bench, certify, curves, headway, mutate, platforms, prove, replay, sim, vectors
from atcs.proofs.cli._common import EXIT_USAGE, Parser, UsageError

__all__ = ["build_parser", "main"]

COMMANDS = (prove, certify, replay, curves, platforms, sim, headway, mutate, bench, vectors)


def build_parser() -> Parser:
    parser = Parser(prog="atcs", description="Prove, replay and benchmark the atcs ATP model.")
    subparsers = parser.add_subparsers(dest="command", required=True, parser_class=Parser)
    for command in COMMANDS:
        command.add_parser(subparsers)
    return parser


def main(argv: list[str] | None = None) -> int:
    out, err = Console(), Console(stderr=True)
    if not out.is_terminal:  # logs and pipes: do not truncate property names to 80 columns
        out = Console(width=160)
    try:
        args = build_parser().parse_args(argv)
        return args.run(args, out, err)
    except UsageError as exc:
        print(f"atcs: error: {exc}", file=sys.stderr)
    except AtcsInputError as exc:
        print(f"atcs: error: {_command(args)}: {exc}", file=sys.stderr)
    return EXIT_USAGE


def _command(args) -> str:
    sub = getattr(args, "vectors_command", None)
    return args.command if sub is None else f"{args.command} {sub}"


if __name__ == "__main__":
    sys.exit(main())
