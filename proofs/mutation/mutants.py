"""Mutants: a model's own step function with one deliberate fault, for proofs that must be able to fail.

A mutant is made from the *source* of the real function (one exact text
replacement, compiled in the function's own module namespace), never from a
hand-copied variant, so it stays in step with the model as the model changes: if
the text to replace is no longer in the source, making the mutant fails loudly.

A fault in a node's own ``step`` or ``init`` gives a new node
(:func:`mutant_node`, :func:`mutant_property`); a fault in a helper the step
calls is swapped in for the duration of a ``with`` block (:func:`patched`).
"""

from __future__ import annotations
import __future__

import dataclasses
import inspect
import sys
import textwrap
import types
from collections.abc import Callable, Iterator
from contextlib import contextmanager, nullcontext
from dataclasses import dataclass
from typing import Any

from atcs.model.node import Node
from atcs.properties.property import Property


def mutate_function(fn: Callable, old: str, new: str) -> Callable:
    """``fn`` recompiled with the one occurrence of ``old`` in its source replaced by ``new``."""
    source = textwrap.dedent(inspect.getsource(fn))
    count = source.count(old)
    if count != 1:
        raise ValueError(
            f"mutating {fn.__module__}.{fn.__qualname__}: {old!r} occurs {count} times in its source; "
            "it must occur exactly once"
        )
    code = compile(
        source.replace(old, new),
        f"<mutant of {fn.__module__}.{fn.__qualname__}: {old!r} -> {new!r}>",
        "exec",
        flags=__future__.annotations.compiler_flag,
        dont_inherit=True,
    )
    namespace = dict(fn.__globals__)
    exec(code, namespace)
    return namespace[fn.__name__]


def mutant_node(node: Node, old: str, new: str, *, function: str = "step", helper: Callable | None = None) -> Node:
    """``node`` with its ``step`` (or ``init``) function mutated; with ``helper``, the step keeps its source
    but the helper it calls by name is the mutant (one call level deep)."""
    real = getattr(node, function)
    if helper is None:
        return dataclasses.replace(node, **{function: mutate_function(real, old, new)})
    if helper.__name__ not in real.__code__.co_names:
        raise ValueError(f"{real.__module__}.{real.__qualname__} does not call {helper.__name__} by name")
    namespace = {**real.__globals__, helper.__name__: mutate_function(helper, old, new)}
    rebound = types.FunctionType(real.__code__, namespace, real.__name__, real.__defaults__, real.__closure__)
    return dataclasses.replace(node, **{function: rebound})


def mutant_property(
    prop: Property, old: str, new: str, *, function: str = "step", helper: Callable | None = None
) -> Property:
    """``prop`` about the mutated node."""
    return dataclasses.replace(prop, node=mutant_node(prop.node, old, new, function=function, helper=helper))


@contextmanager
def patched(function: Callable, old: str, new: str) -> Iterator[Callable]:
    """Within the block, every ``atcs`` module-level binding of ``function`` is its mutant."""
    mutant = mutate_function(function, old, new)
    bindings = [
        (module, name)
        for module in list(sys.modules.values())
        if module is not None and module.__name__.startswith("atcs.")
        for name, value in list(vars(module).items())
        if value is function
    ]
    for module, name in bindings:
        setattr(module, name, mutant)
    try:
        yield mutant
    finally:
        for module, name in bindings:
            setattr(module, name, function)


@dataclass
class MutantRun:
    """A property proved about a mutant (:func:`falsify`)."""

    result: Any
    """The engine's result on the mutant."""
    reproduced: Any
    """The counterexample replayed on the mutant (None without one)."""
    on_real_model: Any
    """The same inputs replayed on the real model (None without a counterexample)."""

    @property
    def killed(self) -> bool:
        """Falsified, its counterexample replays on the mutant at the same step, and the real model does not
        violate the property on those inputs (the fault, not the inputs, is what breaks it)."""
        return (
            self.result.status == "falsified"
            and self.reproduced.first_violation == self.result.k
            and (bool(self.on_real_model.problems) or self.on_real_model.first_violation is None)
        )

    def __str__(self) -> str:
        return f"{self.result.name}: {self.result.status} at k={self.result.k} {self.result.message}".rstrip()


def falsify(
    prop: Property,
    function: Callable,
    old: str,
    new: str,
    *,
    timeout_s: float = 120,
    max_k: int | None = None,
    smooth: bool = False,
) -> MutantRun:
    """Prove ``prop``, without its lemmas (a mutant's lemma may not hold), about the model with ``old`` replaced
    by ``new`` in ``function``: the node's own ``step`` or ``init`` gives a mutant node, any other function is
    swapped in for the proof (:func:`patched`). ``smooth`` asks for the counterexample with the fewest input
    changes (:mod:`atcs.proofs.cex.smoothing`)."""
    from atcs.proofs.cex.trace import replay, reproduce
    from atcs.proofs.engine.prove import prove

    real = dataclasses.replace(prop, lemmas=())
    own = next((name for name in ("step", "init") if getattr(prop.node, name) is function), None)
    if own is not None:
        mutated, context = mutant_property(real, old, new, function=own), nullcontext()
    else:
        mutated, context = real, patched(function, old, new)
    with context:
        result = prove(mutated, timeout_s=timeout_s, max_k=max_k, smooth_cex=smooth)
        reproduced = reproduce(mutated, result.trace) if result.trace is not None else None
    on_real = replay(real, result.trace) if result.trace is not None else None
    return MutantRun(result, reproduced, on_real)
