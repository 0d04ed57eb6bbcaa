"""A node: one synchronous step function with explicit state (DESIGN.md, step-function pattern).

A node bundles the dataclasses of its parameters, state, inputs and outputs with
two functions written once against :class:`~atcs.model.ops.Ops`:

- ``init(o, params, state) -> B``: the initial-state predicate;
- ``step(o, params, state, inputs) -> (next_state, outputs)``: one ATP cycle.

Every field of those dataclasses is annotated ``N`` (a number) or ``B`` (a
boolean); the proof engine reads the annotations to make one z3 variable per
field and step (``field@k``), so field names must be unique across the four
dataclasses of a node.
"""

from __future__ import annotations

import dataclasses
import typing
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Literal

from atcs.model.ops import B, N

Sort = Literal["real", "bool"]


def field_sorts(cls: type) -> dict[str, Sort]:
    """The sort of each field of a node dataclass, in declaration order."""
    if not dataclasses.is_dataclass(cls):
        raise TypeError(f"{cls!r} is not a dataclass; node state, inputs, outputs and params must be")
    hints = typing.get_type_hints(cls)
    sorts: dict[str, Sort] = {}
    for f in dataclasses.fields(cls):
        hint = hints[f.name]
        if hint is N:
            sorts[f.name] = "real"
        elif hint is B:
            sorts[f.name] = "bool"
        else:
            raise TypeError(
                f"{cls.__name__}.{f.name} is annotated {hint!r}; node fields must be annotated N or B"
            )
    return sorts


@dataclass(frozen=True)
class Node:
    """A step function and the types it steps over."""

    name: str
    params: type
    state: type
    inputs: type
    outputs: type
    init: Callable[..., Any]
    step: Callable[..., tuple[Any, Any]]
    seed: str = ""

    def __post_init__(self):
        seen: dict[str, str] = {}
        for role in ("params", "state", "inputs", "outputs"):
            cls = getattr(self, role)
            for name in field_sorts(cls):
                if name in seen:
                    raise ValueError(
                        f"node {self.name!r}: field {name!r} appears in both {seen[name]} and {role}; "
                        "field names must be unique within a node"
                    )
                seen[name] = role

    def sorts(self, role: str) -> dict[str, Sort]:
        """Field sorts of ``params``, ``state``, ``inputs`` or ``outputs``."""
        return field_sorts(getattr(self, role))


def as_dict(value) -> dict[str, Any]:
    """A node dataclass instance as ``{field: value}`` (shallow, unlike dataclasses.asdict)."""
    return {f.name: getattr(value, f.name) for f in dataclasses.fields(value)}
