"""A counterexample as a PNG plot, for any node: speeds against time and distance, locations against
time, boolean commands as lanes, the violating step marked.

What is drawn is read off the node's field names (docs/design.md: names carry units), never configured per node:

- speeds: every real state, input and output field ending in ``_mps`` (drawn in km/h), against time (step x
  cycle, :func:`atcs.proofs.cex.vcd.cycle_s`) and, when the node has a position field, against distance;
- the position field: ``front_m`` of the state, else of the inputs, else the first real scalar state or input
  field whose name contains ``front`` and ends in ``_m`` (``measured_front_m``, ``front_max_m``);
- locations: every real state, input and output field ending in ``_m``, against time;
- lanes: every boolean state, input and output field, and the property's verdict ``holds``.

Array fields are spread over ``field[j]``. Parameters are constant and are not drawn.
"""

from __future__ import annotations

import io
from dataclasses import dataclass
from pathlib import Path

from matplotlib.figure import Figure  # no pyplot: files only, no display or global state

from atcs.model.node import Node, flatten
from atcs.model.profile import KMH_PER_MPS
from atcs.proofs.cex.trace import Replay, Trace
from atcs.proofs.cex.vcd import cycle_s

KMH = float(KMH_PER_MPS)
ROLES = ("state", "inputs", "outputs")

Field = tuple[str, str]
"""(role, flat name), e.g. ``("inputs", "speed_mps")`` or ``("state", "held[2]")``."""


@dataclass(frozen=True)
class PlotFields:
    speeds: list[Field]
    locations: list[Field]
    position: Field | None
    lanes: list[Field]


def _flat_names(node: Node, role: str, kind: str) -> list[str]:
    names = []
    for name, sort in node.sorts(role).items():
        if sort.kind == kind:
            names += [name] if sort.size is None else [f"{name}[{j}]" for j in range(sort.size)]
    return names


def plot_fields(node: Node) -> PlotFields:
    """The fields a counterexample plot of ``node`` draws (module docstring)."""
    reals = {role: _flat_names(node, role, "real") for role in ROLES}
    scalars = {role: [n for n in reals[role] if n in node.sorts(role)] for role in ROLES}
    position = next(((role, "front_m") for role in ("state", "inputs") if "front_m" in scalars[role]), None)
    if position is None:
        position = next(
            ((role, n) for role in ("state", "inputs") for n in scalars[role] if "front" in n and n.endswith("_m")),
            None,
        )
    return PlotFields(
        speeds=[(role, n) for role in ROLES for n in reals[role] if n.split("[")[0].endswith("_mps")],
        locations=[(role, n) for role in ROLES for n in reals[role] if n.split("[")[0].endswith("_m")],
        position=position,
        lanes=[(role, n) for role in ROLES for n in _flat_names(node, role, "bool")],
    )


def _series(trace: Trace, replayed: Replay, field: Field) -> list:
    role, name = field
    records = {"state": trace.states, "inputs": trace.inputs, "outputs": replayed.outputs}[role]
    return [flatten(r)[name] for r in records]


def plot_counterexample(node: Node, trace: Trace, replayed: Replay, path: str | Path) -> Path:
    """Draw the trace (outputs and verdicts from its exact replay) and write the PNG atomically."""
    from atcs.proofs.files import write_atomic

    fields = plot_fields(node)
    cycle = float(cycle_s(trace))
    k_bad = trace.violation_step
    t_bad = k_bad * cycle
    panels = [
        p
        for p, wanted in (
            ("speed", fields.speeds),
            ("distance", fields.speeds and fields.position),
            ("locations", fields.locations),
            ("lanes", True),
        )
        if wanted
    ]
    heights = {"speed": 3, "distance": 3, "locations": 3, "lanes": max(1.2, 0.32 * (len(fields.lanes) + 1))}
    height_in = sum(heights[p] for p in panels) + 0.6 * len(panels) + 0.8
    fig = Figure(figsize=(11, height_in))  # fixed margins: constrained layout would take half the drawing time
    fig.subplots_adjust(
        left=0.17,
        right=0.98,
        top=1 - 0.75 / height_in,
        bottom=0.5 / height_in,
        hspace=0.6 * len(panels) / sum(heights[p] for p in panels),
    )
    axes = dict(
        zip(
            panels,
            fig.subplots(len(panels), 1, squeeze=False, height_ratios=[heights[p] for p in panels])[:, 0],
            strict=True,
        )
    )
    fig.suptitle(f"{trace.property}: violated at step {k_bad} (t = {t_bad:g} s; one step = {cycle:g} s)")

    end_s = (len(trace.inputs) + 1) * cycle  # the state after the last step is held for one cycle

    def held(values):
        """Step k's value from k * cycle to the next step's time: the last one held for a cycle."""
        return [k * cycle for k in range(len(values) + 1)], [*values, values[-1]]

    for panel, chosen, scale, unit in (
        ("speed", fields.speeds, KMH, "speed (km/h)"),
        ("locations", fields.locations, 1.0, "location (m)"),
    ):
        if panel not in axes:
            continue
        ax = axes[panel]
        for field in chosen:
            t, values = held(_series(trace, replayed, field))
            ax.step(t, [float(v) * scale for v in values], where="post", label=".".join(field))
        ax.axvspan(t_bad, t_bad + cycle, color="red", alpha=0.15, label=f"violation (step {k_bad})")
        ax.set(xlabel="time (s)", ylabel=unit, xlim=(0, end_s))
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper left", fontsize="x-small", ncols=2)
    if "distance" in axes:
        ax = axes["distance"]
        steps = len(trace.inputs)
        position = [float(v) for v in _series(trace, replayed, fields.position)[:steps]]
        for field in fields.speeds:
            values = _series(trace, replayed, field)[:steps]
            ax.plot(position, [float(v) * KMH for v in values], marker=".", label=".".join(field))
        ax.axvline(
            position[k_bad],
            color="red",
            linestyle="--",
            linewidth=1.5,
            label=f"violation at {'.'.join(fields.position)} = {position[k_bad]:g} m",
        )
        ax.set(xlabel=f"distance: {'.'.join(fields.position)} (m)", ylabel="speed (km/h)")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper left", fontsize="x-small", ncols=2)
    ax = axes["lanes"]
    lanes = [*fields.lanes, ("property", "holds")]
    for row, field in enumerate(lanes):
        t, values = held(replayed.holds if field == ("property", "holds") else _series(trace, replayed, field))
        y = len(lanes) - 1 - row
        ax.fill_between(
            t,
            y,
            [y + 0.8 * bool(v) for v in values],
            step="post",
            color="#1f77b4" if field[0] != "property" else "#2ca02c",
            alpha=0.8,
        )
    ax.axvspan(t_bad, t_bad + cycle, color="red", alpha=0.15, label=f"violation (step {k_bad})")
    ax.set_yticks(
        [len(lanes) - 1 - r + 0.4 for r in range(len(lanes))], [".".join(f) for f in lanes], fontsize="x-small"
    )
    ax.set(xlabel="time (s)", ylim=(-0.2, len(lanes)), xlim=(0, end_s))
    ax.legend(loc="upper right", fontsize="x-small")
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=100)
    write_atomic(path, buffer.getvalue())
    return Path(path)
