"""A counter that passes its bound after five increments, and one that goes negative for a negative rate."""

from atcs.properties.property import Property

from regression_models import COUNTER

PROPERTIES = (
    Property(
        "counter.below_five",
        "T-4",
        "-",
        "x < 5 for rate 1",
        COUNTER,
        holds=lambda o, p, s, i, out, nxt: nxt.x < o.const(5),
        fixed_params={"rate": 1},
        max_k=10,
    ),
    Property(
        "counter.non_negative_any_rate",
        "T-5",
        "-",
        "x >= 0 without the rate assumption",
        COUNTER,
        holds=lambda o, p, s, i, out, nxt: nxt.x >= o.const(0),
    ),
)
EXPECT = {
    "counter.below_five": {"status": "falsified", "k": 4},
    "counter.non_negative_any_rate": {"status": "falsified", "k": 0},
}
