"""Prove one property: k-induction interleaved with BMC, lemmas first, one deadline.

For k = 0, 1, ..., max_k: the inductive step at depth k (proves the property if
BMC has cleared depths 0 .. k-1), then BMC at depth k (finds the shortest
counterexample). A counterexample is replayed exactly before it is reported.

Verdicts: ``proved`` (engine ``k-induction``, with k, and witnesses that it is not
vacuous, :mod:`atcs.proofs.engine.vacuity`), ``vacuous`` (proved, but its assumptions
admit no run or an implication's condition is never reached: it claims nothing),
``falsified`` (engine ``bmc``, with the depth and the trace), ``unknown``
(timeout, solver gave up, or no k <= max_k closes the induction) and ``error``
(the model or the property could not be built, or a counterexample did not
replay: never a pass).
"""

from __future__ import annotations

import time
import traceback
from dataclasses import dataclass
from enum import StrEnum
from pathlib import Path

from atcs.model import ops
from atcs.model.ops.symbolic import fresh_context
from atcs.proofs.cex.nominal import Nominal, nominalise
from atcs.proofs.cex.smoothing import Smoothing, smooth
from atcs.proofs.cex.trace import Replay, ReplayError, Trace, extract, reproduce
from atcs.proofs.engine.bmc import Bmc, Check
from atcs.proofs.engine.induction import Induction
from atcs.proofs.engine.system import Unrolling
from atcs.proofs.engine.vacuity import Witness, check_vacuity
from atcs.properties.property import Property


class Status(StrEnum):
    """A property's verdict (the module docstring says when each is given); equal to its lower-case name."""

    PROVED = "proved"
    VACUOUS = "vacuous"
    FALSIFIED = "falsified"
    UNKNOWN = "unknown"
    ERROR = "error"


@dataclass
class Result:
    """The verdict of one property and its evidence: depth, counterexample and its replay, witnesses."""

    name: str
    requirement: str
    status: Status
    engine: str
    k: int | None
    seconds: float
    message: str = ""
    trace: Trace | None = None
    replay: Replay | None = None
    witnesses: tuple[Witness, ...] = ()
    """For a proved property: runs showing its assumptions and each implication's condition reachable."""
    smoothing: Smoothing | None = None
    """For a counterexample asked to be smoothed (``smooth_cex=True``): the input changes before and after."""
    nominal: Nominal | None = None
    """For a counterexample asked to be near nominal (``nominal_cex=True``): its distance to nominal before and
    after."""
    parts: tuple[Result, ...] = ()
    """For a property proved in parts (:mod:`atcs.proofs.engine.split`): its halves' results."""

    def __post_init__(self):
        self.status = Status(self.status)


class _Timeout(Exception):
    pass


class _Deadline:
    def __init__(self, seconds: float):
        self.end = time.monotonic() + seconds

    def remaining(self) -> float:
        left = self.left()
        if left <= 0:
            raise _Timeout
        return left

    def left(self) -> float:
        """The time left, 0 when none (never raises)."""
        return max(self.end - time.monotonic(), 0.0)


def check_lemma(prop: Property, lemma: Property) -> None:
    """A lemma may be assumed only if it is about the same node under no more assumptions."""
    if lemma.node is not prop.node:
        raise ValueError(f"lemma {lemma.name} is about node {lemma.node.name!r}, not {prop.node.name!r}")
    extra = [a.name for a in lemma.assumptions if a not in prop.assumptions]
    if extra:
        raise ValueError(f"lemma {lemma.name} assumes {', '.join(extra)}, which {prop.name} does not assume")
    for key, value in lemma.fixed_params.items():
        if prop.fixed_params.get(key, object()) != value:
            raise ValueError(f"lemma {lemma.name} fixes parameter {key}={value!r}; {prop.name} must fix it too")


def prove(
    prop: Property,
    *,
    timeout_s: float = 60.0,
    lemmas: dict[str, Property] | None = None,
    max_k: int | None = None,
    proved: dict[str, Result] | None = None,
    smooth_cex: bool = False,
    nominal_cex: bool = False,
    _chain: tuple[str, ...] = (),
) -> Result:
    """Prove or falsify ``prop`` within ``timeout_s`` seconds (lemmas' proofs included).

    ``lemmas`` resolves the names in ``prop.lemmas`` (normally the property registry). ``proved``
    collects the lemma results of one run by name, so a lemma several properties share is proved once;
    share it only between properties of the same registry, never across a mutated model. With ``smooth_cex``
    a counterexample is smoothed (:mod:`atcs.proofs.cex.smoothing`), with ``nominal_cex`` made near nominal
    (:mod:`atcs.proofs.cex.nominal`), within the time left before it is replayed; not both.

    Each proof (each lemma's too) builds its terms in a fresh z3 context, so its verdict and time do not
    depend on what the process proved before.
    """
    if smooth_cex and nominal_cex:
        raise ValueError("a counterexample is either smoothed or made near nominal, not both")
    refine = "smooth" if smooth_cex else "nominal" if nominal_cex else None
    with fresh_context():
        return _prove(
            prop, timeout_s=timeout_s, lemmas=lemmas, max_k=max_k, proved=proved, refine=refine, _chain=_chain
        )


def bounded_check(
    prop: Property,
    *,
    depth: int,
    timeout_s: float = 60.0,
    lemmas: dict[str, Property] | None = None,
    proved: dict[str, Result] | None = None,
) -> Result:
    """BMC alone, depths 0 to ``depth``, lemmas assumed (proved first, as :func:`prove` does): ``falsified``
    with the counterexample replayed, or ``unknown`` (engine ``bmc``) saying no counterexample exists up to
    ``depth`` (a bounded check, not a proof). What finds a fault when the inductive step of a broken model is too
    hard for the solver: ``atcs mutate`` gives it the properties a mutant leaves unknown."""
    if isinstance(depth, bool) or not isinstance(depth, int) or depth < 0:
        raise ValueError(f"depth must be a whole number >= 0, got {depth!r}")
    with fresh_context():
        return _prove(
            prop,
            timeout_s=timeout_s,
            lemmas=lemmas,
            max_k=depth,
            proved=proved,
            refine=None,
            _chain=(),
            engine=_bmc_to_depth,
        )


def _prove(prop, *, timeout_s, lemmas, max_k, proved, refine, _chain, engine=None) -> Result:
    if timeout_s <= 0:
        raise ValueError(f"timeout_s must be positive, got {timeout_s!r}")
    start = time.monotonic()
    deadline = _Deadline(timeout_s)
    max_k = prop.max_k if max_k is None else max_k

    def result(
        status, engine="", k=None, message="", trace=None, replay=None, witnesses=(), smoothing=None, nominal=None
    ):
        return Result(
            prop.name,
            prop.requirement,
            status,
            engine,
            k,
            time.monotonic() - start,
            message,
            trace,
            replay,
            tuple(witnesses),
            smoothing,
            nominal,
        )

    try:
        assumed, failure = _assumed_lemmas(prop, lemmas, proved, deadline, refine, _chain)
        if failure is not None:
            return result(*failure)
        return (engine or _k_induction_with_bmc)(prop, Unrolling(prop, tuple(assumed)), max_k, deadline, refine, result)
    except _Timeout:
        return result("unknown", message=f"timeout after {timeout_s:g} s")
    except Exception as exc:  # the model or property could not be built: report, never pass
        return result("error", message=f"{type(exc).__name__}: {exc}{model_location(exc)}")


def _k_induction_with_bmc(prop, u, max_k, deadline, refine, result) -> Result:
    """The verdict of k-induction interleaved with BMC: for k = 0 .. ``max_k``, BMC at depth k then the inductive
    step at k, until one of them decides."""
    bmc, induction = Bmc(u), Induction(u)
    for k in range(max_k + 1):
        # the base case first: a counterexample at depth k is found even when the inductive step at k
        # is too hard for the solver (the step of a broken model is typically the harder check)
        decided = _base_case(prop, u, bmc, k, deadline, refine, result)
        if decided is not None:
            return decided
        step = induction.check(k, deadline.remaining())
        if step.result == "unsat":
            return _with_vacuity(u, k, deadline, result)
        if step.result == "unknown":
            return result("unknown", "k-induction", k, _unknown(step, "inductive step", k))
    return result(
        "unknown",
        "k-induction",
        max_k,
        f"not {max_k}-inductive and no counterexample up to depth {max_k}; an auxiliary lemma may make it inductive",
    )


def _bmc_to_depth(prop, u, depth, deadline, refine, result) -> Result:
    """BMC at depths 0 .. ``depth``: the first counterexample, else unknown with the depth cleared."""
    bmc = Bmc(u)
    for k in range(depth + 1):
        decided = _base_case(prop, u, bmc, k, deadline, refine, result)
        if decided is not None:
            return decided
    return result("unknown", "bmc", depth, f"no counterexample up to depth {depth} (a bounded check, not a proof)")


def _base_case(prop, u, bmc, k, deadline, refine, result) -> Result | None:
    """BMC at depth ``k``: the counterexample, unknown if the solver cannot tell, None if there is none."""
    base = bmc.check(k, deadline.remaining())
    if base.result == "sat":
        return _counterexample(prop, u, bmc, k, base.model, (refine, deadline), result)
    if base.result == "unknown":
        return result("unknown", "bmc", k, _unknown(base, "BMC", k))
    return None


def _assumed_lemmas(prop, lemmas, proved, deadline, refine, chain) -> tuple[list[Property], tuple | None]:
    """The lemmas ``prop`` rests on, each proved first (or taken from ``proved``); else the (status, engine, k,
    message) of the verdict: an error for a lemma cycle, an unknown lemma or a failed one, unknown if one is."""
    if prop.name in chain:
        return [], ("error", "", None, f"lemma cycle: {' -> '.join((*chain, prop.name))}")
    assumed = []
    for name in prop.lemmas:
        if lemmas is None or name not in lemmas:
            return [], ("error", "", None, f"lemma {name!r} is not a known property")
        lemma = lemmas[name]
        check_lemma(prop, lemma)
        sub = proved.get(name) if proved is not None else None
        if sub is None:
            sub = prove(
                lemma,
                timeout_s=deadline.remaining(),
                lemmas=lemmas,
                proved=proved,
                smooth_cex=refine == "smooth",
                nominal_cex=refine == "nominal",
                _chain=(*chain, prop.name),
            )
            if proved is not None:
                proved[name] = sub
        if sub.status not in ("proved", "vacuous"):  # a vacuous lemma still holds: assuming it is sound
            status = "error" if sub.status in ("falsified", "error") else "unknown"
            return [], (status, "", None, f"lemma {name} is {sub.status}: {sub.message}".rstrip(": "))
        assumed.append(lemma)
    return assumed, None


def _counterexample(prop, u, bmc, k, model, refinement, result) -> Result:
    """The base case failed at depth ``k``: the counterexample, refined as ``refinement`` (kind, deadline) asks
    (``smooth``, ``nominal`` or None) within the time left (never past it: the counterexample is kept either way),
    replayed exactly."""
    refine, deadline = refinement
    found = {"smoothing": None, "nominal": None}
    if refine == "smooth":
        model, found["smoothing"] = smooth(u, bmc.solver, k, model, deadline.left())
    elif refine == "nominal":
        model, found["nominal"] = nominalise(u, bmc.solver, k, model, deadline.left())
    trace = extract(u, model, k)
    try:
        replayed = reproduce(prop, trace)
    except ReplayError as exc:
        return result("error", "bmc", k, f"counterexample does not replay: {exc}", trace, **found)
    message = "; ".join([f"violated at step {k}", *(r.describe() for r in found.values() if r is not None)])
    return result("falsified", "bmc", k, message, trace, replayed, **found)


def _with_vacuity(u, k, deadline, result) -> Result:
    """The inductive step holds at ``k``: proved if the property is not vacuous, else vacuous or unknown."""
    vacuity = check_vacuity(u, timeout_s=deadline.remaining())
    if vacuity.status == "non-vacuous":
        return result("proved", "k-induction", k, witnesses=vacuity.witnesses)
    if vacuity.status == "vacuous":
        return result("vacuous", "k-induction", k, f"proved, but {vacuity.message}", witnesses=vacuity.witnesses)
    return result(
        "unknown", "k-induction", k, f"proved, but vacuity unknown: {vacuity.message}", witnesses=vacuity.witnesses
    )


_ENGINE_DIRS = (str(Path(__file__).parents[1]), str(Path(ops.__file__).parent))


def model_location(exc: Exception) -> str:
    """Where in the model or property code the exception arose (the innermost frame outside the engine)."""
    for frame in reversed(traceback.extract_tb(exc.__traceback__)):
        if not frame.filename.startswith(_ENGINE_DIRS):
            return f" (at {frame.filename}:{frame.lineno}: {frame.line})"
    return ""


def _unknown(check: Check, what: str, k: int) -> str:
    reason = check.reason or "unknown"
    if reason in ("timeout", "canceled"):
        return f"timeout in the {what} at depth {k}"
    return f"solver returned unknown in the {what} at depth {k}: {reason}"
