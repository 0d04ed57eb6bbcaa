"""The float run of a counterexample: the trace's inputs stepped on the float backend, the simulator's
IEEE doubles, and compared step by step with the exact replay.

Each exact value (parameters, the initial state, every step's inputs) is converted to its nearest double once;
the float run then keeps its own states, as the simulator would on those inputs, so a rounding difference can
carry on to later steps. The comparison (docs/design.md, floats vs reals: keep the gap explicit):

- a boolean (a next-state or output field, or the property's verdict ``holds``) that differs is a divergence:
  the first step and field are reported;
- numbers: the largest absolute difference per field, with its step; a non-finite float is a divergence;
- a float run that raises is a divergence (the step and the exception).

Fields are named ``next_state.<field>`` (the state step k computes), ``outputs.<field>`` and ``holds``, array
fields spread as ``field[j]``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

from atcs.model.node import as_dict, flatten
from atcs.model.ops.floating import FLOAT, floats
from atcs.proofs.cex.trace import Replay, Trace, readable_value
from atcs.properties.property import Property


@dataclass(frozen=True)
class Difference:
    """One field at one step where the float run differs from the exact run."""

    step: int
    field: str
    exact: Fraction | bool
    float: float | bool

    def describe(self) -> str:
        return f"step {self.step}, {self.field}: exact {readable_value(self.exact)}, float {self.float!r}"


@dataclass
class FloatComparison:
    steps: int
    """How many steps the float run completed."""
    first_boolean: Difference | None = None
    """The first boolean that differs (by step, then in field order)."""
    largest: dict[str, Difference] = field(default_factory=dict)
    """Per numeric field, where ``|float - exact|`` is largest (only fields that differ at all)."""
    non_finite: Difference | None = None
    """The first non-finite float (NaN or infinity)."""
    error: str | None = None
    """Why the float run stopped early."""
    float_first_violation: int | None = None

    @property
    def diverged(self) -> bool:
        """A boolean differs, a float is not finite, or the float run failed."""
        return self.first_boolean is not None or self.non_finite is not None or self.error is not None

    def gap(self, name: str) -> Fraction:
        """The largest ``|float - exact|`` of a numeric field, exactly."""
        d = self.largest[name]
        return abs(Fraction(d.float) - d.exact)


def float_replay(prop: Property, trace: Trace, exact: Replay) -> FloatComparison:
    """Step the trace's inputs through ``prop``'s node on floats and compare with ``exact``, the exact replay
    of the same trace (:func:`atcs.proofs.cex.trace.replay`)."""
    node = prop.node
    p = node.params(**{n: floats(v) for n, v in trace.params.items()})
    s = node.state(**{n: floats(v) for n, v in trace.states[0].items()})
    result = FloatComparison(steps=0)
    for k, inputs in enumerate(trace.inputs):
        i = node.inputs(**{n: floats(v) for n, v in inputs.items()})
        try:
            nxt, out = node.step(FLOAT, p, s, i)
            holds = bool(prop.holds(FLOAT, p, s, i, out, nxt))
        except Exception as exc:  # a float run that cannot go on is a divergence, reported, never hidden
            result.error = f"step {k}: {type(exc).__name__}: {exc}"
            return result
        result.steps = k + 1
        if not holds and result.float_first_violation is None:
            result.float_first_violation = k
        pairs = [(f"next_state.{n}", v, flatten(as_dict(nxt))[n]) for n, v in flatten(exact.states[k + 1]).items()]
        pairs += [(f"outputs.{n}", v, flatten(as_dict(out))[n]) for n, v in flatten(exact.outputs[k]).items()]
        pairs.append(("holds", exact.holds[k], holds))
        for name, exact_value, float_value in pairs:
            _compare(result, Difference(k, name, exact_value, float_value))
        s = nxt
    return result


def _compare(result: FloatComparison, d: Difference) -> None:
    if isinstance(d.exact, bool):
        if bool(d.float) != d.exact and result.first_boolean is None:
            result.first_boolean = Difference(d.step, d.field, d.exact, bool(d.float))
        return
    value = float(d.float)
    d = Difference(d.step, d.field, d.exact, value)
    if not math.isfinite(value):
        if result.non_finite is None:
            result.non_finite = d
        return
    gap = abs(Fraction(value) - d.exact)  # exactly: a double's own rounding error at 1/10 is about 5e-18
    if gap and (d.field not in result.largest or gap > result.gap(d.field)):
        result.largest[d.field] = d
