"""A counterexample as a PNG plot, for any node: speeds against time and distance, locations against
time, boolean commands as lanes, the violating step marked.

What is drawn is read off the node's field names (docs/design.md: names carry units), never configured per node:

- speeds: every real state, input and output field ending in ``_mps`` (drawn in km/h), against time (step x
  cycle, :func:`atcs.proofs.cex.vcd.cycle_s`) and, when the node has a position field, against distance;
- the position field: ``front_m`` of the state, else of the inputs, else the first real scalar state or input
  field whose name contains ``front`` and ends in ``_m`` (``measured_front_m``, ``front_max_m``);
- locations: every real state, input and output field ending in ``_m``, against time;
- lanes: every boolean state, input and output field, and the property's verdict ``holds``, one lane each.

Array fields are spread over ``field[j]``. Parameters are constant and are not drawn. A legend names a field
without its unit suffix (``inputs.measured_speed``): the axis says the unit the values are drawn in.

Readability: each trace of a panel has its own line style and marker, the first drawn thickest, so traces that
coincide stay visible. An axis is scaled around the train, not to every value: its range is that of the
reference (locations: the position field; speeds: the state's speeds, the true ones) widened to every value
within ``FAR`` axis units or ``FAR_SPANS`` times the reference's spread of it, plus a margin. A value beyond
that (an unconstrained input the solver set to a million) is drawn at the axis edge, marked with a triangle and
its value.
"""

from __future__ import annotations

import io
from dataclasses import dataclass
from pathlib import Path

from matplotlib.figure import Figure  # no pyplot: files only, no display or global state
from matplotlib.ticker import MaxNLocator

from atcs.model.node import Node, flatten
from atcs.model.profile import KMH_PER_MPS
from atcs.proofs.cex.trace import Replay, Trace
from atcs.proofs.cex.vcd import cycle_s

KMH = float(KMH_PER_MPS)
ROLES = ("state", "inputs", "outputs")
UNIT_SUFFIXES = ("_mps", "_m")

FAR = 100.0
"""Axis units (m or km/h) beyond the reference range within which every value is shown on the axis."""
FAR_SPANS = 10
"""Spreads of the reference range beyond it within which every value is shown on the axis."""

STYLES = (
    ("-", "o"),
    ("--", "s"),
    ("-.", "^"),
    (":", "D"),
    ((0, (6, 2, 1, 2, 1, 2)), "v"),
    ((0, (1, 1)), "P"),
    ((0, (8, 3)), "X"),
    ((0, (3, 1, 1, 1)), "<"),
    ((0, (5, 5)), ">"),
)
"""(line style, marker) of the traces of a panel, in drawing order; repeated past the last."""

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


def legend_label(field: Field) -> str:
    """``role.name`` without the unit suffix (``inputs.measured_speed``, ``state.cells[2]``): the axis gives the
    unit the values are drawn in."""
    role, name = field
    base, bracket, index = name.partition("[")
    for suffix in UNIT_SUFFIXES:
        if base.endswith(suffix):
            base = base.removesuffix(suffix)
            break
    return f"{role}.{base}{bracket}{index}"


def line_style(index: int, count: int) -> dict:
    """Matplotlib keywords of the ``index``-th of ``count`` traces of a panel: its own line style and marker,
    the line and marker thinner for later traces, so a later trace drawn on an earlier one leaves it visible."""
    linestyle, marker = STYLES[index % len(STYLES)]
    thinning = index / max(count - 1, 1)
    return {"linestyle": linestyle, "marker": marker, "linewidth": 3.0 - 1.8 * thinning, "markersize": 8 - 4 * thinning}


def axis_range(reference: list[float], values: list[float]) -> tuple[float, float]:
    """Limits of an axis around ``reference`` (module docstring): its range, widened to each value within ``FAR``
    or ``FAR_SPANS`` spreads of it, plus a 5% margin. Without a reference, the range of all the values."""
    reference = reference or values
    lo, hi = min(reference), max(reference)
    far = max(FAR_SPANS * (hi - lo), FAR)
    near = [v for v in values if lo - far <= v <= hi + far]
    lo, hi = min([lo, *near]), max([hi, *near])
    margin = 0.05 * (hi - lo) or max(0.05 * abs(lo), 1.0)
    return lo - margin, hi + margin


def _series(trace: Trace, replayed: Replay, field: Field) -> list:
    role, name = field
    records = {"state": trace.states, "inputs": trace.inputs, "outputs": replayed.outputs}[role]
    return [flatten(r)[name] for r in records]


@dataclass
class Panel:
    """One panel's traces in axis units: (field, values) and the values its axis is scaled around."""

    traces: list[tuple[Field, list[float]]]
    reference: list[float]

    def limits(self) -> tuple[float, float]:
        return axis_range(self.reference, [v for _, values in self.traces for v in values])


def _panel(trace: Trace, replayed: Replay, chosen: list[Field], reference: list[Field], scale: float) -> Panel:
    def values(field):
        return [float(v) * scale for v in _series(trace, replayed, field)]

    return Panel([(f, values(f)) for f in chosen], [v for f in reference for v in values(f)])


def _draw_clipped(ax, xs: list[float], ys: list[float], limits: tuple[float, float], style: dict, label: str):
    """Draw a trace with the values beyond ``limits`` at the axis edge, each first of a run marked with a
    triangle and its value."""
    lo, hi = limits
    line = ax.plot(xs, [min(max(y, lo), hi) for y in ys], label=label, **style)[0]
    previous = None
    for x, y in zip(xs, ys, strict=True):
        if (y < lo or y > hi) and y != previous:
            edge, marker, offset = (hi, "^", -10) if y > hi else (lo, "v", 4)
            ax.plot([x], [edge], marker=marker, color=line.get_color(), markersize=9, clip_on=False)
            ax.annotate(
                f"{y:.6g}",
                (x, edge),
                xytext=(6, offset),
                textcoords="offset points",
                fontsize="x-small",
                color=line.get_color(),
                bbox={"boxstyle": "round,pad=0.15", "facecolor": "white", "edgecolor": line.get_color(), "alpha": 0.9},
            )
        previous = y


def _legend(ax, title: str | None = None) -> None:
    ax.legend(
        loc="upper left",
        bbox_to_anchor=(1.01, 1.0),
        borderaxespad=0,
        fontsize="x-small",
        title=title,
        title_fontsize="x-small",
    )


@dataclass(frozen=True)
class Timing:
    cycle: float
    violation_step: int

    @property
    def violation_s(self) -> float:
        return self.violation_step * self.cycle

    def held(self, values: list) -> tuple[list[float], list]:
        """Step k's value from k * cycle to the next step's time: the last one held for a cycle."""
        return [k * self.cycle for k in range(len(values) + 1)], [*values, values[-1]]

    def shade(self, ax) -> None:
        start = self.violation_s
        ax.axvspan(start, start + self.cycle, color="red", alpha=0.15, label=f"violation (step {self.violation_step})")


def _time_panel(ax, panel: Panel, timing: Timing, unit: str, end_s: float) -> None:
    limits = panel.limits()
    for index, (field, values) in enumerate(panel.traces):
        t, held = timing.held(values)
        style = line_style(index, len(panel.traces))
        style["drawstyle"] = "steps-post"
        _draw_clipped(ax, t, held, limits, {**style, "markevery": slice(0, len(values))}, legend_label(field))
    timing.shade(ax)
    ax.set(xlabel="time (s)", ylabel=unit, xlim=(0, end_s), ylim=limits)
    ax.grid(True, alpha=0.3)
    _legend(ax, unit)


def _distance_panel(ax, speeds: Panel, position: list[float], position_field: Field, k_bad: int) -> None:
    limits = speeds.limits()
    steps = len(position)
    for index, (field, values) in enumerate(speeds.traces):
        style = line_style(index, len(speeds.traces))
        _draw_clipped(ax, position, values[:steps], limits, style, legend_label(field))
    name = legend_label(position_field)
    ax.axvline(
        position[k_bad],
        color="red",
        linestyle="--",
        linewidth=1.5,
        label=f"violation at {name} = {position[k_bad]:g} m",
    )
    ax.set(xlabel=f"distance: {name} (m)", ylabel="speed (km/h)", ylim=limits)
    ax.ticklabel_format(axis="x", useOffset=False)  # the train's own positions, not offsets from one
    ax.xaxis.set_major_locator(MaxNLocator(nbins=5))  # room for long tick labels of a short run
    ax.grid(True, alpha=0.3)
    _legend(ax, "speed (km/h)")


def _lanes_panel(ax, trace: Trace, replayed: Replay, lanes: list[Field], timing: Timing, end_s: float) -> None:
    """One lane per boolean, one above the other: filled where true, a dotted base line where false."""
    for row, field in enumerate(lanes):
        t, values = timing.held(replayed.holds if field == ("property", "holds") else _series(trace, replayed, field))
        y = len(lanes) - 1 - row
        color = "#1f77b4" if field[0] != "property" else "#2ca02c"
        ax.fill_between(t, y, [y + 0.8 * bool(v) for v in values], step="post", color=color, alpha=0.8, linewidth=0)
        ax.plot([0, end_s], [y, y], color="grey", linestyle=":", linewidth=0.8)
    timing.shade(ax)
    ticks = [len(lanes) - 1 - r + 0.4 for r in range(len(lanes))]
    ax.set_yticks(ticks, [".".join(f) for f in lanes], fontsize="x-small")
    ax.set(xlabel="time (s)", ylim=(-0.2, len(lanes)), xlim=(0, end_s))
    _legend(ax, "filled: true")


def _figure(panels: list[str], lanes: int) -> tuple[Figure, dict]:
    heights = {"speed": 3, "distance": 3, "locations": 3, "lanes": max(1.2, 0.32 * (lanes + 1))}
    height_in = sum(heights[p] for p in panels) + 0.6 * len(panels) + 0.8
    fig = Figure(figsize=(11, height_in))  # fixed margins: constrained layout would take half the drawing time
    fig.subplots_adjust(
        left=0.17,
        right=0.79,  # the legends stand right of the axes, off the traces
        top=1 - 0.75 / height_in,
        bottom=0.5 / height_in,
        hspace=0.6 * len(panels) / sum(heights[p] for p in panels),
    )
    grid = fig.subplots(len(panels), 1, squeeze=False, height_ratios=[heights[p] for p in panels])[:, 0]
    return fig, dict(zip(panels, grid, strict=True))


def plot_counterexample(node: Node, trace: Trace, replayed: Replay, path: str | Path) -> Path:
    """Draw the trace (outputs and verdicts from its exact replay) and write the PNG atomically."""
    from atcs.proofs.files import write_atomic

    buffer = io.BytesIO()
    counterexample_figure(node, trace, replayed).savefig(buffer, format="png", dpi=100)
    write_atomic(path, buffer.getvalue())
    return Path(path)


def counterexample_figure(node: Node, trace: Trace, replayed: Replay) -> Figure:
    """The figure of the trace (outputs and verdicts from its exact replay): speed, distance, location and lane
    panels, those the node has fields for."""
    fields = plot_fields(node)
    timing = Timing(float(cycle_s(trace)), trace.violation_step)
    wanted = {
        "speed": fields.speeds,
        "distance": fields.speeds and fields.position,
        "locations": fields.locations,
        "lanes": True,
    }
    fig, axes = _figure([p for p, w in wanted.items() if w], len(fields.lanes) + 1)
    fig.suptitle(
        f"{trace.property}: violated at step {timing.violation_step} (t = {timing.violation_s:g} s; "
        f"one step = {timing.cycle:g} s)"
    )
    end_s = (len(trace.inputs) + 1) * timing.cycle  # the state after the last step is held for one cycle
    true_speeds = [f for f in fields.speeds if f[0] == "state"]
    speeds = _panel(trace, replayed, fields.speeds, true_speeds, KMH)
    if "speed" in axes:
        _time_panel(axes["speed"], speeds, timing, "speed (km/h)", end_s)
    if "distance" in axes:
        position = [float(v) for v in _series(trace, replayed, fields.position)[: len(trace.inputs)]]
        _distance_panel(axes["distance"], speeds, position, fields.position, timing.violation_step)
    if "locations" in axes:
        reference = [fields.position] if fields.position else [f for f in fields.locations if f[0] == "state"]
        _time_panel(
            axes["locations"], _panel(trace, replayed, fields.locations, reference, 1.0), timing, "location (m)", end_s
        )
    _lanes_panel(axes["lanes"], trace, replayed, [*fields.lanes, ("property", "holds")], timing, end_s)
    return fig
