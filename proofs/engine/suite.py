"""Run many registered properties, in this process or in ``jobs`` worker processes."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from concurrent.futures import as_completed

from atcs.proofs.engine.prove import Result, prove
from atcs.proofs.workers import worker_pool
from atcs.properties import PROPERTIES, Property

_proved_in_this_worker: dict[str, Result] = {}
"""Lemma results in a worker process (workers are spawned afresh for each run)."""


def _prove_registered(
    name: str, timeout_s: float, proved: dict[str, Result] | None = None, smooth: bool = False, nominal: bool = False
) -> Result:
    proved = _proved_in_this_worker if proved is None else proved
    result = proved.get(name) or prove(
        PROPERTIES[name], timeout_s=timeout_s, lemmas=PROPERTIES, proved=proved, smooth_cex=smooth, nominal_cex=nominal
    )
    proved[name] = result
    return result


def run(
    props: list[Property],
    *,
    timeout_s: float,
    jobs: int = 1,
    on_start: Callable[[Property], None] = lambda p: None,
    smooth: bool = False,
    nominal: bool = False,
) -> Iterator[Result]:
    """Yield one result per registered property, in completion order; with ``smooth``, counterexamples are
    smoothed (:mod:`atcs.proofs.cex.smoothing`), with ``nominal`` made near nominal (:mod:`atcs.proofs.cex.nominal`)."""
    if jobs < 1:
        raise ValueError(f"jobs must be at least 1, got {jobs!r}")
    if jobs == 1 or len(props) == 1:
        proved: dict[str, Result] = {}
        for prop in props:
            on_start(prop)
            yield _prove_registered(prop.name, timeout_s, proved, smooth, nominal)
        return
    with worker_pool(jobs) as pool:
        futures = {}
        for prop in props:
            on_start(prop)
            futures[pool.submit(_prove_registered, prop.name, timeout_s, None, smooth, nominal)] = prop
        for future in as_completed(futures):
            yield future.result()
