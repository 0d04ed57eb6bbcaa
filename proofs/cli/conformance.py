"""``atcs conformance [FRAME ...]``: the braking curves against reference frames of the ERA braking-curves tool
(docs/conformance.md); without a frame, the two shipped ones.

Exit code 0 every row within its tolerance, 1 a row outside it, 2 a frame that cannot be read.
"""

from __future__ import annotations

from rich.table import Table

from atcs.proofs.cli._common import EXIT_FALSIFIED, EXIT_OK, reraised


def add_parser(subparsers) -> None:
    c = subparsers.add_parser(
        "conformance", help="compare the braking curves with reference frames of the ERA braking-curves tool"
    )
    c.add_argument("frames", nargs="*", metavar="FRAME", help="frame files (JSON); default: the shipped frames")
    c.add_argument("--rows", action="store_true", help="list every row, not only the summary per curve")
    c.set_defaults(run=run)


def run(args, out, err) -> int:
    from atcs.proofs.conformance.check import check_frame, check_inputs, worst_by_curve
    from atcs.proofs.conformance.frames import FrameError, load_frame, shipped_frames

    paths = args.frames or shipped_frames()
    with reraised("conformance: ", FrameError):
        frames = [load_frame(p) for p in paths]
    failed = False
    for frame in frames:
        results, inputs = check_frame(frame), check_inputs(frame)
        table = Table(title=f"{frame.path.name}: {frame.name}, {len(results)} rows")
        for heading in ("curve", "rows", "within tolerance", "worst error", "tolerance"):
            table.add_column(heading, justify="left" if heading == "curve" else "right")
        for curve, (rows, agree, worst) in worst_by_curve(results).items():
            unit = "m/s^2" if curve == "A_safe" else "m"
            tolerance = max(r.row.tolerance for r in results if r.row.curve == curve)
            style = "" if agree == rows else "[bold red]"
            table.add_row(curve, str(rows), f"{style}{agree}", f"{float(worst):.4f} {unit}", f"{float(tolerance):g}")
        compared = [i for i in inputs if i.agrees is not None]
        if inputs:
            table.add_row(
                "input checks", str(len(inputs)), f"{sum(bool(i.agrees) for i in compared)} of {len(compared)}", "", ""
            )
        out.print(table)
        for i in inputs:
            if i.agrees is None:
                out.print(f"  not compared: {i.row.quantity} (atcs does not compute it)", highlight=False)
        if frame.not_compared:
            out.print(f"  not compared: {', '.join(frame.not_compared)} (not a curve atcs computes)")
        for r in results:
            if args.rows or not r.agrees:
                mark = "ok " if r.agrees else "OUT"
                where = f" at {float(r.row.location_m):g} m" if r.row.location_m is not None else ""
                values = f"expected {float(r.row.expected):g}, computed {float(r.computed):.4f}"
                out.print(
                    f"  {mark} {r.row.curve} at {float(r.row.speed_kmh):g} km/h{where}: {values} "
                    f"(tolerance {float(r.row.tolerance):g})",
                    highlight=False,
                )
        failed |= not all(r.agrees for r in results) or not all(i.agrees for i in compared)
    return EXIT_FALSIFIED if failed else EXIT_OK
