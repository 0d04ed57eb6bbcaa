"""What a safety property is: a named predicate over one step of a node.

A property's predicate is written once against :class:`~atcs.model.ops.Ops` as
``holds(o, params, state, inputs, outputs, next_state) -> B``, so the proof engine
(symbolic), counterexample replay (exact), the simulator and hypothesis tests
(float) all evaluate the same code. The property is claimed for every step of
every run of its node from an initial state, as long as its assumptions hold at
every step so far. Assumptions are predicates ``(o, params, state, inputs) -> B``:
constraints on the environment (sensor ranges, curve ordering, parameter ranges).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from atcs.model.node import Node

_NAME = re.compile(r"^[a-z][a-z0-9_]*(\.[a-z][a-z0-9_]*)+$")


@dataclass(frozen=True)
class Assumption:
    """A named constraint on parameters, state and inputs, assumed at every step."""

    name: str
    text: str
    holds: Callable[..., Any]


@dataclass(frozen=True)
class Property:
    """A safety property of a node (see the module docstring)."""

    name: str
    """Dotted, module first: ``supervision.eb_latched_until_standstill``."""
    requirement: str
    """Requirement id, e.g. ``SUP-02``."""
    seed: str
    """Seed section the requirement comes from, e.g. ``000 §2.4.3``."""
    text: str
    """The property in one English sentence."""
    node: Node
    holds: Callable[..., Any]
    assumptions: tuple[Assumption, ...] = ()
    lemmas: tuple[str, ...] = ()
    """Names of properties of the same node to prove first and then assume."""
    fixed_params: Mapping[str, Any] = field(default_factory=dict)
    """Parameters held at a fixed value in the proof; all others are symbolic."""
    max_k: int = 8
    """Deepest BMC / induction depth tried before giving up with ``unknown``."""
    cases: Callable[..., Any] | None = None
    """``cases(o, params, state) -> tuple of B``: split the inductive step by the state before the last step,
    one solver call per case (the engine adds the rest of the state space as one more case)."""
    certificate_cases: Callable[..., Any] | None = None
    """The split of the certificate's inductive step (:mod:`atcs.proofs.certify.obligations`), as ``cases``, when it is
    not ``cases``: the certificate is checked by cvc5 as well as z3, and a split that helps one solver can stall
    the other (docs/certificates.md). Any split is sound: the certificate adds the rest as one more case."""
    split: Callable[[], tuple[Property, Property]] | None = None
    """The property as two, named ``<name>_h0`` and ``<name>_h1``, each claimed on half of a parameter's range, which
    together are it: the prove run proves them when this one comes back ``unknown`` (:mod:`atcs.proofs.engine.split`).
    None when the property is not split, or its range is at the resolution."""

    def __post_init__(self):
        if not _NAME.match(self.name):
            raise ValueError(
                f"property name {self.name!r} must be dotted lower-case words, module first "
                "(for example 'supervision.eb_above_ebi')"
            )
        if not isinstance(self.max_k, int) or self.max_k < 0:
            raise ValueError(f"property {self.name}: max_k must be a non-negative int, got {self.max_k!r}")
        params = self.node.sorts("params")
        for key in self.fixed_params:
            if key not in params:
                raise ValueError(
                    f"property {self.name}: fixed_params names {key!r}, which is not a parameter of "
                    f"node {self.node.name!r} (parameters: {', '.join(params) or 'none'})"
                )

    @property
    def module(self) -> str:
        return self.name.split(".", 1)[0]

    def assumed(self, o, p, s, i):
        """All assumptions at one step, as one boolean."""
        return o.and_(*(a.holds(o, p, s, i) for a in self.assumptions))
