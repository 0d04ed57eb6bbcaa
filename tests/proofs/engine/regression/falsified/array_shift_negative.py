"""The shift register without the input assumption: a negative sample reaches the output after 3 steps."""

from atcs.properties.property import Property

from regression_models import SHIFT

PROPERTIES = (
    Property(
        "shift.oldest_unconstrained",
        "T-8",
        "-",
        "the output >= 0",
        SHIFT,
        holds=lambda o, p, s, i, out, nxt: out.oldest >= o.const(0),
    ),
)
EXPECT = {"shift.oldest_unconstrained": {"status": "falsified", "k": 3}}
