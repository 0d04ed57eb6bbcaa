"""``atcs bench [NAME]``: run the benchmarks that compare side by side and print ratios.

Exit code 0, or 2 for an unknown benchmark name.
"""

from __future__ import annotations

from atcs.proofs.cli._common import EXIT_OK, UsageError


def add_parser(subparsers) -> None:
    b = subparsers.add_parser("bench", help="run benchmarks that compare side by side and print ratios")
    b.add_argument("name", nargs="?", metavar="NAME", help="one benchmark (default: all)")
    b.set_defaults(run=run)


def run(args, out, err) -> int:
    from atcs.proofs.bench import BENCHMARKS

    if args.name is not None and args.name not in BENCHMARKS:
        raise UsageError(f"bench: unknown benchmark {args.name!r} (known: {', '.join(BENCHMARKS)})")
    for name in [args.name] if args.name else list(BENCHMARKS):
        BENCHMARKS[name](out)
    return EXIT_OK
