"""Nodes shared by several regression files (imported by them as ``regression_models``)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Generic

from atcs.model.node import Node
from atcs.model.ops import B, N
from atcs.properties.property import Assumption


@dataclass(frozen=True)
class Params(Generic[N, B]):
    rate: N


@dataclass(frozen=True)
class Count(Generic[N, B]):
    x: N


@dataclass(frozen=True)
class Tick(Generic[N, B]):
    go: B


@dataclass(frozen=True)
class Out(Generic[N, B]):
    value: N


def counter_step(o, p, s, i):
    """Add ``rate`` on every tick."""
    return Count(x=o.ite(i.go, s.x + p.rate, s.x)), Out(value=s.x)


COUNTER = Node("counter", Params, Count, Tick, Out, init=lambda o, p, s: o.eq(s.x, o.const(0)), step=counter_step)
RATE_POSITIVE = Assumption("rate_positive", "rate > 0", lambda o, p, s, i: p.rate > o.const(0))


@dataclass(frozen=True)
class NoParams(Generic[N, B]):
    pass


@dataclass(frozen=True)
class Cells(Generic[N, B]):
    cells: tuple[N, ...]


@dataclass(frozen=True)
class Sample(Generic[N, B]):
    sample: N


@dataclass(frozen=True)
class Oldest(Generic[N, B]):
    oldest: N


def shift_step(o, p, s, i):
    """Shift ``sample`` into a 3-cell register (an array field); output the cell shifted out."""
    return Cells(cells=(i.sample, *s.cells[:-1])), Oldest(oldest=s.cells[-1])


SHIFT = Node(
    "shift",
    NoParams,
    Cells,
    Sample,
    Oldest,
    sizes={"cells": 3},
    init=lambda o, p, s: o.and_(*(o.eq(c, o.const(0)) for c in s.cells)),
    step=shift_step,
)
SAMPLE_NON_NEGATIVE = Assumption("sample_non_negative", "sample >= 0", lambda o, p, s, i: i.sample >= o.const(0))
