"""A property proved on its cone of influence only: a latch that can sit at 1 and then jump to the bad value 2,
unreachable from 0, is ruled out at k = 2 by the simple-path constraint (1, 1, 2 repeats a state); a clock the
property never reads would make every path simple (its value differs at every step), so without slicing to the
cone no depth proves it. The latch's jump reads ``offset``, which the cone must keep (it is read through the
latch's next value, not by the property)."""

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
class LatchAndClock(Generic[N, B]):
    latch: N
    offset: N
    clock: N


@dataclass(frozen=True)
class Go(Generic[N, B]):
    go: B


@dataclass(frozen=True)
class Out(Generic[N, B]):
    latch_out: N


def step(o, p, s, i):
    one = o.const(1)
    jump = o.ite(i.go, s.offset + o.const(2), one)
    return LatchAndClock(latch=o.ite(o.eq(s.latch, one), jump, s.latch), offset=s.offset, clock=s.clock + one), Out(
        latch_out=s.latch
    )


NODE = Node(
    "latch_and_clock",
    NoParams,
    LatchAndClock,
    Go,
    Out,
    init=lambda o, p, s: o.and_(o.eq(s.latch, o.const(0)), o.eq(s.offset, o.const(0)), o.eq(s.clock, o.const(0))),
    step=step,
)

PROPERTIES = (
    Property(
        "latch.never_two",
        "T-6",
        "-",
        "the latch never becomes 2",
        NODE,
        holds=lambda o, p, s, i, out, nxt: o.not_(o.eq(s.latch, o.const(2))),
        max_k=4,
    ),
)
EXPECT = {"latch.never_two": {"status": "proved", "k": 2}}
