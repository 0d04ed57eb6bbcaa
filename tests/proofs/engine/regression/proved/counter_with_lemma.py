"""A counter from 0: `x != -1` is true but not k-inductive for any k; the lemma `x >= 0` makes it 0-inductive."""

from atcs.properties.property import Property

from regression_models import COUNTER, RATE_POSITIVE

PROPERTIES = (
    Property(
        "counter.non_negative",
        "T-2",
        "-",
        "x >= 0",
        COUNTER,
        holds=lambda o, p, s, i, out, nxt: s.x >= o.const(0),
        assumptions=(RATE_POSITIVE,),
    ),
    Property(
        "counter.never_minus_one",
        "T-3",
        "-",
        "x != -1",
        COUNTER,
        holds=lambda o, p, s, i, out, nxt: o.not_(o.eq(s.x, o.const(-1))),
        assumptions=(RATE_POSITIVE,),
        lemmas=("counter.non_negative",),
    ),
)
EXPECT = {
    "counter.non_negative": {"status": "proved", "k": 1},
    "counter.never_minus_one": {"status": "proved", "k": 0},
}
