"""Plots: the planning area of a driver display, speed against distance with the MRSP, the braking
curves and the end of authority (seed 000 Fig. 15, seed 002 Fig. 9). Written atomically."""

from __future__ import annotations

import math
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure  # no pyplot: files only, no display or global state

from atcs.model.curves import FAR_M, curve_locations
from atcs.model.dynamic_profile import CURVE_NAMES, Horizon, ceilings, curve_ceiling, supervised_targets
from atcs.model.ops.floating import FLOAT
from atcs.model.profile import KMH_PER_MPS, value_at
from atcs.model.train_data import NationalData, TrainData

KMH = float(KMH_PER_MPS)

# curve -> (label, colour, line style), drawn from the farthest (EBD) to the nearest (indication)
CURVE_STYLE = {
    "ebd": ("EBD", "#7f0000", "--"),
    "ebi": ("EBI", "#d62728", "-"),
    "sbi": ("SBI", "#ff7f0e", "-"),
    "warning": ("warning", "#e6b800", "-"),
    "permitted": ("permitted", "#2ca02c", "-"),
    "indication": ("indication", "#1f77b4", ":"),
}


@dataclass(frozen=True)
class SampledCurves:
    """Each curve's speed (m/s) at ``positions_m``, for plotting: the ceilings included, and
    ``mrsp_mps`` the MRSP itself."""

    positions_m: np.ndarray
    mrsp_mps: np.ndarray
    speeds_mps: dict[str, np.ndarray]


def sampled_curves(
    t: TrainData,
    n: NationalData,
    horizon: Horizon,
    from_m: float,
    a_est_mps2: float,
    *,
    samples: int = 400,
    speed_steps: int = 200,
) -> SampledCurves:
    """Each curve over ``[from_m, eoa_m]`` on the float backend. Each target's curves are traced in
    speed (the inverse query at ``speed_steps`` speeds, exact points of the curve), interpolated onto
    ``samples`` positions, and the lowest of the targets and the ceiling taken at each; from its
    slowest traced point to the target a curve holds that speed (a train under it does not reach the
    target's EBD before the target)."""
    if samples < 2 or speed_steps < 2:
        raise ValueError(f"samples and speed_steps must be at least 2, got {samples!r} and {speed_steps!r}")
    o = FLOAT
    to_m = float(horizon.eoa_m)
    if not from_m < to_m:
        raise ValueError(f"from_m must lie before the end of authority {to_m:g} m, got {from_m!r}")
    positions = np.linspace(from_m, to_m, samples)
    mrsp = np.array([float(value_at(o, horizon.mrsp, x)) for x in positions])
    top_speed = float(max(horizon.mrsp.values)) * 1.5 + 10
    targets = supervised_targets(o, n, horizon, from_m)
    speeds = {name: np.full(samples, np.inf) for name in CURVE_NAMES}
    for target in targets:
        # finer near the target's speeds, where the curves end
        v_target, v_foot = float(target.speed_mps), float(target.ebd_foot_mps)
        grid = np.union1d(
            np.linspace(0.0, top_speed, speed_steps), np.linspace(v_target + 1e-6, v_foot + 5.0, speed_steps // 2)
        )
        per_speed = [curve_locations(o, t, n, horizon.gradient, target, float(v), a_est_mps2) for v in grid]
        for name in CURVE_NAMES:
            where = np.array([getattr(c, f"{name}_m") for c in per_speed])
            # a curve constrains speeds above the target's only: every curve ends at the target speed
            constrains = (where < FAR_M / 2) & (grid > v_target)
            if not constrains.any():
                continue
            # locations fall as the speed rises: interpolate the speed over increasing locations
            xs, vs = where[constrains][::-1], grid[constrains][::-1]
            # from the slowest speed it constrains up to the target, a curve holds that speed
            curve = np.interp(positions, xs, vs, left=np.inf, right=vs[-1])
            curve[positions > float(target.location_m)] = np.inf  # past the target: its speed is the MRSP's
            speeds[name] = np.minimum(speeds[name], curve)
    for name in CURVE_NAMES:
        cap = np.array([float(curve_ceiling(ceilings(o, n, v), name)) for v in mrsp])
        speeds[name] = np.minimum(speeds[name], cap)
    return SampledCurves(positions, mrsp, speeds)


def planning_area(sampled: SampledCurves, eoa_m: float, title: str, paths: list[Path]) -> list[Path]:
    """Draw the curves and write one file per path (the format from the suffix: .png, .svg)."""
    fig = Figure(figsize=(11, 5.5), layout="constrained")
    ax = fig.subplots()
    x = sampled.positions_m
    ax.step(x, sampled.mrsp_mps * KMH, where="post", color="black", linewidth=2, label="MRSP")
    for name, (label, colour, style) in CURVE_STYLE.items():
        ax.plot(x, sampled.speeds_mps[name] * KMH, color=colour, linestyle=style, label=label)
    ax.axvline(eoa_m, color="black", linestyle="-.", linewidth=1.5, label=f"end of authority ({eoa_m:g} m)")
    ax.set(xlabel="distance (m)", ylabel="speed (km/h)", title=title, xlim=(x[0], eoa_m + 0.03 * (eoa_m - x[0])))
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper right", fontsize="small")
    for path in paths:
        _save_atomic(fig, Path(path))
    return paths


def _save_atomic(fig, path: Path) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=path.suffix)
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)  # as an ordinary file, not mkstemp's private 0600
    try:
        fig.savefig(tmp, format=path.suffix.removeprefix("."), dpi=120)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def run_plots(sim, records: list[list[dict]], directory: Path, *, sample_every_s: float = 2.0) -> list[Path]:
    """A simulation's figures: per train, speed against distance with the MRSP and, sampled along the run, the
    EBI, SBI and permitted speeds at its max safe front (seed 000 Fig. 15, seed 002 Fig. 9-10); and a
    time-distance diagram of all trains with the protection zones. ``records`` holds each cycle's
    ``train.last`` of every train (as ``atcs sim`` collects them)."""
    from atcs.model.dynamic_profile import Horizon, curve_speeds_at

    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    paths = []
    every = max(1, round(sample_every_s / sim.dt))
    for k, train in enumerate(sim.trains):
        rows = [cycle[k] for cycle in records]
        fig = Figure(figsize=(11, 5.5), layout="constrained")
        ax = fig.subplots()
        ax.plot(
            [r["front_m"] for r in rows], [r["speed_kmh"] for r in rows], color="black", linewidth=1.5, label="speed"
        )
        mrsp = train.mrsp
        ax.step(
            [*mrsp.starts_m, mrsp.end_m],
            [v * KMH for v in (*mrsp.values, mrsp.values[-1])],
            where="post",
            color="grey",
            linewidth=1,
            label="MRSP",
        )
        samples = rows[::every]
        speeds = [
            curve_speeds_at(
                train.train_data,
                train.national,
                Horizon(train.mrsp, train.gradient, r["eoa_m"], 0.0),
                r["front_max_m"],
                float(train.plant.max_acceleration_mps2),
                tolerance_mps=1e-3,
            )
            for r in samples
        ]
        for name in ("ebi", "sbi", "permitted"):
            label, colour, style = CURVE_STYLE[name]
            ax.plot(
                [r["front_max_m"] for r in samples],
                [getattr(s, f"{name}_mps") * KMH for s in speeds],
                color=colour,
                linestyle=style,
                linewidth=1,
                label=f"{label} at the max safe front",
            )
        braking = [r["front_m"] for r in rows if r["eb"]]
        if braking:
            ax.plot(braking, [0] * len(braking), "|", color=CURVE_STYLE["ebi"][1], label="EB commanded")
        fronts = [r["front_m"] for r in rows]
        ax.set(
            xlabel="front (m)",
            ylabel="speed (km/h)",
            title=f"{sim.scenario.name}: {train.spec.name}",
            xlim=(min(fronts) - 50, max(fronts) + 100),
        )
        ax.set_ylim(bottom=0)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="lower left", fontsize="small")
        path = directory / f"{train.spec.name}_speed_distance.png"
        _save_atomic(fig, path)
        paths.append(path)
    fig = Figure(figsize=(11, 5.5), layout="constrained")
    ax = fig.subplots()
    layout = sim.scenario.double_track
    for k, train in enumerate(sim.trains):
        rows = [cycle[k] for cycle in records]
        times = [r["t_s"] for r in rows]
        if layout is not None:  # a train graph: x along the line, up trains rising and down trains falling
            ax.plot(
                times,
                [r["x_m"] if r["track"] != "turn-back" else math.nan for r in rows],
                label=train.spec.name,
                linewidth=1,
            )
            continue
        (line,) = ax.plot(times, [r["front_m"] for r in rows], label=f"{train.spec.name} front")
        ax.plot(
            times,
            [r["front_m"] - float(train.spec.data.train_length_m) for r in rows],
            color=line.get_color(),
            linestyle=":",
            label=f"{train.spec.name} rear",
        )
    for zone in sim.scenario.zones:
        until = sim.time_s if zone.until_s is None else float(zone.until_s)
        at = layout.place(zone.start_m)[1] if layout is not None else float(zone.start_m)
        ax.hlines(
            at, float(zone.from_s), until, color=CURVE_STYLE["ebi"][1], linewidth=2, label=f"protection zone ({at:g} m)"
        )
    if layout is not None:
        for station in sim.scenario.stations[: len(sim.scenario.stations) // 2]:
            ax.axhline(float(station.stop_m), color="grey", linewidth=0.5)
    ylabel = "position along the line (m; turn-backs not drawn)" if layout is not None else "position (m)"
    ax.set(xlabel="time (s)", ylabel=ylabel, title=f"{sim.scenario.name}: time-distance")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left", fontsize="small", ncols=2 if len(sim.trains) > 8 else 1)
    path = directory / "time_distance.png"
    _save_atomic(fig, path)
    paths.append(path)
    return paths
