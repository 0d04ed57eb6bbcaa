"""Certified test vectors of a step function, found with z3, expected outputs computed exactly.

Seed 001 §3.4 (Fig. 9 to 12) tests each of the ATP's sub-function models with input and expected-output test
cases before code generation. A vector here is one step of a node, the model's sub-function: parameters, state
and inputs, and the next state and outputs the exact backend computes from them. :func:`generate` finds vectors
for three kinds of goal (:mod:`atcs.proofs.vectors.goals`):

- ``requirement``: for each property of the node, a reachable step where its assumptions hold and the
  condition of each of its implications holds (the vacuity witnesses, :mod:`atcs.proofs.engine.vacuity`);
- ``boundary``: each comparison at its threshold and just either side of it;
- ``mcdc``: for each condition of each decision, two vectors in which only that condition and the decision's
  outcome differ (unique cause); where the decision's other conditions are coupled to it, two vectors in which
  the condition alone decides the outcome, the others masking nothing (masking MC/DC, DO-178C / CAST-6).

A goal the solver shows impossible in the domain is ``infeasible`` (for MC/DC, the condition cannot change the
decision on its own: a finding about the model); one it gives up on is ``unknown``. Neither is covered. A property
that cannot be built (its assumptions or predicate raise on z3 terms) leaves one ``unknown`` requirement goal
saying why; a step function that cannot be built raises :class:`StepBuildError`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import z3

from atcs.model.errors import AtcsError
from atcs.model.node import Node, as_dict
from atcs.model.ops.exact import EXACT
from atcs.model.ops.symbolic import unwrap, wrap
from atcs.proofs.engine.bmc import new_solver, solve
from atcs.proofs.engine.prove import model_location
from atcs.proofs.engine.system import Unrolling, model_value
from atcs.proofs.engine.vacuity import check_vacuity
from atcs.proofs.vectors.goals import BOUNDARY_DELTA, Decision, StepFrame, boundaries, decides, decisions, gap, short
from atcs.properties.property import Property

KINDS = ("requirement", "boundary", "mcdc")


class StepBuildError(AtcsError):
    """A function's step cannot be built on z3 terms, so it has no vectors; the message says why and where."""


@dataclass
class Vector:
    """One step of a function: what goes in, what the exact model computes, and which goals it covers."""

    id: str
    context: str
    """The property whose environment (fixed parameters, assumptions) the vector is in; empty for none."""
    params: dict[str, Any]
    state: dict[str, Any]
    inputs: dict[str, Any]
    next_state: dict[str, Any] = field(default_factory=dict)
    outputs: dict[str, Any] = field(default_factory=dict)
    covers: list[str] = field(default_factory=list)

    def key(self) -> tuple:
        return tuple(tuple(sorted(r.items())) for r in (self.params, self.state, self.inputs))


@dataclass
class Goal:
    kind: str
    """``requirement``, ``boundary`` or ``mcdc``."""
    id: str
    text: str
    status: str = "unknown"
    """``covered``, ``infeasible`` or ``unknown``."""
    reason: str = ""


@dataclass
class FunctionVectors:
    function: str
    seed: str
    vectors: list[Vector]
    goals: list[Goal]
    requirements: list[str]
    """The requirement ids of the node's properties, each once, in registry order."""
    seconds: float = 0.0
    errors: list[str] = field(default_factory=list)
    """The properties that could not be built, one line each: ``<property>: <why>`` (their goals are unknown)."""
    configuration: dict | None = None
    """For vectors of a configuration's properties: its ``name`` and ``data_sha256`` (the manifest's)."""

    def coverage(self) -> dict[str, dict[str, int]]:
        """Per kind of goal: how many there are and how many are covered, infeasible or unknown."""
        table = {}
        for kind in KINDS:
            goals = [g for g in self.goals if g.kind == kind]
            table[kind] = {
                "goals": len(goals),
                **{s: sum(g.status == s for g in goals) for s in ("covered", "infeasible", "unknown")},
            }
        return table

    def requirements_covered(self) -> list[str]:
        covered = {g.id.split(" ", 1)[0] for g in self.goals if g.kind == "requirement" and g.status == "covered"}
        return [r for r in self.requirements if r in covered]


def expected(node: Node, vector: Vector) -> None:
    """Fill in the next state and outputs of the exact backend (raises what the model raises)."""
    nxt, out = node.step(EXACT, node.params(**vector.params), node.state(**vector.state), node.inputs(**vector.inputs))
    vector.next_state, vector.outputs = as_dict(nxt), as_dict(out)


class _Search:
    """The solver state of one function's generation: the frame, a second copy of it for MC/DC pairs, and the
    vectors found so far (identical vectors merged)."""

    def __init__(self, frame: StepFrame, timeout_s: float, deadline: float):
        self.frame = frame
        self.timeout_s = timeout_s
        self.deadline = deadline
        variables = frame.variables()
        self.twin = [(v, z3.Const(str(v).replace("@v", "@w"), v.sort())) for v in variables]
        self.solver = new_solver()
        self.solver.add(frame.domain)
        self.pair_solver = new_solver()
        self.pair_solver.add(frame.domain, self.copy(frame.domain))
        self.vectors: dict[tuple, Vector] = {}

    def copy(self, term: z3.ExprRef) -> z3.ExprRef:
        return z3.substitute(term, *self.twin)

    def check(self, goal: z3.BoolRef, *, pair: bool = False):
        """The solver's verdict on ``goal`` in the domain (both copies' domains for a pair), or None and why."""
        left = self.deadline - time.monotonic()
        if left <= 0:
            return None, "the generation's time ran out"
        check = solve(self.pair_solver if pair else self.solver, goal, min(self.timeout_s, left))
        if check.result == "unknown":
            return None, check.reason or "unknown"
        return check, ""

    def record(self, model: z3.ModelRef, twin: bool) -> dict[str, dict[str, Any]]:
        """The exact values of the frame's variables (or of their twins) in a model, by role and field."""
        renamed = {str(v): w for v, w in self.twin} if twin else {}

        def value(v):
            if isinstance(v, tuple):
                return tuple(value(x) for x in v)
            term = unwrap(v)
            return model_value(model, wrap(renamed.get(str(term), term)))

        return {
            role: {n: value(v) for n, v in as_dict(getattr(self.frame, role)).items()}
            for role in ("params", "state", "inputs")
        }

    def context_of(self, model: z3.ModelRef, twin: bool) -> str:
        for c in self.frame.contexts:
            term = self.copy(c.term) if twin else c.term
            if z3.is_true(model.eval(term, model_completion=True)):
                return c.property.name
        return ""

    def add(self, node: Node, model: z3.ModelRef, covers: str, *, twin: bool = False) -> Vector:
        values = self.record(model, twin)
        vector = Vector("", self.context_of(model, twin), values["params"], values["state"], values["inputs"])
        return self.keep(node, vector, covers)

    def keep(self, node: Node, vector: Vector, covers: str) -> Vector:
        vector = self.vectors.setdefault(vector.key(), vector)
        if not vector.next_state and not vector.outputs:
            expected(node, vector)
        vector.covers.append(covers)
        return vector


def _unrollings(props: tuple[Property, ...], goals: list[Goal], errors: list[str]) -> list[tuple[Property, Unrolling]]:
    """Each property with its unrolling, the first step built (its assumptions and predicate on z3 terms); a
    property that cannot be built gets one ``unknown`` requirement goal saying why, and a line in ``errors``."""
    built = []
    for prop in props:
        try:
            unrolling = Unrolling(prop)
            unrolling.frame(0)
        except Exception as exc:  # the property could not be built: an unknown goal, never a pass
            why = f"the property could not be built: {type(exc).__name__}: {exc}{model_location(exc)}"
            goals.append(Goal("requirement", f"{prop.requirement} {prop.name} (not built)", prop.text, "unknown", why))
            errors.append(f"{prop.name}: {why}")
            continue
        built.append((prop, unrolling))
    return built


def _requirement_goals(search: _Search, node: Node, built: list[tuple[Property, Unrolling]], goals: list[Goal]) -> None:
    for prop, unrolling in built:
        left = search.deadline - time.monotonic()
        vac = check_vacuity(unrolling, timeout_s=max(min(left, search.timeout_s * 10), 0.001))
        for witness in vac.witnesses:
            goal = Goal(
                "requirement",
                f"{prop.requirement} {prop.name} ({witness.what.split(':')[0]})",
                f"{prop.text} [{witness.what}]",
            )
            goals.append(goal)
            k, trace = witness.step, witness.trace
            vector = Vector("", prop.name, dict(trace.params), dict(trace.states[k]), dict(trace.inputs[k]))
            _cover(goal, lambda goal=goal, vector=vector: search.keep(node, vector, goal.id))
        if vac.status != "non-vacuous":
            goals.append(
                Goal(
                    "requirement",
                    f"{prop.requirement} {prop.name} (not reached)",
                    prop.text,
                    "infeasible" if vac.status == "vacuous" else "unknown",
                    vac.message,
                )
            )


def _boundary_goals(
    search: _Search, node: Node, numbered: list[tuple[int, z3.BoolRef, Decision]], goals: list[Goal]
) -> None:
    for j, comparison, decision in numbered:
        g = gap(comparison)
        observed = decides(decision, comparison)
        for label, offset in (("at", Fraction(0)), ("below", -BOUNDARY_DELTA), ("above", BOUNDARY_DELTA)):
            goal = Goal("boundary", f"B{j} {label}", f"{short(comparison)}: a - b = {offset}")
            goals.append(goal)
            on = g == z3.Q(offset.numerator, offset.denominator, g.ctx)
            check, reason = search.check(z3.And(on, observed))
            if check is not None and check.result == "unsat":
                goal.text += f" (not deciding {decision.id})"
                check, reason = search.check(on)
            else:
                goal.text += f" (deciding {decision.id})"
            _settle(search, node, goal, check, reason, lambda model, goal=goal: (search.add(node, model, goal.id),))


def _mcdc_goals(search: _Search, node: Node, d: Decision, goals: list[Goal]) -> None:
    for j, c in enumerate(d.conditions, start=1):
        goal = Goal("mcdc", f"{d.id}.C{j}", f"{short(c)} decides {d.where}: {short(d.term)}")
        goals.append(goal)
        differs = z3.Xor(d.term, search.copy(d.term))
        flips = z3.Xor(c, search.copy(c))
        others = [c2 == search.copy(c2) for c2 in d.conditions if c2 is not c]
        check, reason = search.check(z3.And(differs, flips, *others), pair=True)
        if check is not None and check.result == "unsat":
            goal.text += " (masking)"
            free = decides(d, c)
            check, reason = search.check(z3.And(differs, flips, free, search.copy(free)), pair=True)
        _settle(
            search,
            node,
            goal,
            check,
            reason,
            lambda model, goal=goal: (
                search.add(node, model, f"{goal.id} (pair a)"),
                search.add(node, model, f"{goal.id} (pair b)", twin=True),
            ),
        )


def _settle(search, node, goal: Goal, check, reason: str, add: Callable) -> None:
    if check is None:
        goal.status, goal.reason = "unknown", reason
    elif check.result == "unsat":
        goal.status = "infeasible"
    else:
        _cover(goal, lambda: add(check.model))


def _cover(goal: Goal, add: Callable) -> None:
    """Add the goal's vector(s); covered, unless the exact model refuses them (a division by zero)."""
    try:
        add()
    except (ArithmeticError, ValueError) as exc:
        goal.status, goal.reason = "unknown", f"the exact model refuses the solver's vector: {exc}"
        return
    goal.status = "covered"


def generate(
    node: Node, props: tuple[Property, ...], *, timeout_s: float = 10, budget_s: float = 3600
) -> FunctionVectors:
    """The vectors of one function (see the module docstring); ``timeout_s`` bounds each solver query,
    ``budget_s`` the whole function (goals past it are ``unknown``)."""
    start = time.monotonic()
    goals: list[Goal] = []
    errors: list[str] = []
    built = _unrollings(props, goals, errors)
    try:
        frame = StepFrame(node, tuple(prop for prop, _ in built))
        found = decisions(frame)
    except Exception as exc:  # the step itself could not be built: no vectors, never a pass
        raise StepBuildError(
            f"the step could not be built on z3 terms: {type(exc).__name__}: {exc}{model_location(exc)}"
        ) from exc
    search = _Search(frame, timeout_s, start + budget_s)
    _requirement_goals(search, node, built, goals)
    numbered = [(j, c, d) for j, (c, d) in enumerate(boundaries(found), start=1)]
    for d in found:  # decision by decision, so a budget that runs out leaves whole decisions, not a kind, unknown
        _boundary_goals(search, node, [b for b in numbered if b[2] is d], goals)
        _mcdc_goals(search, node, d, goals)
    vectors = list(search.vectors.values())
    for n, vector in enumerate(vectors, start=1):
        vector.id = f"{node.name}-{n:04d}"
    requirements = list(dict.fromkeys(p.requirement for p in props))
    return FunctionVectors(node.name, node.seed, vectors, goals, requirements, time.monotonic() - start, errors)
