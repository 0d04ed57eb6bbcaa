"""Counterexample smoothing (JKind's ``--smooth``): of the runs that first violate the property at the
step BMC found, one with the fewest input changes, so the trace reads as a few events instead of noise.

A change is a pair (step j >= 1, input variable) whose value at step j differs from step j - 1; an array input
counts per element (``field[j]``, as the CSV and VCD columns). The count is lowered with a cardinality bound on
the BMC solver itself (the same initial state, transitions, assumptions, lemmas and "no violation before step
k"): each sat answer is a run with fewer changes, and the final unsat answer proves the last run minimal. If
the solver says unknown or the time runs out first, the best run found so far is kept (the BMC run when none
is better) and the result says that the minimum is not proved. The engine replays the chosen run exactly,
like any other counterexample.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import z3

from atcs.model.node import as_dict, flatten
from atcs.model.ops.symbolic import unwrap
from atcs.proofs.cex.trace import input_changes
from atcs.proofs.engine.bmc import solve
from atcs.proofs.engine.system import Unrolling

__all__ = ["Smoothing", "change_indicators", "count_in", "input_changes", "smooth"]


@dataclass(frozen=True)
class Smoothing:
    """What smoothing did to one counterexample."""

    status: str
    """``minimal`` (no run of the same length with fewer input changes exists) or ``not minimal`` (the solver
    said unknown or the time ran out: the best run found is kept)."""
    original_changes: int
    """Input changes of the BMC counterexample."""
    changes: int
    """Input changes of the counterexample kept."""
    message: str = ""

    def describe(self) -> str:
        text = f"smoothed: {self.original_changes} -> {self.changes} input changes ({self.status})"
        return f"{text}: {self.message}" if self.message else text

    def as_json(self) -> dict:
        return {
            "status": self.status,
            "original_input_changes": self.original_changes,
            "input_changes": self.changes,
            "message": self.message,
        }


def change_indicators(u: Unrolling, k: int) -> list[z3.BoolRef]:
    """One term per (step 1..k, input variable): true when the input differs from the step before."""

    def variables(j):
        return flatten(as_dict(u.frame(j).inputs))

    indicators = []
    for j in range(1, k + 1):
        before, now = variables(j - 1), variables(j)
        indicators += [z3.Not(unwrap(now[name]) == unwrap(before[name])) for name in now]
    return indicators


def count_in(model: z3.ModelRef, indicators: list[z3.BoolRef]) -> int:
    """How many indicators are true in ``model``."""
    return sum(z3.is_true(model.eval(i, model_completion=True)) for i in indicators)


def smooth(
    u: Unrolling, solver: z3.Solver, k: int, model: z3.ModelRef, timeout_s: float
) -> tuple[z3.ModelRef, Smoothing]:
    """The run with the fewest input changes among those violating ``u``'s property first at step ``k``.

    ``solver`` holds the BMC constraints up to frame ``k`` (the violation at ``k`` not yet asserted) and
    ``model`` is its counterexample; the solver is left as it was.
    """
    end = time.monotonic() + max(timeout_s, 0.0)
    indicators = change_indicators(u, k)
    goal = z3.Not(u.frame(k).prop)
    best, original = model, count_in(model, indicators)
    changes = original
    while changes > 0:
        left = end - time.monotonic()
        if left <= 0:
            return best, Smoothing(
                "not minimal",
                original,
                changes,
                f"the time ran out looking for a run with at most {changes - 1} changes",
            )
        check = solve(solver, z3.And(goal, z3.AtMost(*indicators, changes - 1)), left)
        if check.result == "unsat":
            break
        if check.result == "unknown":
            return best, Smoothing(
                "not minimal",
                original,
                changes,
                f"the solver said {check.reason or 'unknown'} looking for a run with at most {changes - 1} changes",
            )
        best, changes = check.model, count_in(check.model, indicators)
    return best, Smoothing("minimal", original, changes)
