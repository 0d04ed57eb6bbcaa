"""Vacuity: is a proved property true only because nothing it speaks of can happen?

Two questions, each answered with a witness run found by BMC (a run from an initial state with every assumption
and lemma holding, replayed on the exact backend):

- are the property's assumptions satisfiable together with the initial state (at step 0)?
- for each implication in the property's predicate (``o.implies(a, b)``, also inside a conjunction or the
  consequent of another), is there a reachable step where its antecedent ``a`` holds?

The antecedents are read off the predicate's own term, so no property states them twice. A property whose
assumptions admit no run, or with an antecedent no run reaches within ``depth`` steps, is ``vacuous``: the
engine reports it so, never as proved.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import z3

from atcs.proofs.cex.trace import Trace, extract, replay
from atcs.proofs.engine.bmc import new_solver, solve
from atcs.proofs.engine.system import Unrolling

WITNESS_DEPTH = 8
"""How many steps the witness search looks: past it an antecedent not reached makes the property vacuous."""


@dataclass(frozen=True)
class Witness:
    what: str
    """``assumptions`` or ``antecedent j: <term>``."""
    step: int
    trace: Trace


@dataclass
class Vacuity:
    status: str
    """``non-vacuous``, ``vacuous`` or ``unknown`` (the solver gave up or the time ran out)."""
    message: str = ""
    witnesses: list[Witness] = field(default_factory=list)


def antecedents(term: z3.BoolRef) -> list[z3.BoolRef]:
    """The antecedents of the implications in ``term``: through conjunctions, and conjoined with the outer
    antecedent inside a consequent."""
    if z3.is_and(term):
        return [a for child in term.children() for a in antecedents(child)]
    if z3.is_implies(term):
        outer = term.arg(0)
        return [outer, *(z3.And(outer, inner) for inner in antecedents(term.arg(1)))]
    return []


def _short(term: z3.ExprRef, limit: int = 160) -> str:
    text = " ".join(str(term).split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


def check_vacuity(u: Unrolling, *, timeout_s: float, depth: int = WITNESS_DEPTH) -> Vacuity:
    """Look for the witnesses of :mod:`this module <atcs.proofs.engine.vacuity>` on the unrolling of a property (with
    its lemmas), up to ``depth`` steps, within ``timeout_s`` seconds."""
    end = time.monotonic() + timeout_s
    solver = new_solver()
    solver.add(u.init())
    found: list[Witness] = []
    missing: dict[int, str] = {}
    for k in range(depth + 1):
        f = u.frame(k)
        solver.add(f.trans, f.assumed, f.lemmas)
        goals = antecedents(f.prop)
        if k == 0:
            missing = {j: _short(a) for j, a in enumerate(goals)}
            goals_now = [("assumptions", z3.BoolVal(True, f.prop.ctx))]
        else:
            goals_now = []
        goals_now += [(f"antecedent {j}: {missing[j]}", goals[j]) for j in sorted(missing)]
        for what, goal in goals_now:
            check = solve(solver, goal, max(end - time.monotonic(), 0.001))
            if check.result == "unknown":
                return Vacuity(
                    "unknown",
                    f"the solver gave up looking for a run where the {what} ({check.reason or 'unknown'}, step {k})",
                    found,
                )
            if check.result == "unsat":
                if what == "assumptions":
                    return Vacuity(
                        "vacuous", "no initial state and input meet the assumptions: the property claims nothing", found
                    )
                continue
            trace = extract(u, check.model, k)
            problems = replay(u.prop, trace).problems
            if problems:
                return Vacuity("unknown", f"the witness for the {what} does not replay: {problems[0]}", found)
            found.append(Witness(what, k, trace))
            if what != "assumptions":
                missing.pop(int(what.split(":")[0].removeprefix("antecedent ")))
        if not missing:
            return Vacuity("non-vacuous", "", found)
    first = min(missing)
    return Vacuity(
        "vacuous",
        f"no run reaches antecedent {first} ({missing[first]}) within {depth} steps: the "
        "implication holds only because its condition never arises",
        found,
    )
