"""Run many registered properties, in this process or in ``jobs`` worker processes."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, wait

from atcs.proofs.engine.prove import Result, prove
from atcs.proofs.workers import worker_pool
from atcs.properties import PROPERTIES, Property

_proved_in_this_worker: dict[str, Result] = {}
"""Lemma results in a worker process (workers are spawned afresh for each run)."""
_registry_in_this_worker: dict[str, Property] = PROPERTIES
"""The properties a worker process proves by name: the registered ones, and a configuration's
(:func:`_use_configuration`)."""


def _use_configuration(path: str) -> None:
    """A worker's setup for ``atcs prove --config``: the configuration's properties beside the registered ones."""
    global _registry_in_this_worker
    _registry_in_this_worker = configured_registry(path)


def configured_registry(path: str | None) -> dict[str, Property]:
    """The registered properties, and with a configuration file its train- and line-dependent ones
    (:mod:`atcs.properties.configured`) and their parts by name (:mod:`atcs.proofs.engine.split`)."""
    if path is None:
        return PROPERTIES
    from atcs.model.configuration import load_configuration
    from atcs.proofs.engine.split import PropertyRegistry
    from atcs.properties.configured import configuration_properties

    configured = configuration_properties(load_configuration(path))
    return PropertyRegistry({**PROPERTIES, **{p.name: p for p in configured}})


def configured_nodes(path: str) -> dict[str, tuple]:
    """The nodes of the configuration's properties by name, each with those properties (for ``atcs vectors
    generate --config``: vectors in the environments of the user's data)."""
    from atcs.model.configuration import load_configuration
    from atcs.properties.configured import configuration_properties

    nodes: dict[str, tuple] = {}
    for p in configuration_properties(load_configuration(path)):
        node, props = nodes.get(p.node.name, (p.node, ()))
        nodes[p.node.name] = (node, (*props, p))
    return nodes


def configuration_data_sha256(props) -> str:
    """SHA-256 of what a configuration gives a node's properties: their names, fixed data and assumptions."""
    import hashlib

    digest = hashlib.sha256()
    for p in props:
        fixed = sorted((k, repr(v)) for k, v in p.fixed_params.items())
        digest.update(repr((p.name, fixed, [a.text for a in p.assumptions])).encode())
    return digest.hexdigest()


def _prove_registered(
    name: str,
    timeout_s: float,
    proved: dict[str, Result] | None = None,
    smooth: bool = False,
    nominal: bool = False,
    registry: dict[str, Property] | None = None,
) -> Result:
    proved = _proved_in_this_worker if proved is None else proved
    registry = _registry_in_this_worker if registry is None else registry
    result = proved.get(name) or prove(
        registry[name], timeout_s=timeout_s, lemmas=registry, proved=proved, smooth_cex=smooth, nominal_cex=nominal
    )
    proved[name] = result
    return result


def _prove_in_worker(
    name: str, timeout_s: float, lemma_results: dict[str, Result], smooth: bool, nominal: bool
) -> Result:
    """:func:`_prove_registered` in a worker, with the results of the property's lemmas proved elsewhere."""
    _proved_in_this_worker.update(lemma_results)
    return _prove_registered(name, timeout_s, None, smooth, nominal)


def _lemma_closure(name: str, registry: dict[str, Property]) -> set[str]:
    found, todo = set(), list(registry[name].lemmas)
    while todo:
        lemma = todo.pop()
        if lemma not in found:
            found.add(lemma)
            todo += registry[lemma].lemmas
    return found


def run(
    props: list[Property],
    *,
    timeout_s: float,
    jobs: int = 1,
    on_start: Callable[[Property], None] = lambda p: None,
    smooth: bool = False,
    nominal: bool = False,
    configuration: str | None = None,
) -> Iterator[Result]:
    """Yield one result per registered property (or property of the ``configuration`` file), in completion order;
    with ``smooth``, counterexamples are smoothed (:mod:`atcs.proofs.cex.smoothing`), with ``nominal`` made near
    nominal (:mod:`atcs.proofs.cex.nominal`).

    With ``jobs`` workers, a property whose lemmas are among ``props`` starts once they are proved, with their
    results, so no two workers prove the same lemma."""
    if jobs < 1:
        raise ValueError(f"jobs must be at least 1, got {jobs!r}")
    if jobs == 1 or len(props) == 1:
        proved: dict[str, Result] = {}
        registry = configured_registry(configuration)
        for prop in props:
            on_start(prop)
            yield _prove_registered(prop.name, timeout_s, proved, smooth, nominal, registry)
        return
    registry = configured_registry(configuration)
    names = {p.name for p in props}
    waits = {p.name: _lemma_closure(p.name, registry) & names for p in props}
    done: dict[str, Result] = {}
    setup = (_use_configuration, (configuration,)) if configuration is not None else (None, ())
    with worker_pool(jobs, *setup) as pool:
        futures = {}

        def submit_ready():
            for prop in props:
                if prop.name in waits and waits[prop.name] <= set(done):
                    lemmas = {n: done[n] for n in _lemma_closure(prop.name, registry) if n in done}
                    del waits[prop.name]
                    on_start(prop)
                    futures[pool.submit(_prove_in_worker, prop.name, timeout_s, lemmas, smooth, nominal)] = prop

        submit_ready()
        while futures:
            finished, _ = wait(futures, return_when=FIRST_COMPLETED)
            for future in finished:
                futures.pop(future)
                result = future.result()
                done[result.name] = result
                yield result
            submit_ready()
