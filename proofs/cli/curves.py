"""``atcs curves``: draw the braking curves of a train, track and movement authority (PNG and SVG), and answer
the ERA tool's query of where each curve reaches a speed.

Exit code 0, or 2 for bad train or track data.
"""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

from rich.table import Table

from atcs.proofs.cli._common import EXIT_OK, UsageError, reraised


def add_parser(subparsers) -> None:
    c = subparsers.add_parser("curves", help="draw the braking curves of a train, track and MA (PNG and SVG)")
    c.add_argument(
        "--train",
        metavar="PRESET|FILE",
        default="seed000",  # train_data.PRESETS
        help="seed000 or seed002 (a seed's train and national data, default seed000), or a train data file "
        "(TOML, Gamma or Lambda, docs/train-data.md) with Subset-026's national values",
    )
    c.add_argument(
        "--special-brakes",
        metavar="BRAKE,...",
        default="",
        help="with a train data file: the special brakes active (regenerative, eddy_current, magnetic_shoe, ep), "
        "whose brake models the file declares (default none active)",
    )
    c.add_argument(
        "--mrsp",
        metavar="M:KMH,...",
        default="0:80,600:60,900:70,1200:40",
        help="MRSP as start:limit pairs, metres and km/h (default %(default)s)",
    )
    c.add_argument(
        "--gradient",
        metavar="M:PERMILLE,...",
        default="0:0,500:-10,1100:5",
        help="compensated gradient as start:per-mille pairs, uphill positive (default %(default)s)",
    )
    c.add_argument("--eoa", metavar="M", default="1500", help="end of authority (m, default %(default)s)")
    c.add_argument("--eoa-speed", metavar="KMH", default="0", help="target speed at the EoA (km/h, default 0)")
    c.add_argument("--front", metavar="M", default="0", help="the max safe front: curves from here (m, default 0)")
    c.add_argument(
        "--a-est",
        metavar="MPS2",
        default=None,
        help="estimated acceleration for the EBI (m/s^2, default the train's maximum)",
    )
    c.add_argument(
        "--speed",
        metavar="KMH",
        default=None,
        help="also print where each target's curves reach this speed (the ERA tool's query)",
    )
    c.add_argument(
        "--out", metavar="DIR", default="curves", help="where curves.png and curves.svg go (default ./curves)"
    )
    c.set_defaults(run=run)


def _pairs(option: str, text: str) -> tuple[list[str], list[str]]:
    starts, values = [], []
    for item in text.split(","):
        start, sep, value = item.strip().partition(":")
        if not sep or not start or not value:
            raise UsageError(f"curves: {option}: {item.strip()!r} is not START:VALUE (in {text!r})")
        starts.append(start)
        values.append(value)
    return starts, values


def run(args, out, err) -> int:
    from atcs.model import braking_data, train_data
    from atcs.model.curves import check_braking_capability
    from atcs.model.dynamic_profile import Horizon
    from atcs.model.profile import KMH_PER_MPS
    from atcs.model.restrictions import as_float
    from atcs.sim.plots import planning_area, sampled_curves

    name, train, national = _train(args)
    q = _query(args, train)
    guidance = None
    if name not in train_data.PRESETS:  # the train's data for the EoA's target speed (T_be, T_bs: cm0 or cmt)
        rail = braking_data_of(args)
        speed_kmh = q["eoa_speed"] * KMH_PER_MPS
        train = braking_data.curve_train_data(rail, national, speed_kmh)
        national = braking_data.curve_national_data(rail, national, speed_kmh)
        with reraised("curves: --train ", train_data.TrainDataError):
            guidance = braking_data.guidance_data(rail)
    with reraised("curves: ", train_data.TrainDataError):
        train_data.validate(train, national)
        check_braking_capability(train, national, q["gradient"], guidance)

    horizon = Horizon(q["mrsp"], q["gradient"], q["eoa_m"], q["eoa_speed"])
    sampled = sampled_curves(
        train,
        national,
        Horizon(as_float(q["mrsp"]), as_float(q["gradient"]), float(q["eoa_m"]), float(q["eoa_speed"])),
        float(q["front_m"]),
        float(q["a_est"]),
    )
    directory = Path(args.out)
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise UsageError(f"curves: --out {args.out!r}: {exc.strerror}") from None
    title = f"{name}: braking curves to the EoA at {float(q['eoa_m']):g} m (A_est {float(q['a_est']):.2f} m/s²)"
    paths = planning_area(sampled, float(q["eoa_m"]), title, [directory / "curves.png", directory / "curves.svg"])
    out.print("wrote " + ", ".join(str(p) for p in paths))
    if q["speed"] is not None:
        _print_locations(out, train, national, horizon, q)
        if q["eoa_speed"] == 0:
            _print_service_curves(out, train, national, guidance, q)
    return EXIT_OK


def braking_data_of(args):
    """The train of the ``--train`` file with the brake models of ``--special-brakes`` (a usage error naming the
    file, the field and the value if bad)."""
    from atcs.model.braking_data import with_special_brakes
    from atcs.model.train_data import TrainDataError
    from atcs.model.train_files import load_train

    with reraised("curves: --train ", TrainDataError):
        train = load_train(args.train)
    active = [b.strip() for b in args.special_brakes.split(",") if b.strip()]
    with reraised("curves: --special-brakes: ", TrainDataError):
        return with_special_brakes(train, active)


def _train(args):
    """``(name, train data, national data)`` of ``--train``: a preset, or a train data file (its data for a
    target at standstill; ``run`` derives it again for the EoA's speed)."""
    from atcs.model import braking_data, train_data

    if args.train in train_data.PRESETS:
        if args.special_brakes:
            raise UsageError(f"curves: --special-brakes needs a train data file, not the preset {args.train!r}")
        train, national = (make() for make in train_data.PRESETS[args.train])
        return args.train, train, national
    if not args.train.endswith(".toml"):
        raise UsageError(
            f"curves: --train = {args.train!r} is neither a preset ({', '.join(train_data.PRESETS)}) nor a .toml file"
        )
    rail, national = braking_data_of(args), train_data.subset026_national()
    return rail.name, braking_data.curve_train_data(rail, national, 0), national


def _query(args, train) -> dict:
    """The options as exact numbers and profiles; a bad or out-of-range one is a usage error."""
    from atcs.model.configuration import MAX_LINE_M
    from atcs.model.profile import (
        KMH_PER_MPS,
        MAX_SPEED_KMH,
        ProfileError,
        gradient_profile,
        parse_number,
        speed_profile,
    )

    with reraised("curves: ", ProfileError):
        q = {
            "eoa_m": parse_number("--eoa", "metres", args.eoa),
            "eoa_speed": parse_number("--eoa-speed", "km/h", args.eoa_speed) / KMH_PER_MPS,
            "front_m": parse_number("--front", "metres", args.front),
            "a_est": train.max_acceleration_mps2
            if args.a_est is None
            else parse_number("--a-est", "m/s^2", args.a_est),
            "speed": None if args.speed is None else parse_number("--speed", "km/h", args.speed) / KMH_PER_MPS,
        }
        mrsp_starts, limits = _pairs("--mrsp", args.mrsp)
        gradient_starts, gradients = _pairs("--gradient", args.gradient)
        starts = [parse_number("--mrsp", "start", s) for s in mrsp_starts]
        end_m = max(q["eoa_m"], *starts, *(parse_number("--gradient", "start", s) for s in gradient_starts)) + 100
        q["mrsp"] = speed_profile("--mrsp", mrsp_starts, limits, end_m)
        q["gradient"] = gradient_profile("--gradient", gradient_starts, gradients, end_m)
    speed, top, a_max = q["speed"], MAX_SPEED_KMH / KMH_PER_MPS, train.max_acceleration_mps2
    for option, value, ok, why in (
        ("--eoa", q["eoa_m"], 0 < q["eoa_m"] <= MAX_LINE_M, f"above 0, at most {MAX_LINE_M} m"),
        ("--eoa-speed", q["eoa_speed"], 0 <= q["eoa_speed"] <= top, f"0 to {MAX_SPEED_KMH} km/h"),
        ("--front", q["front_m"], 0 <= q["front_m"] < q["eoa_m"], "from 0, before the EoA"),
        ("--a-est", q["a_est"], 0 <= q["a_est"] <= a_max, f"from 0 to the train's A_max, {float(a_max):.4g} m/s^2"),
        ("--speed", speed, speed is None or 0 < speed <= top, f"above 0, at most {MAX_SPEED_KMH} km/h"),
    ):
        if not ok:
            shown = float(value * KMH_PER_MPS) if option in ("--eoa-speed", "--speed") else float(value)
            raise UsageError(f"curves: {option} = {shown:g} is out of range ({why})")
    return q


def _print_locations(out, train, national, horizon, q: dict) -> None:
    from atcs.model.curves import curve_locations
    from atcs.model.dynamic_profile import CURVE_NAMES, supervised_targets
    from atcs.model.ops.exact import EXACT
    from atcs.model.profile import KMH_PER_MPS

    table = Table(title=f"where each curve reaches {float(q['speed'] * KMH_PER_MPS):g} km/h (m; '-' never)")
    table.add_column("target (m @ km/h)")
    for name in CURVE_NAMES:
        table.add_column(name, justify="right")
    for target in supervised_targets(EXACT, national, horizon, q["front_m"]):
        at = curve_locations(EXACT, train, national, q["gradient"], target, q["speed"], q["a_est"])
        cells = [getattr(at, f"{name}_m") for name in CURVE_NAMES]
        table.add_row(
            f"{float(target.location_m):g} @ {float(target.speed_mps * KMH_PER_MPS):g}",
            *("-" if c > Fraction(10**6) else f"{float(c):.2f}" for c in cells),
        )
    out.print(table)


def _print_service_curves(out, train, national, guidance, q: dict) -> None:
    """The end of authority's SBD and SBI1 at ``--speed``, and with a normal service brake in the train data its
    guidance curve and the permitted speed location the guidance curve adjusts (Subset-026 §3.13.9.3.5.4)."""
    from atcs.model.curves import gui_location_m, guided_permitted_location_m, sbd_location_m, sbi1_location_m
    from atcs.model.ops.exact import EXACT
    from atcs.model.profile import KMH_PER_MPS

    o, g, eoa, v = EXACT, q["gradient"], q["eoa_m"], q["speed"]
    table = Table(
        title=f"the end of authority's service-brake curves at {float(v * KMH_PER_MPS):g} km/h (m; '-' no data)"
    )
    cells = {"SBD": sbd_location_m(o, train, g, eoa, v), "SBI1": sbi1_location_m(o, train, g, eoa, v)}
    if guidance is not None:
        cells["GUI"] = gui_location_m(o, train, guidance, g, eoa, v)
        cells["permitted with GUI"] = guided_permitted_location_m(o, train, national, guidance, g, eoa, v)
    else:
        cells["GUI"] = cells["permitted with GUI"] = None
    for name in cells:
        table.add_column(name, justify="right")
    table.add_row(*("-" if c is None else f"{float(c):.2f}" for c in cells.values()))
    out.print(table)
