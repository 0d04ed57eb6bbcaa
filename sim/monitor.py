"""Run a node cycle by cycle on a concrete backend, checking property predicates at every step.

The predicates are the very ones the proofs use (``Property.holds``); the step
is the node's own step function. A property is checked at a step only while its
assumptions have held at every step so far (as in the proof: outside its
assumptions a property claims nothing). Works with scalars or with numpy arrays
(a batch of trains): a property is violated if it fails for any element.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from atcs.model.errors import AtcsViolation
from atcs.model.node import Node
from atcs.model.ops.floating import FLOAT
from atcs.model.ops.traced import Untraceable, shape, trace, trace_step_first_false
from atcs.properties.property import Property


class PropertyViolation(AtcsViolation):
    """A property predicate was false at a step where the property applies."""

    def __init__(self, prop: Property, step: int, state: Any, inputs: Any, outputs: Any):
        self.prop, self.step = prop, step
        self.state, self.inputs, self.outputs = state, inputs, outputs
        super().__init__(f"{prop.name} ({prop.requirement}) violated at step {step}: {prop.text}")


def registered_properties(node: Node) -> tuple[Property, ...]:
    """The registered properties about ``node``, in the registry's order: what the simulator checks of it."""
    from atcs.properties import PROPERTIES

    return tuple(p for p in PROPERTIES.values() if p.node is node)


def _all(value) -> bool:
    return value if isinstance(value, bool) else bool(np.all(value))


def _holds_at_step(prop: Property, o, p, s, i, out, nxt):
    """``prop`` at one step, its assumptions taken at that step only."""
    return o.implies(prop.assumed(o, p, s, i), prop.holds(o, p, s, i, out, nxt))


def _checked(prop: Property):
    """:func:`_holds_at_step` of ``prop`` as a predicate of the step alone (what a trace is made of)."""

    def predicate(o, p, s, i, out, nxt):
        return _holds_at_step(prop, o, p, s, i, out, nxt)

    predicate.__qualname__ = prop.name
    return predicate


@dataclass(frozen=True)
class _Traced:
    """A program traced once for one shape of its arguments: a function's, or a node's step followed by the check
    of its properties (:func:`~atcs.model.ops.traced.trace_step_first_false`)."""

    run: Any
    keeps: tuple = ()
    """The functions, properties and backend traced: kept alive while the trace is, so that their ids, which key
    it, are not reused."""


class Traces:
    """The programs traced from the simulator's functions (:mod:`atcs.model.ops.traced`), one per function,
    backend and shape of the arguments, traced on first sight; the most recently used are kept. A simulation
    keeps its own, so that each traces the functions as they are when it starts. Where the arguments cannot be
    traced (a function that branches on a value) the function itself runs."""

    KEPT = 512  # shapes (the simulator's route windows come in a few dozen lengths)

    def __init__(self):
        self._programs: OrderedDict[Any, _Traced | None] = OrderedDict()

    def __len__(self) -> int:
        return len(self._programs)

    def _program(self, key, make: Callable[[], _Traced]) -> _Traced | None:
        if key in self._programs:
            self._programs.move_to_end(key)
            return self._programs[key]
        try:
            traced = make()
        except Untraceable:
            traced = None
        self._programs[key] = traced
        if len(self._programs) > self.KEPT:
            self._programs.popitem(last=False)
        return traced

    def call(self, function: Callable[..., Any], ops, *args):
        """``function(ops, *args)``, as its traced program where the arguments can be traced."""
        try:
            key = (id(function), id(ops), shape(args))
        except Untraceable:
            return function(ops, *args)
        traced = self._program(key, lambda: _Traced(trace(function, ops, *args), keeps=(function, ops)))
        return traced.run(*args) if traced is not None else function(ops, *args)

    def node(self, node: Node, params, state, inputs, properties: tuple[Property, ...], ops) -> _Traced | None:
        """The traced step and check for these arguments' shape (one program: a check reuses what the step
        computed), or None where they cannot be traced."""
        try:
            key = (id(node), id(ops), tuple(map(id, properties)), shape((params, state, inputs)))
        except Untraceable:
            return None

        def make() -> _Traced:
            checks = [_checked(p) for p in properties]
            program = trace_step_first_false(node.step, checks, ops, params, state, inputs)
            return _Traced(program, (node, ops, properties))

        return self._program(key, make)


def check_step(
    node: Node,
    params,
    state,
    inputs,
    properties: tuple[Property, ...],
    step: int,
    ops=FLOAT,
    traces: Traces | None = None,
):
    """One step of ``node`` with ``properties`` checked on it (their assumptions taken at this step only):
    returns (next state, outputs), or raises :class:`PropertyViolation`.

    With ``traces``, the step and the checks run as the straight-line programs traced from the very functions
    (the same operations in the same order, without the backend's dispatch), wherever the arguments can be
    traced; without, the functions themselves run."""
    programs = traces.node(node, params, state, inputs, properties, ops) if traces is not None else None
    if programs is not None:
        nxt, out, failed = programs.run(params, state, inputs)
        if failed >= 0:
            raise PropertyViolation(properties[failed], step, state, inputs, out)
        return nxt, out
    nxt, out = node.step(ops, params, state, inputs)
    for prop in properties:
        if not _all(_holds_at_step(prop, ops, params, state, inputs, out, nxt)):
            raise PropertyViolation(prop, step, state, inputs, out)
    return nxt, out


def run(traces: Traces | None, function: Callable[..., Any], ops, *args):
    """``function(ops, *args)``: as its traced program with ``traces`` (:meth:`Traces.call`), else as it is."""
    return traces.call(function, ops, *args) if traces is not None else function(ops, *args)


_PREDICATES: dict[tuple[int, ...], tuple[tuple[Property, ...], Callable[..., tuple]]] = {}


def _predicates(properties: tuple[Property, ...]) -> Callable[..., tuple]:
    """One function of a step giving each property's assumptions and predicate, in turn; the same function for the
    same properties, so that a shared :class:`Traces` traces it once (the properties are kept with it, so that
    their ids, which key it, are not reused)."""
    key = tuple(map(id, properties))
    if key not in _PREDICATES:

        def predicates(o, p, s, i, out, nxt):
            return tuple((prop.assumed(o, p, s, i), prop.holds(o, p, s, i, out, nxt)) for prop in properties)

        _PREDICATES[key] = (properties, predicates)
    return _PREDICATES[key][1]


@dataclass
class Monitor:
    node: Node
    params: Any
    state: Any
    properties: tuple[Property, ...] = ()
    ops: Any = FLOAT
    traces: Traces | None = None
    """Where given, the node's step and the properties' predicates run as their traced programs
    (:meth:`Traces.call`)."""
    step_count: int = field(default=0, init=False)
    _active: dict[str, Any] = field(default_factory=dict, init=False, repr=False)
    _predicates: Callable[..., tuple] = field(init=False, repr=False)

    def __post_init__(self):
        for prop in self.properties:
            if prop.node.name != self.node.name:
                raise ValueError(f"property {prop.name} is about node {prop.node.name!r}, not {self.node.name!r}")
        if not _all(self.node.init(self.ops, self.params, self.state)):
            raise ValueError(f"node {self.node.name!r}: {self.state} is not an initial state")
        self._active = {p.name: True for p in self.properties}
        self._predicates = _predicates(self.properties)

    def applies(self, name: str) -> bool:
        """Property ``name``'s assumptions have held at every step so far (so it has been checked at each)."""
        return _all(self._active[name])

    def step(self, inputs):
        """Run one cycle; return the outputs, or raise :class:`PropertyViolation`."""
        o, p, s = self.ops, self.params, self.state
        nxt, out = run(self.traces, self.node.step, o, p, s, inputs)
        checked = run(self.traces, self._predicates, o, p, s, inputs, out, nxt)
        for prop, (assumed, holds) in zip(self.properties, checked, strict=True):
            active = o.and_(self._active[prop.name], assumed)
            self._active[prop.name] = active
            if not _all(o.implies(active, holds)):
                raise PropertyViolation(prop, self.step_count, s, inputs, out)
        self.state = nxt
        self.step_count += 1
        return out
