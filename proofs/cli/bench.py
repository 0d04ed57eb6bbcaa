"""``atcs bench [NAME]``: run the benchmarks that compare side by side and print ratios.

Exit code 0, or 2 for an unknown benchmark name.
"""

from __future__ import annotations

import argparse
import time

from atcs.proofs.cli._common import EXIT_OK, UsageError, progress_bar


def add_parser(subparsers) -> None:
    b = subparsers.add_parser(
        "bench",
        help="run benchmarks that compare side by side and print ratios",
        add_help=False,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    b.add_argument("-h", "--help", action=_HelpWithBenchmarks, nargs=0, help="show this help message and exit")
    b.add_argument("name", nargs="?", metavar="NAME", help="one benchmark, listed below (default: all)")
    b.set_defaults(run=run)


def benchmark_list() -> str:
    """One line per registered benchmark: its name and its summary."""
    from atcs.proofs.bench import BENCHMARKS, summary

    width = max(map(len, BENCHMARKS))
    return "benchmarks:\n" + "\n".join(f"  {name:<{width}}  {summary(name)}" for name in BENCHMARKS)


class _HelpWithBenchmarks(argparse.Action):
    """``--help`` listing the benchmarks, read from their registry only when asked (it loads numpy)."""

    def __call__(self, parser, namespace, values, option_string=None):
        parser.epilog = benchmark_list()
        parser.print_help()
        parser.exit()


def run(args, out, err) -> int:
    from atcs.proofs.bench import BENCHMARKS

    if args.name is not None and args.name not in BENCHMARKS:
        raise UsageError(f"bench: unknown benchmark {args.name!r} (known: {', '.join(BENCHMARKS)})")
    for name in [args.name] if args.name else list(BENCHMARKS):
        err.print(f"bench {name}: running")
        start = time.monotonic()
        with progress_bar(err, f"bench {name}", 1) as bar:
            BENCHMARKS[name](out, progress=bar.at)
        err.print(f"bench {name}: done in {time.monotonic() - start:.0f} s")
    return EXIT_OK
