"""Counterexample traces: extracted from a solver model, replayed exactly, written as JSON and CSV.

A trace is the parameters, the initial state and the inputs of each step, all as
exact rationals (or booleans). Replaying it runs the node's own step function on
the exact backend; the replay must reproduce every recorded state and violate
the property at the recorded step and not before, otherwise the engine, not the
model, is wrong (:class:`ReplayError`).
"""

from __future__ import annotations

import csv
import decimal
import io
import itertools
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any

import z3

from atcs.model.data_files import read_json
from atcs.model.errors import AtcsError, AtcsInputError
from atcs.model.node import Sort, as_dict, flatten
from atcs.model.numbers import exact_number
from atcs.model.ops.exact import EXACT
from atcs.proofs.engine.system import Unrolling, model_value
from atcs.properties.property import Property

FORMAT = "atcs-trace/1"

Value = Fraction | bool | tuple
"""An exact value: a number, a boolean, or a tuple of them (an array field)."""


class ReplayError(AtcsError):
    """The exact replay does not reproduce the trace: an internal error of the engine."""


class TraceFileError(AtcsInputError):
    """A trace file is malformed; the message names the file, the field and the value."""


@dataclass
class Trace:
    property: str
    node: str
    violation_step: int
    params: dict[str, Value]
    states: list[dict[str, Value]]
    """States 0 .. n (the state after the last step included)."""
    inputs: list[dict[str, Value]]
    """Inputs of steps 0 .. n-1; the violation is at step n-1."""


@dataclass
class Replay:
    """What the exact replay computed, step by step, and where it disagrees with the trace."""

    trace: Trace
    states: list[dict[str, Value]] = field(default_factory=list)
    outputs: list[dict[str, Value]] = field(default_factory=list)
    holds: list[bool] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)
    """Why the trace is not a run of this model: initial state, assumptions, recorded states."""

    @property
    def first_violation(self) -> int | None:
        return next((k for k, ok in enumerate(self.holds) if not ok), None)

    @property
    def reproduced(self) -> bool:
        return not self.problems and self.first_violation == self.trace.violation_step


def extract(u: Unrolling, model: z3.ModelRef, k: int) -> Trace:
    """The trace of a BMC model with the violation at step ``k``."""
    node = u.node
    return Trace(
        property=u.prop.name,
        node=node.name,
        violation_step=k,
        params={n: model_value(model, v) for n, v in as_dict(u.params).items()},
        states=[{n: model_value(model, v) for n, v in as_dict(u.state(j)).items()} for j in range(k + 2)],
        inputs=[{n: model_value(model, v) for n, v in as_dict(u.frame(j).inputs).items()} for j in range(k + 1)],
    )


def replay(prop: Property, trace: Trace, *, ops=EXACT) -> Replay:
    """Run the trace's inputs through the property's node and predicate from its initial state.

    Every difference from the trace (initial state, assumptions, recorded states)
    is collected in ``problems``; the run goes on with the model's own states.
    """
    node = prop.node
    if trace.node != node.name:
        raise ReplayError(f"trace is of node {trace.node!r}, property {prop.name} is about {node.name!r}")
    p = node.params(**trace.params)
    s = node.state(**trace.states[0])
    result = Replay(trace, states=[dict(trace.states[0])])
    if not node.init(ops, p, s):
        result.problems.append(f"the initial state {_show(trace.states[0])} is not an initial state of the model")
    for k, inputs in enumerate(trace.inputs):
        i = node.inputs(**inputs)
        failed = [a.name for a in prop.assumptions if not a.holds(ops, p, s, i)]
        if failed:
            result.problems.append(f"step {k} violates the assumption(s) {', '.join(failed)}")
        nxt, out = node.step(ops, p, s, i)
        result.states.append(as_dict(nxt))
        result.outputs.append(as_dict(out))
        result.holds.append(bool(prop.holds(ops, p, s, i, out, nxt)))
        if as_dict(nxt) != trace.states[k + 1]:
            result.problems.append(
                f"after step {k} the model's state is {_show(as_dict(nxt))}, the trace's {_show(trace.states[k + 1])}"
            )
        s = nxt
    return result


def reproduce(prop: Property, trace: Trace) -> Replay:
    """Replay exactly; raise :class:`ReplayError` unless the violation is reproduced at the recorded step."""
    result = replay(prop, trace)
    if result.problems:
        raise ReplayError(f"{prop.name}: " + "; ".join(result.problems))
    if result.first_violation != trace.violation_step:
        raise ReplayError(
            f"{prop.name}: the solver's trace violates the property at step {trace.violation_step}, "
            f"the exact replay first at {result.first_violation}"
        )
    return result


def _show(values: dict[str, Value]) -> str:
    return "{" + ", ".join(f"{n}={format_value(v)}" for n, v in values.items()) + "}"


# --- files -------------------------------------------------------------------------------


def format_value(value):
    """Exact text for a value: a decimal when it has a finite one, else ``p/q`` (a list for a tuple)."""
    if isinstance(value, tuple):
        return [format_value(v) for v in value]
    if isinstance(value, bool):
        return value
    value = Fraction(value)
    d = value.denominator
    twos = fives = 0
    while d % 2 == 0:
        d //= 2
        twos += 1
    while d % 5 == 0:
        d //= 5
        fives += 1
    if d != 1:
        return f"{value.numerator}/{value.denominator}"
    places = max(twos, fives)
    text = f"{abs(value.numerator) * 10**places // value.denominator:0{places + 1}d}"
    if places:
        text = f"{text[:-places]}.{text[-places:]}".rstrip("0").rstrip(".")
    return ("-" if value < 0 else "") + text


SHOWN_DIGITS = 6
"""Significant digits of the decimal shown beside an exact value (:func:`readable_value`)."""


def rounded_decimal(value: Fraction, digits: int = SHOWN_DIGITS) -> str:
    """``value`` rounded to ``digits`` significant digits (half to even), trailing zeros dropped: ``0.333333``,
    ``1.23457e+6``."""
    with decimal.localcontext(prec=digits, rounding=decimal.ROUND_HALF_EVEN):
        rounded = decimal.Decimal(value.numerator) / decimal.Decimal(value.denominator)
    return f"{rounded.normalize():g}"


def readable_value(value) -> str:
    """A value for people: a number as its exact decimal when it has at most 6 significant digits (``0.1``,
    ``-1.25``, ``1000000``), else rounded to 6 with the exact value (as in the trace file) in parentheses
    (``0.333333 (1/3)``); ``True``/``False``; an array as ``[a, b]``."""
    if isinstance(value, tuple):
        return "[" + ", ".join(readable_value(v) for v in value) + "]"
    if isinstance(value, bool):
        return str(value)
    value = Fraction(value)
    exact = format_value(value)
    rounded = rounded_decimal(value)
    return exact if Fraction(rounded) == value else f"{rounded} ({exact})"


def nearest_double(value):
    """A value as a spreadsheet reads it: a number as the shortest decimal of its nearest double (an integer
    without ``.0``), a boolean as itself."""
    if isinstance(value, bool):
        return value
    value = Fraction(value)
    if value.denominator == 1 and abs(value) < 2**53:
        return str(value.numerator)
    return repr(float(value))


def input_changes(trace: Trace) -> int:
    """The number of (step, input variable) pairs whose value differs from the previous step's (an array input
    counts per element): what smoothing (:mod:`atcs.proofs.cex.smoothing`) minimises."""
    flat = [flatten(inputs) for inputs in trace.inputs]
    return sum(now[name] != before[name] for before, now in itertools.pairwise(flat) for name in now)


def to_json(trace: Trace, replayed: Replay | None = None, *, requirement: str = "") -> dict[str, Any]:
    steps = []
    for k, inputs in enumerate(trace.inputs):
        step: dict[str, Any] = {
            "step": k,
            "state": {n: format_value(v) for n, v in trace.states[k].items()},
            "inputs": {n: format_value(v) for n, v in inputs.items()},
        }
        if replayed is not None:
            step["outputs"] = {n: format_value(v) for n, v in replayed.outputs[k].items()}
            step["holds"] = replayed.holds[k]
        steps.append(step)
    return {
        "format": FORMAT,
        "property": trace.property,
        "requirement": requirement,
        "node": trace.node,
        "violation_step": trace.violation_step,
        "input_changes": input_changes(trace),
        "params": {n: format_value(v) for n, v in trace.params.items()},
        "steps": steps,
        "final_state": {n: format_value(v) for n, v in trace.states[-1].items()},
    }


def to_csv(trace: Trace, replayed: Replay) -> str:
    """One row per step, one column per parameter, state, input and output variable (arrays spread out); numbers
    as the decimal of their nearest double (:func:`nearest_double`), the exact values being in the JSON trace."""
    out = io.StringIO()

    def groups(k):
        return (
            ("param", trace.params),
            ("state", trace.states[k]),
            ("input", trace.inputs[k]),
            ("output", replayed.outputs[k]),
        )

    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(
        ["step"] + [f"{prefix}.{n}" for prefix, record in groups(0) for n in flatten(record)] + ["holds", "violation"]
    )
    for k in range(len(trace.inputs)):
        row = [k] + [nearest_double(v) for _, record in groups(k) for v in flatten(record).values()]
        writer.writerow([*row, replayed.holds[k], k == trace.violation_step])
    return out.getvalue()


def parse_value(path: str, where: str, raw: Any, sort: Sort, error: type[ValueError] = TraceFileError):
    """An exact value of sort ``sort`` read from JSON (``true``/``false``, a number as a string, a list for an
    array); a bad one raises ``error`` naming the file, the field and the value."""
    if sort.size is not None:
        if not isinstance(raw, list) or len(raw) != sort.size:
            raise error(f"{path}: {where} must be a list of {sort.size} values, got {raw!r}")
        return tuple(parse_value(path, f"{where}[{j}]", v, Sort(sort.kind), error) for j, v in enumerate(raw))
    if sort.kind == "bool":
        if not isinstance(raw, bool):
            raise error(f"{path}: {where} must be true or false, got {raw!r}")
        return raw
    if isinstance(raw, bool) or not isinstance(raw, (str, int)):
        raise error(f'{path}: {where} must be an exact number as a string such as "1/3", got {raw!r}')
    try:
        return exact_number(raw)
    except ValueError as exc:
        raise error(f"{path}: {where} = {raw!r} {exc}") from None


def parse_record(
    path: str, where: str, raw: Any, sorts: dict[str, Sort], error: type[ValueError] = TraceFileError
) -> dict[str, Value]:
    """A record of fields of the given sorts read from a JSON object: every field present, none unknown."""
    if not isinstance(raw, dict):
        raise error(f"{path}: {where} must be an object, got {raw!r}")
    missing = [n for n in sorts if n not in raw]
    unknown = [n for n in raw if n not in sorts]
    if missing or unknown:
        raise error(
            f"{path}: {where} has "
            + "; ".join(
                x for x in (missing and f"missing fields {missing}", unknown and f"unknown fields {unknown}") if x
            )
        )
    return {n: parse_value(path, f"{where}.{n}", raw[n], sort, error) for n, sort in sorts.items()}


def from_json(path: str | Path, properties: dict[str, Property]) -> tuple[Property, Trace]:
    """Read a trace file, resolving its property in ``properties``; errors name file, field and value."""
    path = str(path)
    doc = _read_json(path)
    if not isinstance(doc, dict):
        raise TraceFileError(f"{path}: the top level must be an object, got {type(doc).__name__}")
    if doc.get("format") != FORMAT:
        raise TraceFileError(f"{path}: field 'format' must be {FORMAT!r}, got {doc.get('format')!r}")
    name = doc.get("property")
    if name not in properties:
        raise TraceFileError(f"{path}: field 'property' names no registered property: {name!r}")
    prop = properties[name]
    node = prop.node
    steps = doc.get("steps")
    if not isinstance(steps, list) or not steps:
        raise TraceFileError(f"{path}: field 'steps' must be a non-empty list, got {steps!r}")
    k = doc.get("violation_step")
    if isinstance(k, bool) or not isinstance(k, int) or not 0 <= k < len(steps):
        raise TraceFileError(f"{path}: field 'violation_step' must be a step index below {len(steps)}, got {k!r}")
    if doc.get("node") != node.name:
        raise TraceFileError(f"{path}: field 'node' must be {node.name!r} for {name}, got {doc.get('node')!r}")
    params = parse_record(path, "params", doc.get("params"), node.sorts("params"))
    states, inputs = [], []
    for j, step in enumerate(steps):
        if not isinstance(step, dict):
            raise TraceFileError(f"{path}: steps[{j}] must be an object, got {step!r}")
        states.append(parse_record(path, f"steps[{j}].state", step.get("state"), node.sorts("state")))
        inputs.append(parse_record(path, f"steps[{j}].inputs", step.get("inputs"), node.sorts("inputs")))
    states.append(parse_record(path, "final_state", doc.get("final_state"), node.sorts("state")))
    trace = Trace(name, node.name, k, params, states, inputs)
    return prop, trace


def _read_json(path: str) -> Any:
    """The JSON document of a trace file, or a TraceFileError if it cannot be read or is not JSON."""
    return read_json(path, TraceFileError, "the trace")
