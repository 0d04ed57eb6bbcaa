"""Proof certificates: a proved property's k-inductive invariant as SMT-LIB 2 scripts, checked by z3
and by cvc5, independently of the engine that found the proof.

A proof by k-induction (:mod:`atcs.proofs.engine.prove`) gives the invariant ``(k, phi)`` with ``phi`` the property
itself, its lemmas assumed. Its certificate is three kinds of script, each of which must be unsat:

- ``base``: a run from an initial state of k + 1 steps (every transition taken, every assumption and lemma
  holding) on which the property fails at some step 0 .. k;
- ``step``: a path of k + 1 pairwise distinct states from any state, the property holding at steps 0 .. k-1
  and failing at step k (one script per case when the property splits its step, plus the states in no case:
  the split is ``Property.certificate_cases`` when the property has one, else the engine's ``Property.cases``);
- ``invariant``: a step where ``phi`` holds and the property does not.

When every state is initial (a stateless node) the base omits the initial condition (it is ``true``); at k = 0
the base and the step are then one formula, checked once by each solver (the second check records that).

Together they are the engine's argument: no run violates the property within k + 1 steps, and a shortest
violation longer than that would end in a simple path the step rules out. The scripts are standalone SMT-LIB
(``(set-logic ALL)``, declarations, assertions, ``(check-sat)``): any SMT solver can re-check them. Here each
is parsed afresh and checked by z3 and by cvc5. Both must say unsat for the property to be confirmed; a solver
that says sat contradicts the proof, which is an error, never a pass; an unknown leaves it unconfirmed.
"""

from __future__ import annotations

import hashlib
import time
from collections.abc import Mapping
from dataclasses import dataclass

import z3

from atcs.model.ops.symbolic import SYMBOLIC, context, fresh_context, unwrap
from atcs.proofs.engine.system import Unrolling
from atcs.properties.property import Property

SOLVERS = ("z3", "cvc5")
VERDICTS = ("unsat", "sat", "unknown")

CVC5_OPTIONS = {"incremental": "false"}
"""The options cvc5 checks every script with, set through its API before the script is read (docs/certificates.md).
A script has one ``(check-sat)``; cvc5's API solver is incremental by default, and without that mode it answers
the closed-loop step case, which it otherwise does not."""


@dataclass(frozen=True)
class Obligation:
    """One check of a certificate: an SMT-LIB script that must be unsat."""

    check: str
    """``base``, ``step`` (``step_case_1`` ... with a split step) or ``invariant``."""
    claim: str
    """What its being unsat shows, in one sentence."""
    script: str

    @property
    def sha256(self) -> str:
        return hashlib.sha256(self.script.encode()).hexdigest()

    @property
    def formula(self) -> str:
        """The script without its comments: two checks with the same formula have the same verdict (for k = 0
        on a node whose every state is initial, the base and the step are one formula)."""
        return "\n".join(line for line in self.script.splitlines() if not line.startswith(";"))


@dataclass(frozen=True)
class SolverCheck:
    solver: str
    check: str
    verdict: str
    """``unsat`` (confirmed), ``sat`` (contradicts the proof) or ``unknown`` (with the solver's reason)."""
    seconds: float
    reason: str = ""
    resource_units: int | None = None
    """cvc5's count of the resource units it spent (deterministic: the same on any machine), None for z3."""


def obligations(prop: Property, k: int, lemmas: Mapping[str, Property]) -> tuple[Obligation, ...]:
    """The certificate of ``prop`` proved by k-induction at depth ``k``, its lemmas (resolved in ``lemmas``)
    assumed at every step."""
    if not isinstance(k, int) or k < 0:
        raise ValueError(f"{prop.name}: k must be a non-negative whole number, got {k!r}")
    with fresh_context():
        u = Unrolling(prop, tuple(lemmas[name] for name in prop.lemmas))
        frames = [u.frame(j) for j in range(k + 1)]
        path = [z3.And(f.trans, f.assumed, f.lemmas) for f in frames]
        header = f"{prop.name} ({prop.requirement}), k = {k}"
        init = u.init()
        initial = [] if z3.is_true(z3.simplify(init)) else [init]  # a stateless node: every state is initial
        result = [
            Obligation(
                "base",
                f"no run from an initial state violates {prop.name} within {k + 1} steps",
                _script(header, "base", [*initial, *path, z3.Not(_all(f.prop for f in frames))]),
            )
        ]
        step = [*path, *(u.distinct(j, k) for j in range(k)), *(f.prop for f in frames[:k]), z3.Not(frames[k].prop)]
        claim = (
            f"{prop.name} holds after any {k} distinct steps on which it held"
            if k
            else f"{prop.name} holds in every state and input that meet its assumptions"
        )
        split = prop.certificate_cases or prop.cases
        if split is None:
            result.append(Obligation("step", claim, _script(header, "step", step)))
        else:
            cases = split(SYMBOLIC, u.params, u.state(max(k - 1, 0)))
            every = (*cases, SYMBOLIC.not_(SYMBOLIC.or_(*cases)))
            for j, case in enumerate(every, start=1):
                what = f"case {j} of {len(every)}" + (" (the states in no other case)" if j == len(every) else "")
                result.append(
                    Obligation(
                        f"step_case_{j}", f"{claim}: {what}", _script(header, f"step, {what}", [*step, unwrap(case)])
                    )
                )
        first = frames[0]
        result.append(
            Obligation(
                "invariant",
                f"the invariant (the property itself, k = {k}) implies {prop.name}",
                _script(
                    header, "invariant", [first.trans, first.assumed, first.lemmas, first.prop, z3.Not(first.prop)]
                ),
            )
        )
        return tuple(result)


def _all(terms) -> z3.BoolRef:
    terms = list(terms)
    return terms[0] if len(terms) == 1 else z3.And(*terms)


def _script(header: str, check: str, assertions: list) -> str:
    solver = z3.Solver(ctx=context())
    solver.add(*assertions)
    body = solver.to_smt2().replace("; benchmark generated from python API\n", "")
    return f"; atcs proof certificate: {header}\n; check: {check}; expected: unsat\n(set-logic ALL)\n{body}"


def check_obligation(
    solver: str, obligation: Obligation, timeout_s: float, resource_limit: int | None = None
) -> SolverCheck:
    """Parse the obligation's script afresh and check it with ``solver`` (``z3`` or ``cvc5``) within
    ``timeout_s`` seconds and, for cvc5, within ``resource_limit`` resource units (its ``rlimit-per``: a limit
    that gives the same verdict on any machine; None for none)."""
    if solver not in SOLVERS:
        raise ValueError(f"solver must be one of {', '.join(SOLVERS)}, got {solver!r}")
    if not timeout_s > 0:
        raise ValueError(f"timeout_s must be positive, got {timeout_s!r}")
    if resource_limit is not None and (
        solver != "cvc5"
        or isinstance(resource_limit, bool)
        or not isinstance(resource_limit, int)
        or resource_limit < 1
    ):
        raise ValueError(
            f"resource_limit must be a positive whole number of cvc5 resource units (cvc5 only), "
            f"got {resource_limit!r} for {solver}"
        )
    start = time.monotonic()
    if solver == "z3":
        verdict, reason, units = (*_z3(obligation.script, timeout_s), None)
    else:
        verdict, reason, units = _cvc5(obligation.script, timeout_s, resource_limit)
    return SolverCheck(solver, obligation.check, verdict, time.monotonic() - start, reason, units)


def _z3(script: str, timeout_s: float) -> tuple[str, str]:
    ctx = z3.Context()
    assertions = z3.parse_smt2_string(script, ctx=ctx)
    # the preprocessing the engine's solver uses (proofs/engine/bmc.py), on the parsed script
    solver = z3.Then("simplify", "propagate-values", "solve-eqs", "elim-term-ite", "smt", ctx=ctx).solver()
    solver.set("timeout", max(1, int(timeout_s * 1000)))
    solver.add(assertions)
    verdict = solver.check()
    if verdict == z3.unknown:
        return "unknown", solver.reason_unknown()
    return str(verdict), ""


def _cvc5(script: str, timeout_s: float, resource_limit: int | None) -> tuple[str, str, int]:
    import cvc5

    terms = cvc5.TermManager()
    solver = cvc5.Solver(terms)
    for option, value in CVC5_OPTIONS.items():
        solver.setOption(option, value)
    solver.setOption("tlimit-per", str(max(1, int(timeout_s * 1000))))
    if resource_limit is not None:
        solver.setOption("rlimit-per", str(resource_limit))
    symbols = cvc5.SymbolManager(terms)
    parser = cvc5.InputParser(solver, symbols)
    parser.setStringInput(cvc5.InputLanguage.SMT_LIB_2_6, script, "certificate")
    answers = []
    while True:
        command = parser.nextCommand()
        if command.isNull():
            break
        answers.append(command.invoke(solver, symbols).strip())
    units = solver.getStatistics().get(True, True)["resource::resourceUnitsUsed"]["value"]
    answer = answers[-1] if answers else ""
    verdict, _, reason = answer.partition(" ")  # e.g. "unknown (TIMEOUT)", "unknown (RESOURCEOUT)"
    if verdict not in VERDICTS:
        return "unknown", f"cvc5 answered {answer!r}", units
    return verdict, reason.strip("()").lower() if verdict == "unknown" else "", units
