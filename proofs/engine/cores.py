"""Inductive validity cores: what a k-induction proof needs of the model, its assumptions and its lemmas.

As Kind 2 and JKind give them (Ghassabani, Gacek and Whalen, 2016): for a property proved by k-induction at depth
k, a minimal set of its parts such that the proof still goes through with the others dropped. The parts
(:attr:`~atcs.proofs.engine.system.Frame.parts`) are the node's state equations (``equation <field>``: the next
value of one state field is what the step computes), the property's assumptions (``assumption <name>``) and its
lemmas (``lemma <name>``), each taken or dropped at every step at once. The proof is the same checks as the
engine's: BMC at depths 0 .. k-1 from an initial state, and the inductive step at depth k (simple paths, the
property's case split), each unsatisfiable.

Deletion-based: every part is tried in turn, and dropped if every check stays unsatisfiable without it. A check
that comes back ``unknown`` keeps the part and makes the core not minimal (``minimal`` false): the core is then
still sufficient, since every part it leaves out was shown unneeded. A state equation never in the core means the
proof holds whatever the step does to that field.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import z3

from atcs.model.ops.symbolic import SYMBOLIC, fresh_context, unwrap
from atcs.proofs.engine.bmc import new_solver
from atcs.proofs.engine.system import Unrolling
from atcs.properties.property import Property


@dataclass(frozen=True)
class ValidityCore:
    """The parts a proof needs (in the order :attr:`Frame.parts` lists them) and those it does not."""

    needs: tuple[str, ...]
    unneeded: tuple[str, ...]
    minimal: bool
    """Every part in ``needs`` was shown needed (no check came back ``unknown``)."""
    seconds: float

    def record(self) -> dict:
        return {"needs": list(self.needs), "unneeded": list(self.unneeded), "minimal": self.minimal}


class _Checks:
    """The proof's checks with a chosen set of parts."""

    def __init__(self, prop: Property, lemmas: tuple[Property, ...], k: int):
        self.u, self.k = Unrolling(prop, lemmas), k
        self.parts = list(self.u.frame(k).parts)

    def _path(self, solver: z3.Solver, keep: set[str], depth: int) -> None:
        for j in range(depth + 1):
            frame = self.u.frame(j)
            solver.add(*(term for name, term in frame.parts.items() if name in keep))
            if j < depth:
                solver.add(frame.prop)

    def queries(self, keep: set[str]):
        """Each check as a solver with its formula, to be unsatisfiable."""
        for depth in range(self.k):  # the base case
            solver = new_solver()
            solver.add(self.u.init())
            self._path(solver, keep, depth)
            solver.add(z3.Not(self.u.frame(depth).prop))
            yield solver
        cases = (None,)
        if self.u.prop.cases is not None:
            given = self.u.prop.cases(SYMBOLIC, self.u.params, self.u.state(max(self.k - 1, 0)))
            cases = (*given, SYMBOLIC.not_(SYMBOLIC.or_(*given)))
        for case in cases:  # the inductive step
            solver = new_solver()
            self._path(solver, keep, self.k)
            solver.add(*(self.u.distinct(a, b) for b in range(1, self.k + 1) for a in range(b)))
            solver.add(z3.Not(self.u.frame(self.k).prop))
            if case is not None:
                solver.add(unwrap(case))
            yield solver

    def verdict(self, keep: set[str], deadline: float) -> str:
        """``unsat`` if every check is, else ``sat`` or ``unknown`` (the first that is not)."""
        for solver in self.queries(keep):
            solver.set("timeout", max(1, int((deadline - time.monotonic()) * 1000)))
            result = solver.check()
            if result != z3.unsat:
                return str(result)
        return "unsat"


def validity_core(prop: Property, lemmas: tuple[Property, ...], k: int, timeout_s: float) -> ValidityCore:
    """The validity core of ``prop`` proved at depth ``k`` with ``lemmas`` (module docstring); ``timeout_s`` for
    every check together. Raises ``ValueError`` if a check with every part is satisfiable (the property is not
    proved at ``k``); if one comes back unknown, every part is kept (the engine's proof used them all: sufficient,
    not minimal)."""
    start = time.monotonic()
    deadline = start + timeout_s
    with fresh_context():
        checks = _Checks(prop, lemmas, k)
        keep = set(checks.parts)
        whole = checks.verdict(keep, deadline)
        if whole == "sat":
            raise ValueError(f"{prop.name} is not proved at depth {k} with all its parts: no validity core")
        minimal = whole == "unsat"
        for part in checks.parts if minimal else ():
            if time.monotonic() >= deadline:
                minimal = False
                break
            verdict = checks.verdict(keep - {part}, deadline)
            if verdict == "unsat":
                keep.discard(part)
            elif verdict == "unknown":
                minimal = False
    needs = tuple(p for p in checks.parts if p in keep)
    unneeded = tuple(p for p in checks.parts if p not in keep)
    return ValidityCore(needs, unneeded, minimal, time.monotonic() - start)


__all__ = ["ValidityCore", "validity_core"]
