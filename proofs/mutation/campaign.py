"""The mutation campaign of ``atcs mutate``: every mutant of the model against the proof suite.

For each mutant (:mod:`atcs.proofs.mutation.sites`) the properties of every node whose proofs run the mutated
function are proved about the mutated model, lemmas included (themselves proved about the mutant first),
cheapest nodes first; the first property killed ends the mutant's run. Each property first gets an equal share
of the mutant's time limit, so one slow proof does not starve the properties after it; those left unknown are
then given a bounded check (BMC alone to the property's ``max_k`` plus :data:`BOUNDED_DEPTH_BEYOND_K`, within
the same share: a fault the inductive step is too hard to show may be a short run away), and then tried again, in
the same order, with the time that is left. Verdicts (``VERDICTS``):

- ``killed``: a property is falsified, its counterexample replays on the mutant at the same step, and the real
  model does not violate it on those inputs (:attr:`atcs.proofs.mutation.mutants.MutantRun.killed`);
- ``survived``: every property proved (or vacuous) about the mutant;
- ``timeout``: no kill, and some property unknown (the per-mutant time limit, or the solver gave up);
- ``incompetent``: the mutant does not compile or its model cannot be built (counted apart);
- ``equivalent``: listed in the registry of equivalent mutants (:mod:`atcs.proofs.mutation.equivalents`), not run.

The kill rate of a module is killed / (killed + survived + timeout).
"""

from __future__ import annotations

import dataclasses
import fnmatch
import signal
import time
from collections.abc import Callable, Iterator
from concurrent.futures import as_completed
from contextlib import contextmanager
from dataclasses import dataclass, field
from functools import cache

from atcs.proofs.mutation.mutants import MutantRun, patched
from atcs.proofs.mutation.sites import Mutant, enumerate_mutants, node_functions
from atcs.proofs.workers import worker_pool
from atcs.properties.property import Property

VERDICTS = ("killed", "survived", "timeout", "incompetent", "equivalent")
COUNTED = ("killed", "survived", "timeout")
"""The verdicts the kill rate's denominator counts."""


@dataclass
class Check:
    """One property proved about a mutant."""

    property: str
    status: str
    seconds: float
    message: str = ""


@dataclass
class Outcome:
    """A mutant's verdict."""

    mutant: Mutant
    verdict: str
    seconds: float
    killed_by: str | None = None
    k: int | None = None
    message: str = ""
    checks: list[Check] = field(default_factory=list)
    run: MutantRun | None = None
    """The killing run (in the process that ran it; not sent back from a worker)."""

    def record(self) -> dict:
        m = self.mutant
        return {
            "id": m.id,
            "module": m.model_module,
            "function": m.function,
            "line": m.line,
            "operator": m.operator,
            "original": m.original,
            "replacement": m.replacement,
            "verdict": self.verdict,
            "killed_by": self.killed_by,
            "k": self.k,
            "seconds": round(self.seconds, 3),
            "message": self.message,
            "checks": [dataclasses.asdict(c) for c in self.checks],
            "diff": m.diff,
        }


def _registry() -> dict[str, Property]:
    from atcs.properties import PROPERTIES

    return PROPERTIES


@cache
def _functions_of(node_name: str) -> frozenset[tuple[str, str]]:
    node = next(p.node for p in _registry().values() if p.node.name == node_name)
    return frozenset((f.__module__, f.__name__) for f in node_functions(node))


def all_mutants() -> list[Mutant]:
    """Every mutant of the functions the registered properties' nodes run, in a fixed order."""
    nodes = {p.node.name: p.node for p in _registry().values()}
    return enumerate_mutants(nodes[name] for name in sorted(nodes))


def select_mutants(mutants: list[Mutant], pattern: str | None) -> list[Mutant]:
    """The mutants whose id matches the glob ``pattern`` (e.g. ``supervision.*``; all if None)."""
    return mutants if pattern is None else [m for m in mutants if fnmatch.fnmatchcase(m.id, pattern)]


def _lemmas_first(props: list[Property]) -> list[Property]:
    by_name = {p.name: p for p in props}
    ordered: dict[str, Property] = {}

    def visit(p):
        for name in p.lemmas:
            if name in by_name:
                visit(by_name[name])
        ordered.setdefault(p.name, p)

    for p in props:
        visit(p)
    return list(ordered.values())


def node_names() -> list[str]:
    """The nodes of the registered properties, by name."""
    return sorted({p.node.name for p in _registry().values()})


def node_cost(node_name: str) -> tuple[int, str]:
    """How dear a node's proofs are, by the number of the model's functions its step runs: a mutant meets the
    cheap proofs first (the sub-function nodes, then the larger ones, the closed loop and separation last)."""
    return len(_functions_of(node_name)), node_name


def affected_properties(mutant: Mutant, nodes: tuple[str, ...] | None = None) -> list[Property]:
    """The properties of every node (of ``nodes`` if given) whose proofs run the mutated function: cheap nodes
    first, lemmas first."""
    target = (f"atcs.model.{mutant.model_module}", mutant.function)
    props = [
        p
        for p in _registry().values()
        if target in _functions_of(p.node.name) and (nodes is None or p.node.name in nodes)
    ]
    props.sort(key=lambda p: node_cost(p.node.name))
    return _lemmas_first(props)


@contextmanager
def mutated(mutant: Mutant, props: list[Property]) -> Iterator[dict[str, Property]]:
    """Within the block the mutant replaces the real function everywhere; yields ``props`` about the mutated
    nodes, by name (a node whose own ``step`` or ``init`` is the function gets the mutant in its place)."""
    function = mutant.resolve()
    with patched(function, mutant.old, mutant.new) as fake:
        nodes = {}
        for p in props:
            if p.node.name not in nodes:
                swaps = {role: fake for role in ("step", "init") if getattr(p.node, role) is function}
                nodes[p.node.name] = dataclasses.replace(p.node, **swaps) if swaps else p.node
        yield {p.name: dataclasses.replace(p, node=nodes[p.node.name]) for p in props}


HANG_GRACE_S = 60
"""How long past its time limit a mutant may still run before it is stopped: the solver keeps to the limit, but
the mutant's own Python code may not return at all (``while len(profiles) > 1`` made ``>= 1``)."""


class _Hang(BaseException):
    """Raised by the alarm in a mutant that overran its time limit and grace (a BaseException, so that no
    ``except Exception`` on the way turns it into a verdict)."""


def run_mutant(mutant: Mutant, *, timeout_s: float, nodes: tuple[str, ...] | None = None) -> Outcome:
    """Prove the affected properties (of ``nodes`` only, if given) about ``mutant`` until one kills it, within
    ``timeout_s`` in all; a mutant still running :data:`HANG_GRACE_S` after that is stopped (``timeout``)."""
    if not timeout_s > 0:
        raise ValueError(f"timeout_s must be positive, got {timeout_s!r}")
    start = time.monotonic()
    checks: list[Check] = []

    def overran(signum, frame):
        raise _Hang

    limit = timeout_s + HANG_GRACE_S
    previous = signal.signal(signal.SIGALRM, overran)
    signal.setitimer(signal.ITIMER_REAL, limit)
    try:
        return _run_mutant(mutant, timeout_s, nodes, start, checks)
    except _Hang:
        return Outcome(
            mutant,
            "timeout",
            time.monotonic() - start,
            checks=checks,
            message=f"stopped {limit:g} s after it started: the mutant's own code did not return "
            "(a loop that never ends?)",
        )
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def _run_mutant(
    mutant: Mutant, timeout_s: float, nodes: tuple[str, ...] | None, start: float, checks: list[Check]
) -> Outcome:
    props = affected_properties(mutant, nodes)

    def outcome(verdict, **kw):
        return Outcome(mutant, verdict, time.monotonic() - start, checks=checks, **kw)

    run = _Proofs(mutant, props, timeout_s, start, checks, outcome)
    share = timeout_s / max(len(props), 1)
    ending = run.proof_pass(props, share)
    if ending is None:
        _forget_unknown_lemmas(run.proved)  # a lemma that ran out of its share is tried again with the time left
        ending = _bounded_checks(mutant, props, run, share)
        ending = ending and outcome(**ending)
    if ending is None:
        ending = run.proof_pass([p for p in props if p.name in run.unknown and p.name not in run.done], None)
    if ending is not None:
        return ending
    if run.unknown:
        return outcome("timeout", message="; ".join(run.unknown.values()))
    if not props:
        return outcome("incompetent", message="no selected node's proofs run this function")
    return outcome("survived", message=f"{len(props)} properties proved about the mutant")


@dataclass
class _Proofs:
    """One mutant's proofs: what each property said so far, and the time its limit leaves."""

    mutant: Mutant
    props: list[Property]
    timeout_s: float
    start: float
    checks: list[Check]
    outcome: Callable[..., Outcome]
    proved: dict = field(default_factory=dict)
    unknown: dict[str, str] = field(default_factory=dict)  # property -> why it did not kill (a second try may still)
    done: set[str] = field(default_factory=set)  # proved, vacuous, or falsified on the real model too

    def left(self) -> float:
        return self.timeout_s - (time.monotonic() - self.start)

    def proof_pass(self, props: list[Property], share: float | None) -> Outcome | None:
        """Prove ``props`` about the mutant, each within ``share`` (None: the time left): the outcome if one kills
        it or shows it incompetent, else None."""
        from atcs.proofs.engine.prove import prove

        for prop in props:
            left = self.left()
            if left <= 0:
                self.unknown[prop.name] = f"{prop.name}: not run, the mutant's {self.timeout_s:g} s were spent"
                _record(self.checks, Check(prop.name, "not run", 0.0))
                continue
            try:
                with mutated(self.mutant, self.props) as registry:
                    result = prove(
                        registry[prop.name],
                        timeout_s=left if share is None else min(left, share),
                        lemmas=registry,
                        proved=self.proved,
                    )
            except (SyntaxError, ValueError, TypeError, NameError) as exc:  # the mutant itself cannot be made
                return self.outcome("incompetent", message=f"{type(exc).__name__}: {exc}")
            _record(self.checks, Check(prop.name, result.status, round(result.seconds, 3), result.message))
            ending = _outcome_of_proof(prop, result, self.unknown, self.done, self.outcome)
            if ending is not None:
                return ending
        return None


BOUNDED_DEPTH_BEYOND_K = 4
"""How far past a property's own ``max_k`` the bounded check of a property a mutant leaves unknown looks."""


def _bounded_checks(mutant: Mutant, props: list[Property], run: _Proofs, share: float) -> dict | None:
    """BMC alone (:func:`~atcs.proofs.engine.prove.bounded_check`, to the property's ``max_k`` plus
    :data:`BOUNDED_DEPTH_BEYOND_K`) on each property the first pass left unknown, each within its share of the
    time left: the ``outcome`` arguments of a kill, else None (``unknown`` keeps the proofs' messages)."""
    from atcs.proofs.cex.trace import replay
    from atcs.proofs.engine.prove import bounded_check

    for prop in [p for p in props if p.name in run.unknown and p.name not in run.done]:
        budget = min(share, run.left())
        if budget <= 0:
            return None
        with mutated(mutant, props) as registry:
            result = bounded_check(
                registry[prop.name], depth=prop.max_k + BOUNDED_DEPTH_BEYOND_K, timeout_s=budget, lemmas=registry
            )
        if result.status == "falsified":
            killed = MutantRun(result, result.replay, replay(prop, result.trace))
            if killed.killed:
                message = f"{result.message} (a bounded check: the proof was unknown)"
                _record(run.checks, Check(prop.name, result.status, round(result.seconds, 3), message))
                return {"verdict": "killed", "killed_by": prop.name, "k": result.k, "message": message, "run": killed}
    return None


def _forget_unknown_lemmas(proved: dict) -> None:
    """Drop the unknown lemma results from ``proved``, so that those lemmas are proved again."""
    for name in [name for name, r in proved.items() if r.status == "unknown"]:
        del proved[name]


def _outcome_of_proof(prop: Property, result, unknown: dict[str, str], done: set[str], outcome) -> Outcome | None:
    """What one proof about the mutant says: the outcome if it kills the mutant or shows it incompetent, else None,
    with ``prop`` marked in ``done`` or ``unknown``."""
    from atcs.proofs.cex.trace import replay

    if result.status == "falsified":
        run = MutantRun(result, result.replay, replay(prop, result.trace))
        if run.killed:
            return outcome("killed", killed_by=prop.name, k=result.k, message=result.message, run=run)
        unknown[prop.name] = f"{prop.name}: falsified, but the real model also fails on those inputs"
        done.add(prop.name)
    elif result.status == "error" and not result.message.startswith("lemma "):
        return outcome("incompetent", message=f"{prop.name}: {result.message}")
    elif result.status in ("proved", "vacuous"):
        unknown.pop(prop.name, None)
        done.add(prop.name)
    else:
        unknown[prop.name] = f"{prop.name}: {result.status}: {result.message}".rstrip(": ")
    return None


def _record(checks: list[Check], check: Check) -> None:
    """Keep one check per property: its last try."""
    checks[:] = [c for c in checks if c.property != check.property]
    checks.append(check)


_worker_mutants: dict[str, Mutant] = {}


def _run_by_id(mutant_id: str, timeout_s: float, nodes: tuple[str, ...] | None) -> Outcome:
    if not _worker_mutants:
        _worker_mutants.update((m.id, m) for m in all_mutants())
    outcome = run_mutant(_worker_mutants[mutant_id], timeout_s=timeout_s, nodes=nodes)
    outcome.run = None  # traces stay in the worker; the record carries the verdict
    return outcome


def run(
    mutants: list[Mutant],
    *,
    timeout_s: float,
    jobs: int = 1,
    equivalent: dict[str, str] | None = None,
    nodes: tuple[str, ...] | None = None,
    on_done: Callable[[Outcome], None] = lambda o: None,
) -> list[Outcome]:
    """Every mutant's outcome, in the order of ``mutants`` (``equivalent``: id -> reason, not run; ``nodes``:
    only these nodes' properties are proved)."""
    if jobs < 1:
        raise ValueError(f"jobs must be at least 1, got {jobs!r}")
    equivalent = equivalent or {}
    outcomes: dict[str, Outcome] = {}
    for m in mutants:
        if m.id in equivalent:
            outcomes[m.id] = Outcome(m, "equivalent", 0.0, message=equivalent[m.id])
            on_done(outcomes[m.id])
    todo = [m for m in mutants if m.id not in outcomes]
    if jobs == 1:
        for m in todo:
            outcomes[m.id] = run_mutant(m, timeout_s=timeout_s, nodes=nodes)
            on_done(outcomes[m.id])
    else:
        with worker_pool(jobs) as pool:
            futures = {pool.submit(_run_by_id, m.id, timeout_s, nodes): m for m in todo}
            for future in as_completed(futures):
                o = future.result()
                outcomes[o.mutant.id] = o
                on_done(o)
    return [outcomes[m.id] for m in mutants]


def kill_rates(outcomes: list[Outcome]) -> dict[str, dict]:
    """Per model module (and ``all``): the count of each verdict and the kill rate (None when nothing counts)."""
    groups: dict[str, list[Outcome]] = {}
    for o in outcomes:
        groups.setdefault(o.mutant.model_module, []).append(o)
    groups["all"] = outcomes
    rates = {}
    for module, group in groups.items():
        counts = {v: sum(o.verdict == v for o in group) for v in VERDICTS}
        counted = sum(counts[v] for v in COUNTED)
        rates[module] = {**counts, "kill_rate": round(counts["killed"] / counted, 4) if counted else None}
    return rates
