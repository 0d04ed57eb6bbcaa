"""What each property's proof reaches: the model lines run, and the decisions taken, while its terms are built.

A property's terms are those the engine hands the solver (:class:`~atcs.proofs.engine.system.Unrolling`): its
node's ``init`` and one ``step`` under the symbolic Ops, its assumptions, its predicate and its lemmas'. They
are built under a trace function that records every line of a model function run
(:func:`~atcs.proofs.coverage.sites.model_modules`) and, for each ``SymbolicOps.ite``, ``and_`` or ``or_``
called, the model line that called it; the node's step once for all its properties (:func:`reach_node`).
The symbolic Ops take both branches of every ``ite``, so a line is
reached when a term of the property's comes out of it, whatever the branch.
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass

from atcs.model.ops.symbolic import SYMBOLIC, SymbolicOps, fresh_context
from atcs.proofs.coverage.sites import DECISION_KINDS, model_modules, statement_lines
from atcs.proofs.engine.system import Unrolling
from atcs.properties import PROPERTIES, Property


@dataclass(frozen=True)
class Reached:
    """What one property's terms reach: ``(module, line)`` and ``(module, line, kind)``."""

    property: str
    lines: frozenset[tuple[str, int]]
    decisions: frozenset[tuple[str, int, str]]


class _Tracer:
    """A trace function recording the model lines run and the model lines calling a symbolic decision."""

    def __init__(self):
        self.files = {str(path): module for module, path in model_modules().items()}
        self.decision_code = {getattr(SymbolicOps, kind).__code__: kind for kind in DECISION_KINDS}
        self.lines: set[tuple[str, int]] = set()
        self.decisions: set[tuple[str, int, str]] = set()

    def _local(self, frame, event, arg):
        if event == "line":
            self.lines.add((self.files[frame.f_code.co_filename], frame.f_lineno))
        return self._local

    def _call(self, frame, event, arg):
        code = frame.f_code
        kind = self.decision_code.get(code)
        if kind is not None:
            caller = frame.f_back
            module = self.files.get(caller.f_code.co_filename) if caller is not None else None
            if module is not None:
                self.decisions.add((module, caller.f_lineno, kind))
            return None
        return self._local if code.co_filename in self.files else None

    @contextmanager
    def tracing(self) -> Iterator[_Tracer]:
        """Record while open; what was recorded before is dropped."""
        self.lines, self.decisions = set(), set()
        previous = sys.gettrace()
        sys.settrace(self._call)
        try:
            yield self
        finally:
            sys.settrace(previous)

    def reached(self) -> tuple[frozenset, frozenset]:
        """The statements (by first line) and decisions recorded."""
        statements = {(m, statement_lines(m).get(line)) for m, line in self.lines}
        return frozenset(s for s in statements if s[1] is not None), frozenset(self.decisions)


def reach_node(properties: list[Property]) -> list[Reached]:
    """What each of ``properties`` (all about one node) reaches: the node's ``init`` and ``step`` are built once
    (the first property's unrolling: fixed parameters are symbolic constants too, so they take no other path) and
    count for each; then each property's assumptions, predicate and lemmas on that step."""
    tracer = _Tracer()
    with fresh_context():
        with tracer.tracing():
            unrolling = Unrolling(properties[0])
            unrolling.init()
            frame = unrolling.frame(0)
        step_lines, step_decisions = tracer.reached()
        o, p = SYMBOLIC, unrolling.params
        s, i, out, nxt = frame.state, frame.inputs, frame.outputs, frame.next_state
        found = []
        for prop in properties:
            with tracer.tracing():
                prop.assumed(o, p, s, i)
                prop.holds(o, p, s, i, out, nxt)
                for lemma in prop.lemmas:
                    PROPERTIES[lemma].holds(o, p, s, i, out, nxt)
            lines, decisions = tracer.reached()
            found.append(Reached(prop.name, step_lines | lines, step_decisions | decisions))
    return found


def reach_all(properties: Iterable[Property], progress: Callable[[str], None] = lambda name: None) -> list[Reached]:
    """What each property reaches, in the order given (:func:`reach_node` per node)."""
    by_node: dict[str, list[Property]] = {}
    for prop in properties:
        by_node.setdefault(prop.node.name, []).append(prop)
    found = {}
    for group in by_node.values():
        for reached in reach_node(group):
            found[reached.property] = reached
            progress(reached.property)
    return [found[prop.name] for prop in properties]


__all__ = ["Reached", "reach_all", "reach_node"]
