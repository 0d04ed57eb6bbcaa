"""``atcs headway``: the least steady-state headway, measured in closed loop, the ATP's and the separation
invariant's, in both modes (sim/headway.py explains the three figures).

Exit code 0, or 2 for a bad speed: not a number, or outside the range the measurement runs at
(:func:`~atcs.sim.headway.speed_range_kmh`).
"""

from __future__ import annotations

from rich.table import Table

from atcs.proofs.cli._common import EXIT_OK, UsageError, progress_bar, reraised


def add_parser(subparsers) -> None:
    h = subparsers.add_parser(
        "headway",
        help="the least steady-state headway: measured in closed loop, the ATP's "
        "and the separation invariant's, in both modes",
    )
    h.add_argument("--speed", metavar="KMH", default="80", help="the steady speed (km/h, default 80)")
    h.set_defaults(run=run)


def _check_speed(text: str, speed) -> None:
    """Refuse a speed the measurement cannot run at (:func:`~atcs.sim.headway.speed_range_kmh` says why)."""
    from atcs.sim.headway import speed_range_kmh

    lowest, highest = speed_range_kmh()
    if not lowest <= speed <= highest:
        raise UsageError(
            f"headway: --speed = {text!r} is outside the supported range, {float(lowest):g} to {float(highest):g} km/h "
            f"(below {float(lowest):g} the run reaches no steady state; above {float(highest):g} the measurement is "
            "not checked)"
        )


def run(args, out, err) -> int:
    from atcs.model.profile import ProfileError, parse_number
    from atcs.sim.headway import HeadwayError, headway_report

    with reraised("", ProfileError):
        speed = parse_number("headway", "--speed", args.speed, ProfileError)
    _check_speed(args.speed, speed)
    with reraised("headway: ", HeadwayError), progress_bar(err, "cycles", 1) as bar:
        rows = headway_report(
            speed,
            on_mode=lambda mode: err.print(f"headway: measuring {mode} at {float(speed):g} km/h (a closed-loop run)"),
            progress=bar.at,
        )
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
