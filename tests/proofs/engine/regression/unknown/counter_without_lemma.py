"""The counter's `x != -1` without its lemma: no depth closes the induction."""

from atcs.properties.property import Property

from regression_models import COUNTER, RATE_POSITIVE


def _never_minus_one(name, max_k):
    return Property(
        name,
        "T-3",
        "-",
        "x != -1",
        COUNTER,
        holds=lambda o, p, s, i, out, nxt: o.not_(o.eq(s.x, o.const(-1))),
        assumptions=(RATE_POSITIVE,),
        max_k=max_k,
    )


PROPERTIES = (
    _never_minus_one("counter.never_minus_one_no_lemma", 4),
    _never_minus_one("counter.never_minus_one_out_of_time", 10**6),
)
EXPECT = {
    "counter.never_minus_one_no_lemma": {"status": "unknown", "k": 4, "message": "not 4-inductive"},
    "counter.never_minus_one_out_of_time": {"status": "unknown", "message": "timeout", "timeout_s": 0.5},
}
