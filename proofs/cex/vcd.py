"""A counterexample as a VCD waveform (IEEE 1364 value change dump, written with pyvcd), readable by GTKWave.

One variable per parameter, state, input and output field, in the scopes ``<node>.params``, ``.state``,
``.inputs`` and ``.outputs`` (an array field spread over ``field[j]``), plus ``holds`` and ``violation`` in
``<node>``. Numbers are VCD ``real`` variables: an exact rational is written as its nearest double, printed
with 16 significant digits (pyvcd's format), so the waveform shows, but does not carry, the exact value (the
JSON trace does). Booleans are 1-bit wires.

Time: one timestamp per ATP cycle. The cycle is the node's ``cycle_s`` parameter when it has one, else seed
001's 100 ms. The timescale is the largest VCD unit (1, 10 or 100 of s, ms, us, ns, ps, fs) that divides the
cycle exactly, so step k is at ``k * cycle / unit``: at seed 001's 100 ms, timescale ``100 ms`` and step k at
time k. Step k's state, inputs, outputs and verdict are at step k's time; the state after the last step at the
next one.
"""

from __future__ import annotations

import io
from fractions import Fraction

from vcd import VCDWriter

from atcs.model.node import flatten
from atcs.proofs.cex.trace import Replay, Trace

SEED_CYCLE_S = Fraction(1, 10)
"""The ATP cycle of seed 001 (100 ms), for nodes without a ``cycle_s`` parameter."""

_UNITS = [
    (Fraction(magnitude) * Fraction(10) ** exponent, f"{magnitude} {name}")
    for exponent, name in ((0, "s"), (-3, "ms"), (-6, "us"), (-9, "ns"), (-12, "ps"), (-15, "fs"))
    for magnitude in (100, 10, 1)
]


def cycle_s(trace: Trace) -> Fraction:
    """The duration of one step: the node's ``cycle_s`` parameter if it has a positive one, else 100 ms."""
    value = trace.params.get("cycle_s")
    if isinstance(value, Fraction) and value > 0:
        return value
    return SEED_CYCLE_S


def timescale(cycle: Fraction) -> tuple[str, int, bool]:
    """The VCD timescale, the number of its units per cycle, and whether that is exact: the largest unit that
    divides ``cycle``; a cycle no unit divides (not a whole number of femtoseconds) gets one ``100 ms`` unit per
    cycle, not exact (said in the header's comment)."""
    for unit, text in _UNITS:
        ticks = cycle / unit
        if ticks.denominator == 1:
            return text, int(ticks), True
    return "100 ms", 1, False


def _value(value):
    return bool(value) if isinstance(value, bool) else float(value)


def to_vcd(trace: Trace, replayed: Replay, *, date: str = "") -> str:
    """The VCD text of a trace and its exact replay (outputs and verdicts come from the replay)."""
    cycle = cycle_s(trace)
    scale, ticks, exact_scale = timescale(cycle)
    comment = (
        f"atcs counterexample: {trace.property}, node {trace.node}, violated at step {trace.violation_step}; "
        f"one step per ATP cycle of {float(cycle):g} s"
        + ("" if exact_scale else " (not a whole number of femtoseconds: one 100 ms unit per cycle)")
        + "; numbers are the doubles nearest the exact values of the JSON trace"
    )
    steps = len(trace.inputs)
    buffer = io.StringIO()
    with VCDWriter(buffer, timescale=scale, date=date or "unknown", comment=comment, version="atcs") as writer:
        top = trace.node

        def register(scope, name, value):
            if isinstance(value, bool):
                return writer.register_var(scope, name, "wire", size=1, init=value)
            return writer.register_var(scope, name, "real", init=_value(value))

        for name, value in flatten(trace.params).items():  # constant: the initial value is the whole story
            register((top, "params"), name, value)
        rows = [
            ("state", [flatten(s) for s in trace.states]),
            ("inputs", [flatten(i) for i in trace.inputs]),
            ("outputs", [flatten(o) for o in replayed.outputs]),
        ]
        variables = {role: {n: register((top, role), n, v) for n, v in values[0].items()} for role, values in rows}
        holds = writer.register_var(top, "holds", "wire", size=1, init=replayed.holds[0])
        violation = writer.register_var(top, "violation", "wire", size=1, init=trace.violation_step == 0)
        for k in range(1, steps + 1):
            time = k * ticks
            for role, values in rows:
                if k < len(values):
                    for name, value in values[k].items():
                        writer.change(variables[role][name], time, _value(value))
            if k < steps:
                writer.change(holds, time, replayed.holds[k])
                writer.change(violation, time, k == trace.violation_step)
    return buffer.getvalue()
