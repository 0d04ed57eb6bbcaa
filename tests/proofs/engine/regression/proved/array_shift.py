"""A 3-cell shift register held in an array field: non-negative inputs keep every cell non-negative."""

from atcs.properties.property import Property

from regression_models import SAMPLE_NON_NEGATIVE, SHIFT

PROPERTIES = (
    Property(
        "shift.cells_non_negative",
        "T-6",
        "-",
        "every cell >= 0",
        SHIFT,
        holds=lambda o, p, s, i, out, nxt: o.and_(*(c >= o.const(0) for c in nxt.cells)),
        assumptions=(SAMPLE_NON_NEGATIVE,),
    ),
    Property(
        "shift.oldest_non_negative",
        "T-7",
        "-",
        "the output >= 0",
        SHIFT,
        holds=lambda o, p, s, i, out, nxt: out.oldest >= o.const(0),
        assumptions=(SAMPLE_NON_NEGATIVE,),
    ),
)
EXPECT = {
    "shift.cells_non_negative": {"status": "proved", "k": 1},
    "shift.oldest_non_negative": {"status": "proved", "k": 3},
}
