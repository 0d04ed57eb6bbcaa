"""Near-nominal counterexamples (``--nominal``): of the runs that first violate the property at the step BMC
found, one whose inputs stay as near their nominal values as the violation allows.

No node declares nominal values, so nominal is read off the field names (docs/design.md: names carry units and
roles). A measured input is nominal when it equals its true counterpart, a real field of the same shape in the
node's state or inputs: ``measured_X`` and ``X_meas...`` (``X_measured_m``) measure ``X`` (``X_m``), and an input
``X`` is the measured one of a field ``true_X``. Every other real input is nominal at 0. Over the steps 0..k of
the run (an array input per element) the search minimises, in this order of priority:

1. the measurement error, the sum of ``|measured - true|`` over the measured inputs;
2. the input magnitude, the sum of ``|input|`` over the other real inputs.

The measurement error comes first so that a sensor error stays only where the violation needs one, whatever the
other inputs' sizes. Booleans are free. Both work on the BMC constraints (the same initial state, transitions,
assumptions, lemmas and "no violation before step k") within the time left of the property's timeout. On linear
constraints z3's optimizer (``z3.Optimize``, lexicographic) is asked first; where it attains both minima, the run
is optimal. Otherwise (nonlinear constraints, an infimum not attained, no answer in time) each sum is bisected on
the BMC solver between a proved lower bound and the best run's value. An unknown answer or the end of the time
keeps the best run found (the BMC run if none is better), and the result says why. The engine replays the chosen
run exactly, like any other counterexample.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction

import z3

from atcs.model.node import Node, as_dict
from atcs.model.ops.symbolic import unwrap
from atcs.proofs.cex.trace import Trace, extract, format_value, readable_value
from atcs.proofs.engine.bmc import Check, solve
from atcs.proofs.engine.system import Unrolling

__all__ = ["Nominal", "Pair", "deviations", "measurement_pairs", "nominal_distance", "nominalise"]

Pair = tuple[str, str, str]
"""(measured input, role of its true counterpart, true counterpart), e.g.
``("measured_speed_mps", "state", "speed_mps")``."""


def _true_name(measured: str) -> str | None:
    """The field a measured input's name says it measures, or None: ``measured_X`` and ``X_meas..._unit`` measure
    ``X`` (``X_unit``)."""
    if measured.startswith("measured_"):
        return measured.removeprefix("measured_")
    head, sep, tail = measured.partition("_meas")
    if not sep or not head:
        return None
    unit = tail.partition("_")[2]
    return f"{head}_{unit}" if unit else head


def measurement_pairs(node: Node) -> list[Pair]:
    """The node's measured real inputs, each with its true counterpart (module docstring), in input order."""
    reals = {role: {n: s for n, s in node.sorts(role).items() if s.kind == "real"} for role in ("state", "inputs")}

    def counterpart(name: str) -> tuple[str, str] | None:
        names = [true for true in (_true_name(name), f"true_{name}") if true is not None]
        candidates = [(role, true) for true in names for role in ("state", "inputs")]
        return next(((role, true) for role, true in candidates if reals[role].get(true) == reals["inputs"][name]), None)

    return [(name, *found) for name in reals["inputs"] if (found := counterpart(name)) is not None]


def deviations(node: Node, states: Sequence[dict], inputs: Sequence[dict]) -> tuple[list[tuple], list]:
    """Over the given steps: the (measured, true) value pairs of every measured input, and the values of every
    other real input (array fields per element); ``states[j]`` and ``inputs[j]`` are step j's records."""
    pairs = measurement_pairs(node)
    measured = {name for name, _, _ in pairs}
    others = [n for n, s in node.sorts("inputs").items() if s.kind == "real" and n not in measured]
    errors, magnitudes = [], []
    for state, step_inputs in zip(states, inputs, strict=False):  # a trace has one state more than inputs
        records = {"state": state, "inputs": step_inputs}
        for name, role, true in pairs:
            errors += zip(_elements(step_inputs[name]), _elements(records[role][true]), strict=True)
        for name in others:
            magnitudes += _elements(step_inputs[name])
    return errors, magnitudes


def _elements(value) -> list:
    return list(value) if isinstance(value, tuple) else [value]


def nominal_distance(node: Node, trace: Trace) -> tuple[Fraction, Fraction]:
    """The measurement error and the input magnitude of a trace (module docstring), exactly."""
    errors, magnitudes = deviations(node, trace.states, trace.inputs)
    return sum((abs(m - t) for m, t in errors), Fraction(0)), sum((abs(v) for v in magnitudes), Fraction(0))


@dataclass(frozen=True)
class Nominal:
    """What the search for a near-nominal run did to one counterexample."""

    status: str
    """``optimal`` (no run of the same length is nearer nominal), ``near optimal`` (each distance above its
    minimum by at most ``TOLERANCE`` of the BMC run's, the minimum not attained or not pinned down) or ``not
    optimal`` (the solver said unknown or the time ran out: the best run found is kept, the BMC run if none is
    better)."""
    original: tuple[Fraction, Fraction]
    """Measurement error and input magnitude of the BMC counterexample."""
    distance: tuple[Fraction, Fraction]
    """Measurement error and input magnitude of the counterexample kept."""
    lower: tuple[Fraction, Fraction] = (Fraction(0), Fraction(0))
    """Proved lower bounds: no run has a smaller measurement error, and none with at most the kept run's
    measurement error has a smaller input magnitude (equal to ``distance`` when ``optimal``)."""
    message: str = ""

    def describe(self) -> str:
        (error_before, size_before), (error, size) = self.original, self.distance
        text = (
            f"nominal: measurement error {readable_value(error_before)} -> {readable_value(error)}, "
            f"input magnitude {readable_value(size_before)} -> {readable_value(size)} ({self.status})"
        )
        return f"{text}: {self.message}" if self.message else text

    def as_json(self) -> dict:
        return {
            "status": self.status,
            "original_measurement_error": format_value(self.original[0]),
            "measurement_error": format_value(self.distance[0]),
            "original_input_magnitude": format_value(self.original[1]),
            "input_magnitude": format_value(self.distance[1]),
            "measurement_error_lower_bound": format_value(self.lower[0]),
            "input_magnitude_lower_bound": format_value(self.lower[1]),
            "message": self.message,
        }


TOLERANCE = Fraction(1, 1000)
"""The bisection stops once a distance is within this fraction of its starting value (the BMC run's) above its
proved lower bound: at most 12 solver calls per distance, each halving the gap."""


def _objectives(u: Unrolling, k: int) -> list[z3.ArithRef]:
    """The measurement error and the input magnitude of steps 0..k as z3 terms."""
    states = [as_dict(u.state(j)) for j in range(k + 1)]
    inputs = [as_dict(u.frame(j).inputs) for j in range(k + 1)]
    errors, magnitudes = deviations(u.node, states, inputs)

    def absolute(term):
        term = unwrap(term)
        return z3.If(term >= 0, term, -term)

    def total(terms):
        return z3.Sum(terms) if terms else z3.RealVal(0, u.init().ctx)

    return [total([absolute(m - t) for m, t in errors]), total([absolute(v) for v in magnitudes])]


def _value(model: z3.ModelRef, term: z3.ArithRef) -> Fraction:
    return model.eval(term, model_completion=True).as_fraction()


@dataclass
class _Search:
    """The best run so far and, per distance, the proved lower bound and the value reached."""

    model: z3.ModelRef
    rational: Callable[[z3.ModelRef], bool]
    """Whether a run has rational values only (an exact trace can be extracted from it)."""
    bounds: list[tuple[Fraction, Fraction]] = field(default_factory=list)
    stopped: str = ""
    """Why the search stopped before pinning every distance down; empty if it did not."""

    @property
    def status(self) -> str:
        if self.stopped:
            return "not optimal"
        if all(lower == value for lower, value in self.bounds):
            return "optimal"
        return "near optimal"

    def bisect(self, solver: z3.Solver, goal: z3.BoolRef, objective: z3.ArithRef, end: float) -> None:
        """Lower ``objective`` on ``solver`` + ``goal`` by bisection between a proved lower bound (the objective is
        above it) and the best run's value: first exactly 0, then halving the gap until it is within
        ``TOLERANCE`` of the starting value."""
        lower, value = Fraction(0), _value(self.model, objective)
        bound, close = Fraction(0), TOLERANCE * value
        while value - lower > close:
            check = solve(solver, z3.And(goal, objective <= z3.RealVal(bound, solver.ctx)), end - time.monotonic())
            if check.result == "unsat":
                lower = bound
            elif check.result == "sat" and self.rational(check.model):
                self.model, value = check.model, _value(check.model, objective)
            else:
                self.stopped = _why(check, end)
                break
            bound = (lower + value) / 2
        self.bounds.append((lower, value))


def _why(check: Check, end: float) -> str:
    """Why a bisection step gave no run to go on with."""
    if check.result == "sat":
        return "the solver's run has irrational values"
    if time.monotonic() >= end or check.reason in ("timeout", "canceled"):
        return "the time ran out"
    return f"the solver said {check.reason or 'unknown'}"


def _is_linear(solver: z3.Solver) -> bool:
    goal = z3.Goal(ctx=solver.ctx)
    goal.add(*solver.assertions())
    return z3.Probe("is-lra", ctx=solver.ctx)(goal) == 1.0


def _optimize(run: z3.BoolRef, objectives: list[z3.ArithRef], timeout_s: float, search: _Search) -> None:
    """z3's optimizer on linear constraints: when it gives a counterexample in time, it becomes ``search``'s run,
    and if it attains every minimum (none is an infimum, ``10 + epsilon``) the distances are pinned down."""
    optimizer = z3.Optimize(ctx=run.ctx)
    optimizer.set(timeout=max(1, int(timeout_s * 1000)), priority="lex")
    optimizer.add(run)
    handles = [optimizer.minimize(objective) for objective in objectives]
    if optimizer.check() != z3.sat:
        return
    model = optimizer.model()
    if not z3.is_true(model.eval(run, model_completion=True)) or not search.rational(model):
        return
    search.model = model
    values = [model.eval(o, model_completion=True) for o in objectives]
    if all(z3.is_true(z3.simplify(h.value() == v)) for h, v in zip(handles, values, strict=True)):
        search.bounds = [(v.as_fraction(), v.as_fraction()) for v in values]


def nominalise(
    u: Unrolling, solver: z3.Solver, k: int, model: z3.ModelRef, timeout_s: float
) -> tuple[z3.ModelRef, Nominal]:
    """The run nearest nominal among those violating ``u``'s property first at step ``k`` (module docstring).

    ``solver`` holds the BMC constraints up to frame ``k`` (the violation at ``k`` not yet asserted) and ``model``
    is its counterexample; the solver is left as it was.
    """
    end = time.monotonic() + max(timeout_s, 0.0)
    objectives = _objectives(u, k)
    goal = z3.Not(u.frame(k).prop)

    def rational(m: z3.ModelRef) -> bool:
        try:
            extract(u, m, k)
        except ValueError:
            return False
        return True

    search = _Search(model, rational)
    if _is_linear(solver):
        _optimize(z3.And(*solver.assertions(), goal), objectives, (end - time.monotonic()) / 2, search)
    if not search.bounds:  # not pinned down by the optimizer: bisect from its run, or BMC's
        for objective in objectives:
            if not search.stopped:
                search.bisect(solver, goal, objective, end)
                goal = z3.And(goal, objective <= z3.RealVal(search.bounds[-1][1], solver.ctx))
    original = nominal_distance(u.node, extract(u, model, k))
    kept = nominal_distance(u.node, extract(u, search.model, k))
    lower = tuple(b[0] for b in search.bounds) + (Fraction(0),) * (2 - len(search.bounds))
    return search.model, Nominal(search.status, original, kept, lower, _message(search))


def _message(search: _Search) -> str:
    """Why the run kept is not proved optimal, if it is not."""
    names = ("measurement error", "input magnitude")
    if search.stopped:
        return f"{search.stopped} lowering the {names[len(search.bounds) - 1]}; the best run found is kept"
    gaps = [
        f"{n} above {readable_value(lower)}"
        for n, (lower, value) in zip(names, search.bounds, strict=True)
        if lower < value
    ]
    return f"within {float(TOLERANCE):.1%} of the BMC run's distance: {', '.join(gaps)}" if gaps else ""
