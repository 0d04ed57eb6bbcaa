"""Proofs about the model: the one front door.

``prove`` one property (:class:`Result` with a :class:`Status`), ``prove_all`` the suite, ``certify`` proofs
with z3 and cvc5, ``generate_vectors`` for a node, ``replay`` a counterexample exactly, ``read_trace`` one from
its file. The implementation lives in the subpackages (engine/, cex/, certify/, vectors/, mutation/, bench/,
cli/); names are loaded on first use, so importing this package loads no solver.
"""

from __future__ import annotations

from importlib import import_module

__all__ = ["Result", "Status", "certify", "generate_vectors", "prove", "prove_all", "read_trace", "replay"]

_WHERE = {
    "Result": ("atcs.proofs.engine.prove", "Result"),
    "Status": ("atcs.proofs.engine.prove", "Status"),
    "prove": ("atcs.proofs.engine.prove", "prove"),
    "prove_all": ("atcs.proofs.engine.suite", "run"),
    "certify": ("atcs.proofs.certify.campaign", "run"),
    "generate_vectors": ("atcs.proofs.vectors.generate", "generate"),
    "replay": ("atcs.proofs.cex.trace", "replay"),
    "read_trace": ("atcs.proofs.cex.trace", "from_json"),
}


def __getattr__(name: str):
    try:
        module, attribute = _WHERE[name]
    except KeyError:
        raise AttributeError(f"module 'atcs.proofs' has no attribute {name!r}") from None
    value = globals()[name] = getattr(import_module(module), attribute)
    return value


def __dir__() -> list[str]:
    return sorted(__all__)
