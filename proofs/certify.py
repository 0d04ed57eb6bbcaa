"""``atcs certify``: write the certificate of every proved property and check it with z3 and cvc5 (issue 9).

The depth ``k`` of each proof comes from a run of the prover (or a prove report, ``--report``). A property is
``confirmed`` by a solver when that solver finds every check of its certificate unsat, and ``certified`` when
both solvers confirm it and every lemma it assumes is certified. A ``sat`` from either solver is a
``disagreement``: an error. An ``unknown`` leaves the property ``unconfirmed``.
"""

from __future__ import annotations

import json
import multiprocessing
from collections.abc import Callable, Iterator, Mapping
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path

from atcs.proofs.certificate import SOLVERS, Obligation, SolverCheck, check_obligation, obligations
from atcs.properties import PROPERTIES, Property

STATUSES = ("certified", "unconfirmed", "disagreement", "error")


class ProveReportError(ValueError):
    """A prove report that cannot give the depths; the message names the file, the field and the value."""


@dataclass
class Certified:
    name: str
    requirement: str
    k: int
    lemmas: tuple[str, ...]
    obligations: tuple[Obligation, ...]
    checks: tuple[SolverCheck, ...]
    status: str = ""
    message: str = ""

    @property
    def confirmed_by(self) -> tuple[str, ...]:
        """The solvers that found every check unsat."""
        return tuple(s for s in SOLVERS if all(c.verdict == "unsat" for c in self.checks if c.solver == s))

    def own_status(self) -> str:
        """The verdict on this certificate alone (lemmas aside)."""
        if any(c.verdict == "sat" for c in self.checks):
            return "disagreement"
        return "certified" if self.confirmed_by == SOLVERS else "unconfirmed"


def solver_versions() -> dict[str, str]:
    import cvc5
    import z3

    return {"z3": z3.get_version_string(), "cvc5": getattr(cvc5, "__version__", "unknown")}


def depths_from_report(path: str | Path) -> dict[str, int]:
    """The depth of each proved property in a prove report (``atcs prove --json``)."""
    try:
        doc = json.loads(Path(path).read_text())
    except OSError as exc:
        raise ProveReportError(f"{path}: cannot read the prove report: {exc.strerror}") from None
    except json.JSONDecodeError as exc:
        raise ProveReportError(f"{path}: not a JSON prove report: {exc}") from None
    records = doc.get("properties") if isinstance(doc, dict) else None
    if not isinstance(records, list):
        raise ProveReportError(f"{path}: properties is missing or not a list (is it an atcs prove --json report?)")
    depths = {}
    for j, record in enumerate(records):
        name, status, k = (record.get(key) for key in ("name", "status", "k")) if isinstance(record, dict) \
            else (None, None, None)
        if not isinstance(name, str) or name not in PROPERTIES:
            raise ProveReportError(f"{path}: properties[{j}].name = {name!r} is not a registered property")
        if status == "proved":
            if not isinstance(k, int) or isinstance(k, bool) or k < 0:
                raise ProveReportError(f"{path}: properties[{j}].k = {k!r} (of {name}) is not a depth")
            depths[name] = k
    return depths


def certify_one(name: str, k: int, timeout_s: float) -> Certified:
    """The certificate of one registered property proved at depth ``k``, checked by every solver."""
    prop = PROPERTIES[name]
    try:
        obs = obligations(prop, k, PROPERTIES)
    except Exception as exc:  # the model could not be built: an error, never a pass
        return Certified(name, prop.requirement, k, prop.lemmas, (), (), "error", f"{type(exc).__name__}: {exc}")
    checks = tuple(check_obligation(solver, ob, timeout_s) for ob in obs for solver in SOLVERS)
    return Certified(name, prop.requirement, k, prop.lemmas, obs, checks)


def run(props: list[Property], depths: Mapping[str, int], *, timeout_s: float, jobs: int = 1,
        on_start: Callable[[Property], None] = lambda p: None) -> Iterator[Certified]:
    """Yield the certificate of each property in ``depths``, checked, in completion order."""
    if jobs < 1:
        raise ValueError(f"jobs must be at least 1, got {jobs!r}")
    todo = [p for p in props if p.name in depths]
    if jobs == 1 or len(todo) <= 1:
        for prop in todo:
            on_start(prop)
            yield certify_one(prop.name, depths[prop.name], timeout_s)
        return
    with ProcessPoolExecutor(max_workers=jobs, mp_context=multiprocessing.get_context("spawn")) as pool:
        futures = []
        for prop in todo:
            on_start(prop)
            futures.append(pool.submit(certify_one, prop.name, depths[prop.name], timeout_s))
        for future in as_completed(futures):
            yield future.result()


def settle(results: Mapping[str, Certified], depths: Mapping[str, int]) -> None:
    """Give each certificate its status, a property being certified only if its lemmas are."""
    def status(name: str, chain: tuple[str, ...] = ()) -> str:
        c = results[name]
        if c.status:
            return c.status
        own = c.own_status()
        if own != "certified":
            c.status, c.message = own, _message(c)
            return own
        for lemma in c.lemmas:
            if lemma not in results or lemma in chain:
                c.status, c.message = "unconfirmed", f"lemma {lemma} has no certificate" + (
                    "" if lemma in depths else " (it was not proved)")
                return c.status
            if status(lemma, (*chain, name)) != "certified":
                c.status, c.message = "unconfirmed", f"lemma {lemma} is {results[lemma].status}"
                return c.status
        c.status = "certified"
        return c.status

    for name in results:
        status(name)


def _message(c: Certified) -> str:
    bad = [ch for ch in c.checks if ch.verdict != "unsat"]
    return "; ".join(f"{ch.solver} says {ch.verdict} on {ch.check}" + (f" ({ch.reason})" if ch.reason else "")
                     for ch in bad)


def record(c: Certified, directory: Path | None) -> dict:
    """A certificate's JSON record (its scripts' files relative to ``directory``)."""
    return {
        "name": c.name, "requirement": c.requirement, "k": c.k, "lemmas": list(c.lemmas), "status": c.status,
        "confirmed_by": list(c.confirmed_by), "message": c.message,
        "checks": [{"check": ob.check, "claim": ob.claim, "file": f"{c.name}/{ob.check}.smt2" if directory else None,
                    "sha256": ob.sha256,
                    **{ch.solver: {"verdict": ch.verdict, "seconds": round(ch.seconds, 3), "reason": ch.reason}
                       for ch in c.checks if ch.check == ob.check}}
                   for ob in c.obligations],
    }
