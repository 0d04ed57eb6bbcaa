"""An envelope's map: JSON (every cell of every property, its bounds as exact fractions and as numbers, its
verdict and proofs) and PNG plots of 2-D slices (per train, each pair of its range fields; a cell's colour is the
worst verdict of any of the train's properties there)."""

from __future__ import annotations

import io
import itertools
import json
from fractions import Fraction
from pathlib import Path

from atcs.proofs.envelope.sweep import WORST_FIRST, PropertyMap

__all__ = ["COLOURS", "map_json", "plot_slices", "write_map"]

COLOURS = {
    "proved": "#2ca02c",
    "unknown": "#ffbf00",
    "vacuous": "#bcbd22",
    "falsified": "#d62728",
    "error": "#9467bd",
}
"""A verdict's colour in the plots."""


def _interval(low: Fraction, high: Fraction) -> dict:
    return {"min": str(low), "max": str(high), "min_float": float(low), "max_float": float(high)}


def write_map(maps: dict[str, PropertyMap], counterexamples: dict[tuple[str, str], str], directory) -> list[Path]:
    """Write ``<dir>/map.json`` (:func:`map_json`) and the plots (:func:`plot_slices`); returns the files."""
    from atcs.proofs.files import write_atomic

    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    path = directory / "map.json"
    write_atomic(path, json.dumps({"envelopes": map_json(maps, counterexamples)}, indent=2) + "\n")
    return [path, *plot_slices(maps, directory)]


def map_json(maps: dict[str, PropertyMap], counterexamples: dict[tuple[str, str], str]) -> list[dict]:
    """The ``envelopes`` of the JSON report: one entry per property; ``counterexamples`` gives the file written
    for a falsified cell by (property, cell id)."""
    entries = []
    for name, m in maps.items():
        entries.append(
            {
                "name": name,
                "requirement": m.requirement,
                "train": m.train,
                "line": m.line,
                "status": m.status,
                "ranges": {r.field: {**_interval(r.min, r.max), "resolution": str(r.resolution)} for r in m.ranges},
                "cells": [
                    {
                        "id": c.cell.id,
                        "bounds": {f: _interval(lo, hi) for f, lo, hi in c.cell.bounds},
                        "status": c.status,
                        "seconds": round(c.seconds, 3),
                        "proofs": [_proof(r) for r in c.results],
                        "reused": c.reused,
                        "counterexample": counterexamples.get((name, c.cell.id)),
                    }
                    for c in m.cells
                ],
            }
        )
    return entries


def _proof(r) -> dict:
    return {"name": r.name, "status": str(r.status), "seconds": round(r.seconds, 3), "message": r.message}


def plot_slices(maps: dict[str, PropertyMap], directory: str | Path) -> list[Path]:
    """Write ``<dir>/<train>.<x>.<y>.png`` for each train and pair of its range fields (a train of one range: its
    field against nothing, ``<train>.<x>.png``), the other fields' cells cut at their range's middle; returns the
    files written."""
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch, Rectangle

    from atcs.proofs.files import write_atomic

    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    written = []
    by_train: dict[str, list[PropertyMap]] = {}
    for m in maps.values():
        by_train.setdefault(m.train, []).append(m)
    for train, train_maps in by_train.items():
        ranges = train_maps[0].ranges
        fields = [r.field for r in ranges]
        middle = {r.field: (r.min + r.max) / 2 for r in ranges}
        pairs = list(itertools.combinations(fields, 2)) or [(fields[0], None)]
        for x, y in pairs:
            fig = Figure(figsize=(6.4, 4.8))
            ax = fig.add_subplot()
            cuts = [(m, c) for m in train_maps for c in m.cells if _contains(c.cell.bounds, middle, {x, y})]
            for _, c in sorted(cuts, key=lambda mc: -WORST_FIRST.index(mc[1].status)):  # the worst drawn last, on top
                box = {f: (lo, hi) for f, lo, hi in c.cell.bounds}
                (x0, x1), (y0, y1) = box[x], box[y] if y else (0, 1)
                ax.add_patch(
                    Rectangle(
                        (float(x0), float(y0)),
                        float(x1 - x0),
                        float(y1 - y0),
                        facecolor=COLOURS[c.status],
                        edgecolor="black",
                        linewidth=0.5,
                    )
                )
            rx = next(r for r in ranges if r.field == x)
            ax.set_xlim(float(rx.min), float(rx.max))
            ax.set_xlabel(x)
            if y:
                ry = next(r for r in ranges if r.field == y)
                ax.set_ylim(float(ry.min), float(ry.max))
                ax.set_ylabel(y)
            else:
                ax.set_ylim(0, 1)
                ax.set_yticks([])
            others = [f for f in fields if f not in (x, y)]
            cut = "; ".join(f"{f} = {float(middle[f]):g}" for f in others)
            ax.set_title(f"{train}: {len(train_maps)} properties" + (f" ({cut})" if cut else ""), fontsize=9)
            seen = sorted({c.status for _, c in cuts}, key=WORST_FIRST.index)
            ax.legend(handles=[Patch(facecolor=COLOURS[s], label=s) for s in seen], loc="upper right", fontsize=8)
            path = directory / (f"{train}.{x}.{y}.png" if y else f"{train}.{x}.png")
            buffer = io.BytesIO()
            fig.savefig(buffer, format="png", dpi=100)
            write_atomic(path, buffer.getvalue())
            written.append(path)
    return written


def _contains(bounds, point: dict, free: set) -> bool:
    """Whether the cell ``bounds`` contains ``point`` in every field but the ``free`` ones."""
    return all(lo <= point[f] <= hi for f, lo, hi in bounds if f not in free)
