"""``atcs railml``: a line's infrastructure from a railML 3.1 or 3.2 file, as a configuration's ``[[lines]]``
table (docs/configuration.md#railml-3-import).

Exit code 0, or 2 for a file that cannot be imported (one line naming the element, the attribute and the value).
"""

from __future__ import annotations

import argparse
from fractions import Fraction

from atcs.model.numbers import exact_number
from atcs.model.track_layout import MAX_SWITCH_THROW_S
from atcs.proofs.cli._common import EXIT_OK, UsageError, check_outputs

MAX_SWITCH_LENGTH_M = 500
"""The longest switch extent accepted (m)."""


def _bounded(text: str, high, unit: str) -> Fraction:
    """A number in ``(0, high]``, exactly (:func:`~atcs.model.numbers.exact_number`: a huge exponent is refused,
    not expanded)."""
    try:
        value = exact_number(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number of {unit}, got {text!r}") from None
    if not 0 < value <= high:
        raise argparse.ArgumentTypeError(f"must be in (0, {high}] {unit}, got {text!r}")
    return value


def _switch_length(text: str) -> Fraction:
    return _bounded(text, MAX_SWITCH_LENGTH_M, "metres")


def _throw_time(text: str) -> Fraction:
    return _bounded(text, MAX_SWITCH_THROW_S, "seconds")


def add_parser(subparsers) -> None:
    r = subparsers.add_parser("railml", help="import a line from railML 3 as a configuration's [[lines]] table")
    r.add_argument("file", metavar="FILE.xml", help="the railML 3.1 or 3.2 file")
    r.add_argument("--name", required=True, help="the line's name in the configuration")
    r.add_argument(
        "--net-elements",
        metavar="ID,...",
        default=None,
        help="the line's net elements in order, where the topology branches (default: the one chain its "
        "net relations make)",
    )
    r.add_argument(
        "--switch-throw-s",
        metavar="S",
        type=_throw_time,
        default=None,
        help="how long the object controller takes to throw a switch (railML has no such time); needed when the "
        "line runs through a switch",
    )
    r.add_argument(
        "--switch-length-m",
        metavar="M",
        type=_switch_length,
        default=None,
        help="the extent of a switch the file gives neither a linearLocation nor a branch length (default: such a "
        "switch is refused)",
    )
    r.add_argument("--out", metavar="FILE", default=None, help="write the table here (default: print it)")
    r.set_defaults(run=run)


def run(args, out, err) -> int:
    from atcs.model.railml import import_line, line_toml
    from atcs.proofs.files import write_atomic

    check_outputs(files={"--out": args.out})
    order = None if args.net_elements is None else [e.strip() for e in args.net_elements.split(",") if e.strip()]
    line = import_line(args.file, args.name, order, args.switch_length_m)
    if line.switches and args.switch_throw_s is None:
        raise UsageError(
            f"railml: the line runs through {line.switches} switches: give --switch-throw-s, the object "
            "controller's throw time (railML has none)"
        )
    if not line.switches and args.switch_throw_s is not None:
        raise UsageError("railml: --switch-throw-s is given, but the line runs through no switch")
    table = line_toml(line, args.switch_throw_s)
    if args.out is None:
        out.print(table, end="", markup=False, highlight=False)
    else:
        write_atomic(args.out, table)
        out.print(f"wrote the line {line.name!r} ({float(line.length_m):g} m) to {args.out}", markup=False)
    for kind, count in line.not_used:
        err.print(f"not used: {count} {kind}", markup=False, highlight=False)
    return EXIT_OK
