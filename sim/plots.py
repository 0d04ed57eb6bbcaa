"""Plots: the planning area of a driver display, speed against distance with the MRSP, the braking
curves and the end of authority (seed 000 Fig. 15, seed 002 Fig. 9). Written atomically."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from matplotlib.figure import Figure  # no pyplot: files only, no display or global state

from atcs.model.dynamic_profile import SampledCurves
from atcs.model.profile import KMH_PER_MPS

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
