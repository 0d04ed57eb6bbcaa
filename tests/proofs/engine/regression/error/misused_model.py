"""Models and properties the engine must refuse with a clear message (status error, never proved)."""

import dataclasses

from atcs.model.node import Node
from atcs.properties.property import Assumption, Property

from regression_models import COUNTER, RATE_POSITIVE, Count, Out, Params


def python_if_step(o, p, s, i):
    if s.x > o.const(3):  # a Python branch on a model value: must be o.ite
        return Count(x=s.x), Out(value=s.x)
    return Count(x=s.x + p.rate), Out(value=s.x)


def python_eq_step(o, p, s, i):
    nxt = s.x + p.rate if s.x == o.const(0) else s.x  # `==` on model values: must be o.eq
    return Count(x=nxt), Out(value=s.x)


def float_constant_step(o, p, s, i):
    return Count(x=s.x * 0.5), Out(value=s.x)


def _prop(name, node, **kw):
    return Property(name, "T-E", "-", "x >= 0", node, holds=lambda o, p, s, i, out, nxt: s.x >= o.const(0), **kw)


RATE_SMALL = Assumption("rate_small", "rate < 1", lambda o, p, s, i: p.rate < o.const(1))

PROPERTIES = (
    _prop("errors.python_if", dataclasses.replace(COUNTER, step=python_if_step)),
    _prop("errors.python_eq", dataclasses.replace(COUNTER, step=python_eq_step)),
    _prop("errors.float_constant", dataclasses.replace(COUNTER, step=float_constant_step)),
    _prop("errors.unknown_lemma", COUNTER, lemmas=("errors.no_such_lemma",)),
    _prop("errors.lemma_with_more_assumptions", COUNTER, assumptions=(RATE_POSITIVE, RATE_SMALL)),
    _prop("errors.cycle_a", COUNTER, lemmas=("errors.cycle_b",)),
    _prop("errors.cycle_b", COUNTER, lemmas=("errors.cycle_a",)),
    _prop(
        "errors.lemma_assumes_more",
        COUNTER,
        lemmas=("errors.lemma_with_more_assumptions",),
        assumptions=(RATE_POSITIVE,),
    ),
)
EXPECT = {
    "errors.python_if": {"status": "error", "message": "o.ite"},
    "errors.python_eq": {"status": "error", "message": "o.eq"},
    "errors.float_constant": {"status": "error", "message": "float"},
    "errors.unknown_lemma": {"status": "error", "message": "errors.no_such_lemma"},
    "errors.lemma_with_more_assumptions": {"status": "proved", "k": 1},
    "errors.cycle_a": {"status": "error", "message": "lemma cycle: errors.cycle_a -> errors.cycle_b -> errors.cycle_a"},
    "errors.cycle_b": {"status": "error", "message": "lemma cycle"},
    "errors.lemma_assumes_more": {"status": "error", "message": "rate_small"},
}


def node_with_clashing_fields():
    """Node construction itself refuses a field name used twice (checked by the test)."""
    return Node("clash", Params, Count, Count, Out, init=None, step=None)
