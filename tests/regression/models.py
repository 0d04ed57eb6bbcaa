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
