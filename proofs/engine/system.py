"""The transition system of a property's node, unrolled step by step.

``init`` and ``trans`` are not written by hand: they come from running the node's
``init`` and ``step`` functions under the symbolic Ops. Frame ``k`` holds

- the state variables ``field@k`` and input variables ``field@k``,
- the outputs of the step (terms, not variables),
- ``trans[k]``: the next-state variables ``field@(k+1)`` equal the step's result,
- ``assumed[k]``, ``prop[k]`` and ``lemmas[k]``: the property's assumptions,
  predicate and auxiliary lemmas at step ``k``.

Parameters are one set of constants for the whole run (``name``, no ``@``):
symbolic unless the property fixes them.
"""

from __future__ import annotations

from dataclasses import dataclass

import z3

from atcs.model.node import Node, Sort
from atcs.model.ops import to_fraction
from atcs.model.ops.symbolic import SYMBOLIC, Bool, Real, context, unwrap
from atcs.properties.property import Property


def _variable(kind: str, label: str):
    return Real(z3.Real(label, context())) if kind == "real" else Bool(z3.Bool(label, context()))


def variable(name: str, sort: Sort, suffix: str | None):
    """Fresh z3 constants for one field: ``name@suffix``, or a tuple ``name[j]@suffix``."""
    at = "" if suffix is None else f"@{suffix}"
    if sort.size is None:
        return _variable(sort.kind, f"{name}{at}")
    return tuple(_variable(sort.kind, f"{name}[{j}]{at}") for j in range(sort.size))


def variables(cls: type, node: Node, role: str, suffix: str | None):
    """An instance of ``cls`` whose fields are fresh z3 constants ``field@suffix``."""
    return cls(**{name: variable(name, sort, suffix) for name, sort in node.sorts(role).items()})


def _fixed_scalar(node: Node, name: str, kind: str, value):
    if kind == "bool":
        if not isinstance(value, bool):
            raise TypeError(f"fixed parameter {name!r} of node {node.name!r} is boolean, got {value!r}")
        return Bool(z3.BoolVal(value, context()))
    f = to_fraction(value, what=f"fixed parameter {name!r}")
    return Real(z3.Q(f.numerator, f.denominator, context()))


def _fixed(node: Node, name: str, value):
    sort = node.sorts("params")[name]
    if sort.size is None:
        return _fixed_scalar(node, name, sort.kind, value)
    if not isinstance(value, (tuple, list)) or len(value) != sort.size:
        raise TypeError(f"fixed parameter {name!r} of node {node.name!r} needs {sort.size} values, got {value!r}")
    return tuple(_fixed_scalar(node, f"{name}[{j}]", sort.kind, v) for j, v in enumerate(value))


def equal(left, right) -> Bool:
    """Two field values (scalars or tuples) are equal."""
    if isinstance(left, tuple):
        return SYMBOLIC.and_(*(SYMBOLIC.eq(a, b) for a, b in zip(left, right, strict=True)))
    return SYMBOLIC.eq(left, right)


@dataclass
class Frame:
    state: object
    inputs: object
    outputs: object
    next_state: object
    trans: z3.BoolRef
    assumed: z3.BoolRef
    prop: z3.BoolRef
    lemmas: z3.BoolRef
    parts: dict[str, z3.BoolRef]
    """``trans``, ``assumed`` and ``lemmas`` conjunct by conjunct: ``equation <field>``, ``assumption <name>``,
    ``lemma <name>`` (what a validity core is made of, :mod:`atcs.proofs.engine.cores`)."""


class Unrolling:
    """Frames 0, 1, 2, ... of a property's node, created on demand."""

    def __init__(self, prop: Property, lemmas: tuple[Property, ...] = ()):
        self.prop = prop
        self.node = prop.node
        self.lemmas = lemmas
        fixed = dict(prop.fixed_params)
        values = {}
        for name, sort in self.node.sorts("params").items():
            values[name] = _fixed(self.node, name, fixed[name]) if name in fixed else variable(name, sort, None)
        self.params = self.node.params(**values)
        self.frames: list[Frame] = []
        self._states = [variables(self.node.state, self.node, "state", "0")]

    def state(self, k: int):
        """The state variables ``field@k``."""
        self.frame(max(k - 1, 0))
        return self._states[k]

    def init(self) -> z3.BoolRef:
        return unwrap(self.node.init(SYMBOLIC, self.params, self.state(0)))

    def frame(self, k: int) -> Frame:
        while len(self.frames) <= k:
            self._add_frame()
        return self.frames[k]

    def _add_frame(self):
        o, p, node = SYMBOLIC, self.params, self.node
        k = len(self.frames)
        s = self._states[k]
        i = variables(node.inputs, node, "inputs", str(k))
        computed, out = node.step(o, p, s, i)
        nxt = variables(node.state, node, "state", str(k + 1))
        self._states.append(nxt)
        equations = {f"equation {n}": equal(getattr(nxt, n), getattr(computed, n)) for n in node.sorts("state")}
        trans = unwrap(o.and_(*equations.values()))
        assumptions = {f"assumption {a.name}": a.holds(o, p, s, i) for a in self.prop.assumptions}
        assumed = unwrap(o.and_(*assumptions.values()))
        holds = unwrap(self.prop.holds(o, p, s, i, out, nxt))
        lemmas = {f"lemma {lemma.name}": lemma.holds(o, p, s, i, out, nxt) for lemma in self.lemmas}
        parts = {name: unwrap(term) for name, term in (equations | assumptions | lemmas).items()}
        self.frames.append(Frame(s, i, out, nxt, trans, assumed, holds, unwrap(o.and_(*lemmas.values())), parts))

    def distinct(self, a: int, b: int) -> z3.BoolRef:
        """States ``a`` and ``b`` differ in at least one field."""
        sa, sb = self.state(a), self.state(b)
        return unwrap(
            SYMBOLIC.or_(*(SYMBOLIC.not_(equal(getattr(sa, n), getattr(sb, n))) for n in self.node.sorts("state")))
        )


def model_value(model: z3.ModelRef, value):
    """The exact value (Fraction or bool, or a tuple of them) of a wrapped term in a z3 model."""
    if isinstance(value, tuple):
        return tuple(model_value(model, v) for v in value)
    term = model.eval(unwrap(value), model_completion=True)
    if z3.is_true(term):
        return True
    if z3.is_false(term):
        return False
    if z3.is_rational_value(term):
        return term.as_fraction()
    raise ValueError(f"the solver's value {term} for {unwrap(value)} is not rational and cannot be replayed exactly")
