"""What a test vector of one step can cover: requirements, comparison boundaries, MC/DC of decisions.

The goals are read off the z3 terms of one step of a node (its own ``step`` function run on the symbolic
backend, :class:`StepFrame`), so nothing restates the model:

- a *decision* is a boolean term where the step branches or assigns: each boolean output and next-state
  field, and the condition of every ``ite`` (``o.ite``, and the ``min``/``max``/table look-ups built from it);
- its *conditions* are the atoms it combines with and/or/not (comparisons and boolean variables);
- a *boundary* is a comparison ``a < b`` (``<=``, ``>``, ``>=``, ``=``): the vectors put ``a - b`` at 0 and
  at plus and minus :data:`BOUNDARY_DELTA`, where the solver can with the comparison deciding its decision's
  outcome (so an implementation that gets the threshold wrong shows a different output).

The step's domain is where some property of the node speaks: the disjunction, over the node's properties, of
its fixed parameters and its assumptions (seed 001 §3.4: each sub-function is tested in the environment its
requirements assume). A node no property is about has the whole state space.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from fractions import Fraction

import z3

from atcs.model.node import Node, as_dict
from atcs.model.ops.symbolic import SYMBOLIC, context, unwrap
from atcs.proofs.engine.system import _fixed, equal, variables
from atcs.properties.property import Property

BOUNDARY_DELTA = Fraction(1, 1000)
"""How far either side of a comparison's threshold the "around" vectors are (in the compared quantity's unit)."""

_COMPARISONS = (z3.Z3_OP_LT, z3.Z3_OP_LE, z3.Z3_OP_GT, z3.Z3_OP_GE)
_CONNECTIVES = (z3.Z3_OP_AND, z3.Z3_OP_OR, z3.Z3_OP_NOT, z3.Z3_OP_IMPLIES, z3.Z3_OP_XOR)


@dataclass(frozen=True)
class Context:
    """One property's environment: its fixed parameters and its assumptions, over the frame's variables."""

    property: Property
    term: z3.BoolRef


class StepFrame:
    """One symbolic step of a node: every parameter, state and input field a z3 constant (``field@v``)."""

    def __init__(self, node: Node, properties: tuple[Property, ...] = ()):
        self.node = node
        self.properties = properties
        o = SYMBOLIC
        self.params = variables(node.params, node, "params", "v")
        self.state = variables(node.state, node, "state", "v")
        self.inputs = variables(node.inputs, node, "inputs", "v")
        self.next_state, self.outputs = node.step(o, self.params, self.state, self.inputs)
        self.contexts = tuple(self._context(p) for p in properties)
        self.domain = z3.Or(*(c.term for c in self.contexts)) if self.contexts else z3.BoolVal(True, context())

    def _context(self, prop: Property) -> Context:
        o, p = SYMBOLIC, self.params
        fixed = [equal(getattr(p, name), _fixed(self.node, name, value)) for name, value in prop.fixed_params.items()]
        return Context(prop, unwrap(o.and_(*fixed, prop.assumed(o, p, self.state, self.inputs))))

    def variables(self) -> list[z3.ExprRef]:
        """Every z3 constant of the frame, parameters, state and inputs, in declaration order."""
        return [unwrap(v) for record in (self.params, self.state, self.inputs) for v in _leaves(as_dict(record))]

    def results(self) -> Iterator[tuple[str, z3.ExprRef]]:
        """``(where, term)`` of every next-state and output field (array elements spread as ``field[j]``)."""
        for role, record in (("next_state", self.next_state), ("outputs", self.outputs)):
            for name, value in as_dict(record).items():
                if isinstance(value, tuple):
                    for j, v in enumerate(value):
                        yield f"{role}.{name}[{j}]", unwrap(v)
                else:
                    yield f"{role}.{name}", unwrap(value)


def _leaves(record: dict) -> Iterator:
    for value in record.values():
        yield from value if isinstance(value, tuple) else (value,)


@dataclass(frozen=True)
class Decision:
    id: str
    where: str
    """The first result field it was found in, and how: ``outputs.service_brake`` or ``ite in ...``."""
    term: z3.BoolRef
    conditions: tuple[z3.BoolRef, ...]


def is_comparison(term: z3.ExprRef) -> bool:
    """An ordering comparison, or an equation between numbers."""
    return z3.is_app(term) and (
        term.decl().kind() in _COMPARISONS or (term.decl().kind() == z3.Z3_OP_EQ and z3.is_arith(term.arg(0)))
    )


def conditions(decision: z3.BoolRef) -> tuple[z3.BoolRef, ...]:
    """The atoms a decision combines (comparisons and boolean variables), each once, in the order first met."""
    found: dict[int, z3.BoolRef] = {}
    seen: set[int] = set()

    def visit(t):
        if t.get_id() in seen:
            return
        seen.add(t.get_id())
        if z3.is_true(t) or z3.is_false(t):
            return
        kind = t.decl().kind() if z3.is_app(t) else None
        boolean_ite = kind == z3.Z3_OP_ITE and z3.is_bool(t)
        boolean_eq = kind == z3.Z3_OP_EQ and z3.is_bool(t.arg(0))
        if kind in _CONNECTIVES or boolean_ite or boolean_eq:
            for child in t.children():
                visit(child)
        else:
            found.setdefault(t.get_id(), t)

    visit(decision)
    return tuple(found.values())


def decisions(frame: StepFrame) -> list[Decision]:
    """Every decision of the step with at least one condition, each once, in the order of the result fields."""
    found: list[Decision] = []
    known: set[int] = set()
    seen: set[int] = set()

    def add(term, where):
        if term.get_id() in known:
            return
        known.add(term.get_id())
        conds = conditions(term)
        if conds:
            found.append(Decision(f"D{len(found) + 1}", where, term, conds))

    def visit(t, where):
        if t.get_id() in seen:
            return
        seen.add(t.get_id())
        if z3.is_app(t) and t.decl().kind() == z3.Z3_OP_ITE:
            add(t.arg(0), f"ite in {where}")
        for child in t.children():
            visit(child, where)

    for where, term in frame.results():
        if z3.is_bool(term):
            add(term, where)
        visit(term, where)
    return found


def boundaries(found: list[Decision]) -> list[tuple[z3.BoolRef, Decision]]:
    """The comparisons among the decisions' conditions whose two sides are not both constants, each once, with
    the first decision it is a condition of."""
    atoms: dict[int, tuple[z3.BoolRef, Decision]] = {}
    for d in found:
        for c in d.conditions:
            if is_comparison(c) and not z3.is_rational_value(z3.simplify(c.arg(0) - c.arg(1))):
                atoms.setdefault(c.get_id(), (c, d))
    return list(atoms.values())


def decides(decision: Decision, condition: z3.BoolRef) -> z3.BoolRef:
    """The condition alone decides the decision's outcome: flipping it, the others as they are, flips the
    outcome (the Boolean derivative)."""
    ctx = condition.ctx
    return z3.Xor(
        z3.substitute(decision.term, (condition, z3.BoolVal(True, ctx))),
        z3.substitute(decision.term, (condition, z3.BoolVal(False, ctx))),
    )


def gap(comparison: z3.BoolRef) -> z3.ArithRef:
    """``a - b`` of a comparison ``a ⋈ b``: its threshold is where this is 0."""
    return comparison.arg(0) - comparison.arg(1)


_INFIX = {
    z3.Z3_OP_LT: "<",
    z3.Z3_OP_LE: "<=",
    z3.Z3_OP_GT: ">",
    z3.Z3_OP_GE: ">=",
    z3.Z3_OP_EQ: "==",
    z3.Z3_OP_ADD: "+",
    z3.Z3_OP_SUB: "-",
    z3.Z3_OP_MUL: "*",
    z3.Z3_OP_DIV: "/",
}


def short(term: z3.ExprRef, limit: int = 120) -> str:
    """A term as one line of at most ``limit`` characters, printed only as far as the limit (z3's own printer
    takes seconds on the large shared terms of a table look-up)."""
    parts: list[str] = []
    size = [0]

    def emit(text: str) -> bool:
        parts.append(text)
        size[0] += len(text)
        return size[0] <= limit

    complete = _print_term(term, emit)
    text = "".join(parts)
    if complete and text.startswith("(") and text.endswith(")") and z3.is_app(term) and term.decl().kind() in _INFIX:
        text = text[1:-1]
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _print_term(t: z3.ExprRef, emit: Callable[[str], bool]) -> bool:
    """Print a term through ``emit``, infix where z3 has an infix operator, stopping as soon as ``emit`` says the
    limit is passed; True if the term was printed whole."""
    if not z3.is_app(t) or t.num_args() == 0:
        return emit(str(t))
    kind = t.decl().kind()
    if kind in _INFIX and t.num_args() >= 2:
        if not emit("("):
            return False
        for j, child in enumerate(t.children()):
            if (j and not emit(f" {_INFIX[kind]} ")) or not _print_term(child, emit):
                return False
        return emit(")")
    if not emit(f"{t.decl().name()}("):
        return False
    for j, child in enumerate(t.children()):
        if (j and not emit(", ")) or not _print_term(child, emit):
            return False
    return emit(")")
