"""Two registers that swap every cycle: `x == 0` holds, but is only 2-inductive."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Generic

from atcs.model.node import Node
from atcs.model.ops import B, N
from atcs.properties.property import Property


@dataclass(frozen=True)
class NoParams(Generic[N, B]):
    pass


@dataclass(frozen=True)
class Regs(Generic[N, B]):
    x: N
    y: N


@dataclass(frozen=True)
class NoInputs(Generic[N, B]):
    pass


@dataclass(frozen=True)
class Out(Generic[N, B]):
    x_out: N


def step(o, p, s, i):
    return Regs(x=s.y, y=s.x), Out(x_out=s.x)


NODE = Node(
    "swap",
    NoParams,
    Regs,
    NoInputs,
    Out,
    init=lambda o, p, s: o.and_(o.eq(s.x, o.const(0)), o.eq(s.y, o.const(0))),
    step=step,
)

PROPERTIES = (
    Property("swap.x_zero", "T-1", "-", "x stays 0", NODE, holds=lambda o, p, s, i, out, nxt: o.eq(s.x, o.const(0))),
)
EXPECT = {"swap.x_zero": {"status": "proved", "k": 2}}
