"""A node: one synchronous step function with explicit state (docs/design.md, step-function pattern).

A node bundles the dataclasses of its parameters, state, inputs and outputs with
two functions written once against :class:`~atcs.model.ops.Ops`:

- ``init(o, params, state) -> B``: the initial-state predicate;
- ``step(o, params, state, inputs) -> (next_state, outputs)``: one ATP cycle.

Every field of those dataclasses is annotated ``N`` (a number), ``B`` (a
boolean), or ``tuple[N, ...]`` / ``tuple[B, ...]`` (a fixed-capacity array, as
SCADE's arrays: its length for proofs is given in ``Node.sizes``). The proof
engine reads the annotations to make one z3 variable per field and step
(``field@k``, or ``field[j]@k`` for arrays), so field names must be unique across
the four dataclasses of a node.
"""

from __future__ import annotations

import dataclasses
import typing
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, Generic, Literal

from atcs.model.ops import B, N


@dataclass(frozen=True)
class Sort:
    """A field's sort: ``real`` or ``bool``, a scalar (``size`` None) or a tuple of ``size``."""

    kind: Literal["real", "bool"]
    size: int | None = None


def field_kinds(cls: type) -> dict[str, tuple[str, bool]]:
    """``{field: (kind, is_array)}`` of a node dataclass, in declaration order."""
    if not dataclasses.is_dataclass(cls):
        raise TypeError(f"{cls!r} is not a dataclass; node state, inputs, outputs and params must be")
    hints = typing.get_type_hints(cls)
    kinds: dict[str, tuple[str, bool]] = {}
    for f in dataclasses.fields(cls):
        hint = hints[f.name]
        args = typing.get_args(hint) if typing.get_origin(hint) is tuple else ()
        element, is_array = (args[0], True) if len(args) == 2 and args[1] is Ellipsis else (hint, False)
        if element is N:
            kinds[f.name] = ("real", is_array)
        elif element is B:
            kinds[f.name] = ("bool", is_array)
        else:
            raise TypeError(
                f"{cls.__name__}.{f.name} is annotated {hint!r}; node fields must be annotated "
                "N, B, tuple[N, ...] or tuple[B, ...]"
            )
    return kinds


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
    sizes: Mapping[str, int] = dataclasses.field(default_factory=dict)
    """The length of each array field (the capacity the proofs cover)."""

    def __post_init__(self):
        seen: dict[str, str] = {}
        arrays = set()
        for role in ("params", "state", "inputs", "outputs"):
            for name, (_, is_array) in field_kinds(getattr(self, role)).items():
                if name in seen:
                    raise ValueError(
                        f"node {self.name!r}: field {name!r} appears in both {seen[name]} and {role}; "
                        "field names must be unique within a node"
                    )
                seen[name] = role
                if is_array:
                    arrays.add(name)
        for name in sorted(arrays):
            size = self.sizes.get(name)
            if isinstance(size, bool) or not isinstance(size, int) or size < 1:
                raise ValueError(f"node {self.name!r}: array field {name!r} needs a size >= 1 in sizes, got {size!r}")
        for name in sorted(set(self.sizes) - arrays):
            raise ValueError(f"node {self.name!r}: sizes names {name!r}, which is not an array field")

    def sorts(self, role: str) -> dict[str, Sort]:
        """Field sorts of ``params``, ``state``, ``inputs`` or ``outputs``."""
        return {
            name: Sort(kind, self.sizes[name] if is_array else None)
            for name, (kind, is_array) in field_kinds(getattr(self, role)).items()
        }


@dataclass(frozen=True)
class Stateless(Generic[N, B]):
    """The state of a node without memory (a pure function of parameters and inputs)."""


def always(o, p, s):
    """The initial-state predicate of a :class:`Stateless` node."""
    return o.const_bool(True)


def stateless_node(
    name: str,
    *,
    params: type,
    inputs: type,
    outputs: type,
    step: Callable[..., tuple[Any, Any]],
    seed: str = "",
    sizes: Mapping[str, int] | None = None,
) -> Node:
    """A node without memory: its state is :class:`Stateless` and every state is initial (:func:`always`);
    ``step(o, p, s, i)`` returns ``s`` unchanged with the outputs."""
    return Node(
        name=name,
        params=params,
        state=Stateless,
        inputs=inputs,
        outputs=outputs,
        init=always,
        step=step,
        seed=seed,
        sizes=dict(sizes or {}),
    )


def as_dict(value) -> dict[str, Any]:
    """A node dataclass instance as ``{field: value}`` (shallow, unlike dataclasses.asdict)."""
    return {f.name: getattr(value, f.name) for f in dataclasses.fields(value)}


def flatten(record: Mapping[str, Any]) -> dict[str, Any]:
    """``{field: value}`` with each array field spread over ``field[0]``, ``field[1]``, ..."""
    flat = {}
    for name, value in record.items():
        if isinstance(value, tuple):
            flat.update({f"{name}[{j}]": v for j, v in enumerate(value)})
        else:
            flat[name] = value
    return flat
