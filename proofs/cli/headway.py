"""``atcs headway``: the least steady-state headway, measured in closed loop, the ATP's and the separation
invariant's, in both modes (sim/headway.py explains the three figures).

Exit code 0, or 2 for a bad speed.
"""

from __future__ import annotations

from rich.table import Table

from atcs.proofs.cli._common import EXIT_OK, UsageError, reraised


def add_parser(subparsers) -> None:
    h = subparsers.add_parser(
        "headway",
        help="the least steady-state headway: measured in closed loop, the ATP's "
        "and the separation invariant's, in both modes",
    )
    h.add_argument("--speed", metavar="KMH", default="80", help="the steady speed (km/h, default 80)")
    h.set_defaults(run=run)


def run(args, out, err) -> int:
    from atcs.model.profile import ProfileError, parse_number
    from atcs.sim.headway import HeadwayError, headway_report

    with reraised("", ProfileError):
        speed = parse_number("headway", "--speed", args.speed, ProfileError)
    if not 0 < speed <= 120:
        raise UsageError(f"headway: --speed = {args.speed!r} must be in (0, 120] km/h")
    with reraised("headway: ", HeadwayError):
        rows = headway_report(speed)
    table = Table(
        title=f"headway at a steady {float(speed):g} km/h: gap from the follower's front to the leader's "
        "rear, and (gap + train length) / speed"
    )
    for column in ("mode", "measured (sim)", "ATP-limited", "invariant bound"):
        table.add_column(column, justify="left" if column == "mode" else "right")
    for row in rows:
        table.add_row(
            row["mode"],
            *(
                f"{float(row[f'{k}_gap_m']):.1f} m, {float(row[f'{k}_headway_s']):.1f} s"
                for k in ("measured", "atp", "invariant")
            ),
        )
    out.print(table)
    out.print(
        f"measured with {float(rows[0]['resource_length_m']):g} m resources (sim/headway.py explains the three figures)"
    )
    return EXIT_OK
