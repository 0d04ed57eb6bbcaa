"""The inductive step of k-induction, with simple-path constraints.

Step case at depth k: a path of k + 1 pairwise distinct states, from *any* state
(no ``init``), where every transition is taken, every assumption and lemma
holds, the property holds at steps 0 .. k-1 and fails at step k. If that is
unsatisfiable and BMC found no violation at depths 0 .. k-1, the property holds
at every step of every run (k = 0 means it holds in every state and input that
meets the assumptions).

A property may split the step case by the last state before step k
(``Property.cases``): each case is checked by its own solver call, and one more
call covers the states in none of the cases, so the split never loses a state.

Why the simple-path constraint is sound: a shortest run to a violation never
visits a state twice (cutting the loop would give a shorter one), so its last
k + 1 states are distinct.
"""

from __future__ import annotations

import time

import z3

from atcs.model.ops.symbolic import SYMBOLIC, unwrap
from atcs.proofs.engine.bmc import Check, new_solver, solve
from atcs.proofs.engine.system import Unrolling


class Induction:
    def __init__(self, unrolling: Unrolling):
        self.u = unrolling
        self.solver = new_solver()
        self.depth = -1

    def check(self, k: int, timeout_s: float) -> Check:
        """Is there a counterexample to induction at depth ``k``? Call with k = 0, 1, 2, ..."""
        if k != self.depth + 1:
            raise ValueError(f"induction depths must be checked in order: expected {self.depth + 1}, got {k}")
        if k > 0:
            self.solver.add(self.u.frame(k - 1).prop)
        f = self.u.frame(k)
        self.solver.add(f.trans, f.assumed, f.lemmas)
        for j in range(k):
            self.solver.add(self.u.distinct(j, k))
        self.depth = k
        if self.u.prop.cases is None:
            return solve(self.solver, z3.Not(f.prop), timeout_s)
        end = time.monotonic() + timeout_s
        before = self.u.state(max(k - 1, 0))
        cases = self.u.prop.cases(SYMBOLIC, self.u.params, before)
        for case in (*cases, SYMBOLIC.not_(SYMBOLIC.or_(*cases))):
            check = solve(self.solver, z3.And(z3.Not(f.prop), unwrap(case)), max(end - time.monotonic(), 0.001))
            if check.result != "unsat":
                return check
        return Check("unsat")
