"""``atcs certify``: write the certificate of every proved property and check it with z3 and cvc5.

The depth ``k`` of each proof comes from a run of the prover (or a prove report, ``--report``). A property is
``confirmed`` by a solver when that solver finds every check of its certificate unsat, and ``certified`` when
both solvers confirm it and every lemma it assumes is certified. A ``sat`` from either solver is a
``disagreement``: an error. An ``unknown`` leaves the property ``unconfirmed``; that solver then has no say on
the property's later checks (recorded as ``unknown``, "not checked"), so a time-out costs one time limit per
property, not one per check. Each solver has its own per-check time limit.
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Iterator, Mapping
from concurrent.futures import as_completed
from dataclasses import dataclass
from enum import StrEnum
from pathlib import Path

from atcs.model.data_files import read_json
from atcs.model.errors import AtcsInputError
from atcs.proofs.certify.obligations import SOLVERS, Obligation, SolverCheck, check_obligation, obligations
from atcs.proofs.engine.prove import Status
from atcs.proofs.workers import worker_pool
from atcs.properties import PROPERTIES, Property


class CertificateStatus(StrEnum):
    """A certificate's verdict (the module docstring says when each is given); equal to its lower-case name."""

    CERTIFIED = "certified"
    UNCONFIRMED = "unconfirmed"
    DISAGREEMENT = "disagreement"
    ERROR = "error"
    NOT_PROVED = "not proved"
    """The property has no proof to certify."""


class ProveReportError(AtcsInputError):
    """A prove report that cannot give the depths; the message names the file, the field and the value."""


class ListingError(AtcsInputError):
    """A certificates listing (``--reuse``) that cannot be read; the message names the file, the field and the
    value."""


REUSED = "reused: cvc5 found this very script unsat in {source}"
"""The reason of a cvc5 verdict taken from an earlier run's listing (:func:`cvc5_unsat_scripts`)."""


@dataclass
class Certified:
    name: str
    requirement: str
    k: int
    lemmas: tuple[str, ...]
    obligations: tuple[Obligation, ...]
    checks: tuple[SolverCheck, ...]
    status: CertificateStatus | None = None
    message: str = ""

    @property
    def confirmed_by(self) -> tuple[str, ...]:
        """The solvers that found every check unsat."""
        return tuple(s for s in SOLVERS if all(c.verdict == "unsat" for c in self.checks if c.solver == s))

    def own_status(self) -> CertificateStatus:
        """The verdict on this certificate alone (lemmas aside)."""
        if any(c.verdict == "sat" for c in self.checks):
            return CertificateStatus.DISAGREEMENT
        return CertificateStatus.CERTIFIED if self.confirmed_by == SOLVERS else CertificateStatus.UNCONFIRMED


def solver_versions() -> dict[str, str]:
    import cvc5
    import z3

    return {"z3": z3.get_version_string(), "cvc5": getattr(cvc5, "__version__", "unknown")}


_registry_in_this_worker: Mapping[str, Property] = PROPERTIES
"""The properties a worker process certifies by name: the registered ones, and a configuration's."""


def _use_configuration(path: str) -> None:
    """A worker's setup for ``atcs certify --config``: the configuration's properties beside the registered ones."""
    global _registry_in_this_worker
    from atcs.proofs.engine.suite import configured_registry

    _registry_in_this_worker = configured_registry(path)


STATUSES = tuple(s.value for s in Status)
"""The verdicts a prove report records."""


def depths_from_report(path: str | Path, registry: Mapping[str, Property] = PROPERTIES) -> dict[str, int]:
    """The depth of each property proved in a prove report (``atcs prove --json``), parts included (a property
    proved in parts has none of its own); its names must be in ``registry``."""
    doc = read_json(path, ProveReportError, "the prove report")
    records = doc.get("properties") if isinstance(doc, dict) else None
    if not isinstance(records, list):
        raise ProveReportError(f"{path}: properties is missing or not a list (is it an atcs prove --json report?)")
    depths = {}
    for j, record in enumerate(records):
        name, status, k = (
            (record.get(key) for key in ("name", "status", "k")) if isinstance(record, dict) else (None, None, None)
        )
        if not isinstance(name, str) or name not in registry:
            raise ProveReportError(f"{path}: properties[{j}].name = {name!r} is not a registered property")
        if status not in STATUSES:
            raise ProveReportError(
                f"{path}: properties[{j}].status = {status!r} (of {name}) is not a verdict ({', '.join(STATUSES)})"
            )
        if status == "proved" and not record.get("parts"):  # one proved in parts has its parts' records
            deepest = registry[name].max_k
            if not isinstance(k, int) or isinstance(k, bool) or not 0 <= k <= deepest:
                raise ProveReportError(
                    f"{path}: properties[{j}].k = {k!r} (of {name}) is not a depth from 0 to its max_k, {deepest}"
                )
            depths[name] = k
    return depths


def cvc5_unsat_scripts(path: str | Path) -> tuple[dict[str, int | None], str]:
    """The scripts an earlier ``atcs certify`` listing (its ``certificates.json``) records cvc5 finding unsat, by
    their SHA-256, with the resource units cvc5 used; none if that run's cvc5 is not this one (a verdict is kept
    only for the same script and the same solver). Also what to say about it: how many were found, or why none."""
    doc = read_json(path, ListingError, "the certificates listing")
    records = doc.get("properties") if isinstance(doc, dict) else None
    if not isinstance(records, list):
        raise ListingError(f"{path}: properties is missing or not a list (is it an atcs certify certificates.json?)")
    versions = doc.get("solver_versions")
    version = versions.get("cvc5") if isinstance(versions, dict) else None
    if not isinstance(version, str):
        raise ListingError(f"{path}: solver_versions.cvc5 must be a version string, got {version!r}")
    scripts: dict[str, int | None] = {}
    for j, record in enumerate(records):
        checks = record.get("checks") if isinstance(record, dict) else None
        if not isinstance(checks, list):
            raise ListingError(f"{path}: properties[{j}].checks must be a list, got {checks!r}")
        for m, check in enumerate(checks):
            where = f"properties[{j}].checks[{m}]"
            digest = check.get("sha256") if isinstance(check, dict) else None
            if not isinstance(digest, str) or len(digest) != 64:
                raise ListingError(f"{path}: {where}.sha256 must be a SHA-256 in hex, got {digest!r}")
            cvc5 = check.get("cvc5")
            if not isinstance(cvc5, dict) or cvc5.get("verdict") not in ("sat", "unsat", "unknown"):
                raise ListingError(f"{path}: {where}.cvc5 must hold cvc5's verdict, got {cvc5!r}")
            units = cvc5.get("resource_units")
            if cvc5["verdict"] == "unsat":
                scripts[digest] = units if isinstance(units, int) and not isinstance(units, bool) else None
    ours = solver_versions()["cvc5"]
    if version != ours:
        return {}, f"none of its verdicts reused: they are cvc5 {version}'s, this is cvc5 {ours}"
    return scripts, f"{len(scripts)} scripts cvc5 {ours} found unsat"


def solver_timeouts(timeout_s: float | Mapping[str, float]) -> dict[str, float]:
    """Each solver's per-check time limit: one number for both, or one per solver (every solver named)."""
    limits = dict(timeout_s) if isinstance(timeout_s, Mapping) else {s: timeout_s for s in SOLVERS}
    if set(limits) != set(SOLVERS):
        raise ValueError(f"timeout_s must give a limit for each of {', '.join(SOLVERS)}, got {sorted(limits)!r}")
    for solver, limit in limits.items():
        if isinstance(limit, bool) or not isinstance(limit, (int, float)) or not limit > 0:
            raise ValueError(f"timeout_s[{solver!r}] must be a positive number of seconds, got {limit!r}")
    return limits


def certify_one(
    name: str,
    k: int,
    timeout_s: float | Mapping[str, float],
    cvc5_resource_limit: int | None = None,
    z3_only: bool = False,
    registry: Mapping[str, Property] | None = None,
    cvc5_unsat: Mapping[str, int | None] | None = None,
    reused_from: str = "",
) -> Certified:
    """The certificate of one registered property proved at depth ``k``, checked by every solver within its
    per-check time limit (:func:`solver_timeouts`), cvc5 also within ``cvc5_resource_limit`` units a check;
    with ``z3_only`` cvc5 is not asked (its checks say so, and the property stays unconfirmed). A script whose
    SHA-256 is in ``cvc5_unsat`` (:func:`cvc5_unsat_scripts` of the listing ``reused_from``) is not given to cvc5
    again: its verdict is that listing's, said so in the check's reason; z3 checks every script."""
    limits = solver_timeouts(timeout_s)
    registry = _registry_in_this_worker if registry is None else registry
    prop = registry[name]
    try:
        obs = obligations(prop, k, registry)
    except Exception as exc:  # the model could not be built: an error, never a pass
        return Certified(name, prop.requirement, k, prop.lemmas, (), (), "error", f"{type(exc).__name__}: {exc}")
    checks = []
    gave_up = {"cvc5": "cvc5 was not asked (--z3-only)"} if z3_only else {}
    done: dict[tuple[str, str], SolverCheck] = {}  # (solver, formula) -> its check
    for ob in obs:
        for solver in SOLVERS:
            if solver in gave_up:  # that solver cannot confirm this property any more: say so, do not wait again
                checks.append(SolverCheck(solver, ob.check, "unknown", 0.0, f"not checked: {gave_up[solver]}"))
                continue
            same = done.get((solver, ob.formula))
            if same is not None:  # the same formula: the same verdict, not checked twice
                checks.append(
                    SolverCheck(
                        solver, ob.check, same.verdict, 0.0, f"the formula of {same.check}", same.resource_units
                    )
                )
                continue
            if solver == "cvc5" and cvc5_unsat and ob.sha256 in cvc5_unsat:
                check = SolverCheck(
                    solver, ob.check, "unsat", 0.0, REUSED.format(source=reused_from), cvc5_unsat[ob.sha256]
                )
            else:
                check = check_obligation(solver, ob, limits[solver], cvc5_resource_limit if solver == "cvc5" else None)
            done[(solver, ob.formula)] = check
            checks.append(check)
            if check.verdict == "unknown":
                gave_up[solver] = f"{solver} said unknown on {ob.check}"
    return Certified(name, prop.requirement, k, prop.lemmas, obs, tuple(checks))


def run(
    props: list[Property],
    depths: Mapping[str, int],
    *,
    timeout_s: float | Mapping[str, float],
    jobs: int = 1,
    cvc5_resource_limit: int | None = None,
    z3_only: Collection[str] = (),
    on_start: Callable[[Property], None] = lambda p: None,
    configuration: str | None = None,
    reuse: str | Path | None = None,
) -> Iterator[Certified]:
    """Yield the certificate of each property in ``depths`` (registered, or of the ``configuration`` file),
    checked, in completion order (``timeout_s``: one per-check limit for both solvers, or one per solver;
    ``z3_only``: the properties cvc5 is not asked about; ``reuse``: an earlier run's listing, whose cvc5 verdicts
    on the very same scripts are taken, :func:`certify_one`)."""
    from atcs.proofs.engine.suite import configured_registry

    timeout_s = solver_timeouts(timeout_s)
    if jobs < 1:
        raise ValueError(f"jobs must be at least 1, got {jobs!r}")
    todo = [p for p in props if p.name in depths]
    cvc5_unsat = cvc5_unsat_scripts(reuse)[0] if reuse is not None else {}
    reused = {"cvc5_unsat": cvc5_unsat, "reused_from": str(reuse)} if cvc5_unsat else {}
    if jobs == 1 or len(todo) <= 1:
        registry = configured_registry(configuration)
        for prop in todo:
            on_start(prop)
            yield certify_one(
                prop.name, depths[prop.name], timeout_s, cvc5_resource_limit, prop.name in z3_only, registry, **reused
            )
        return
    setup = (_use_configuration, (configuration,)) if configuration is not None else (None, ())
    with worker_pool(jobs, *setup) as pool:
        futures = []
        for prop in todo:
            on_start(prop)
            futures.append(
                pool.submit(
                    certify_one,
                    prop.name,
                    depths[prop.name],
                    timeout_s,
                    cvc5_resource_limit,
                    prop.name in z3_only,
                    **reused,
                )
            )
        for future in as_completed(futures):
            yield future.result()


def settle(results: Mapping[str, Certified], depths: Mapping[str, int]) -> None:
    """Give each certificate its status, a property being certified only if its lemmas are."""

    def status(name: str, chain: tuple[str, ...] = ()) -> str:
        c = results[name]
        if c.status:
            return c.status
        own = c.own_status()
        if own != CertificateStatus.CERTIFIED:
            c.status, c.message = own, _message(c)
            return own
        for lemma in c.lemmas:
            if lemma not in results or lemma in chain:
                c.status, c.message = (
                    CertificateStatus.UNCONFIRMED,
                    f"lemma {lemma} has no certificate" + ("" if lemma in depths else " (it was not proved)"),
                )
                return c.status
            if status(lemma, (*chain, name)) != CertificateStatus.CERTIFIED:
                c.status, c.message = CertificateStatus.UNCONFIRMED, f"lemma {lemma} is {results[lemma].status}"
                return c.status
        c.status = CertificateStatus.CERTIFIED
        return c.status

    for name in results:
        status(name)


def _message(c: Certified) -> str:
    bad = [ch for ch in c.checks if ch.verdict != "unsat"]
    said = [ch for ch in bad if not ch.reason.startswith("not checked: ")]
    skipped: dict[str, int] = {}
    for ch in bad:
        if ch not in said:
            skipped[ch.reason] = skipped.get(ch.reason, 0) + 1
    return "; ".join(
        [
            *(f"{ch.solver} says {ch.verdict} on {ch.check}" + (f" ({ch.reason})" if ch.reason else "") for ch in said),
            *(f"{n} {'check' if n == 1 else 'checks'} {why}" for why, n in skipped.items()),
        ]
    )


def record(c: Certified, directory: Path | None) -> dict:
    """A certificate's JSON record (its scripts' files relative to ``directory``)."""
    return {
        "name": c.name,
        "requirement": c.requirement,
        "k": c.k,
        "lemmas": list(c.lemmas),
        "status": c.status,
        "confirmed_by": list(c.confirmed_by),
        "message": c.message,
        "checks": [
            {
                "check": ob.check,
                "claim": ob.claim,
                "file": f"{c.name}/{ob.check}.smt2" if directory else None,
                "sha256": ob.sha256,
                **{
                    ch.solver: {
                        "verdict": ch.verdict,
                        "seconds": round(ch.seconds, 3),
                        "reason": ch.reason,
                        **({} if ch.resource_units is None else {"resource_units": ch.resource_units}),
                    }
                    for ch in c.checks
                    if ch.check == ob.check
                },
            }
            for ob in c.obligations
        ],
    }
