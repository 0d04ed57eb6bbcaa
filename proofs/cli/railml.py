"""``atcs railml``: a line's infrastructure from a railML 3.1 or 3.2 file, as a configuration's ``[[lines]]``
table (docs/configuration.md#railml-3-import).

Exit code 0, or 2 for a file that cannot be imported (one line naming the element, the attribute and the value).
"""

from __future__ import annotations

from atcs.proofs.cli._common import EXIT_OK, check_outputs


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
    r.add_argument("--out", metavar="FILE", default=None, help="write the table here (default: print it)")
    r.set_defaults(run=run)


def run(args, out, err) -> int:
    from atcs.model.railml import import_line, line_toml
    from atcs.proofs.files import write_atomic

    check_outputs(files={"--out": args.out})
    order = None if args.net_elements is None else [e.strip() for e in args.net_elements.split(",") if e.strip()]
    line = import_line(args.file, args.name, order)
    table = line_toml(line)
    if args.out is None:
        out.print(table, end="", markup=False, highlight=False)
    else:
        write_atomic(args.out, table)
        out.print(f"wrote the line {line.name!r} ({float(line.length_m):g} m) to {args.out}", markup=False)
    for kind, count in line.not_used:
        err.print(f"not used: {count} <{kind}>", markup=False, highlight=False)
    return EXIT_OK
