"""The ``atcs`` command line: one module per command, each with ``add_parser(subparsers)`` and a ``run``;
:mod:`._common` holds what they share (exit codes, progress, output checks, the property selection).

Exit codes (docs/exit-codes.md): 0 everything asked for holds, 1 a verdict against, 2 bad input, 3 incomplete;
``replay`` adds 4 (each command's module says what its codes mean). Any command: 70 an internal error, one line
on stderr (``ATCS_TRACEBACK=1`` re-raises it with its traceback), 130 interrupted.
"""

from __future__ import annotations

import argparse
import os
import sys

from rich.console import Console

from atcs.model.errors import AtcsInputError
from atcs.proofs.cli import (
    bench,
    certify,
    conformance,
    coverage,
    curves,
    headway,
    mutate,
    platforms,
    prove,
    railml,
    replay,
    sim,
    vectors,
)
from atcs.proofs.cli._common import EXIT_INTERNAL, EXIT_INTERRUPTED, EXIT_USAGE, Parser, UsageError

__all__ = ["build_parser", "main", "version_lines"]

COMMANDS = (
    prove,
    certify,
    replay,
    coverage,
    curves,
    conformance,
    railml,
    platforms,
    sim,
    headway,
    mutate,
    bench,
    vectors,
)
TRACEBACK_VARIABLE = "ATCS_TRACEBACK"
"""Set to 1, an internal error or an interruption is re-raised with its traceback (for developers)."""


def build_parser() -> Parser:
    parser = Parser(prog="atcs", description="Prove, replay and benchmark the atcs ATP model.")
    parser.add_argument(
        "--version",
        action=_PrintVersion,
        nargs=0,
        help="print the versions of atcs, Python, z3 and cvc5 and the model's source hash, and exit",
    )
    subparsers = parser.add_subparsers(dest="command", required=True, parser_class=Parser)
    for command in COMMANDS:
        command.add_parser(subparsers)
    return parser


def version_lines() -> list[str]:
    """atcs, Python, z3 and cvc5 versions and the SHA-256 of the model's and properties' sources (the one vector
    files record), one per line."""
    from atcs.proofs.certify.campaign import solver_versions
    from atcs.proofs.vectors.files import model_sha256, tool_versions

    tools, solvers = tool_versions(), solver_versions()
    return [
        f"atcs {tools['atcs']}",
        f"Python {tools['python']}",
        f"z3 {solvers['z3']}",
        f"cvc5 {solvers['cvc5']}",
        f"model sha256 {model_sha256()}",
    ]


class _PrintVersion(argparse.Action):
    """``--version``: one line per version, then exit 0 (as ``--help`` does)."""

    def __call__(self, parser, namespace, values, option_string=None):
        print("\n".join(version_lines()))
        parser.exit()


def main(argv: list[str] | None = None) -> int:
    out, err = Console(), Console(stderr=True)
    if not out.is_terminal:  # logs and pipes: tables 160 columns wide, and a long line is never broken
        out = Console(width=160, soft_wrap=True)
    args = None
    try:
        args = build_parser().parse_args(argv)
        return args.run(args, out, err)
    except UsageError as exc:
        print(f"atcs: error: {exc}", file=sys.stderr)
    except AtcsInputError as exc:
        print(f"atcs: error: {_command(args)}: {exc}", file=sys.stderr)
    except KeyboardInterrupt:
        if os.environ.get(TRACEBACK_VARIABLE) == "1":
            raise
        print("atcs: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except Exception as exc:  # a bug of atcs: one line, not a traceback
        if os.environ.get(TRACEBACK_VARIABLE) == "1":
            raise
        print(f"atcs: internal error: {_command(args)}: {_described(exc)} (please report this)", file=sys.stderr)
        return EXIT_INTERNAL
    return EXIT_USAGE


def _described(exc: Exception) -> str:
    """``<ExceptionType>: <message>`` on one line (the type alone for an empty message)."""
    message = " ".join(str(exc).splitlines())
    return f"{type(exc).__name__}: {message}" if message else type(exc).__name__


def _command(args) -> str:
    if args is None:  # the command line was not parsed yet
        return "atcs"
    sub = getattr(args, "vectors_command", None)
    return args.command if sub is None else f"{args.command} {sub}"


if __name__ == "__main__":
    sys.exit(main())
