"""The gradient's share of the safe deceleration (seed 000 §2.3, equation 2; Subset-026 §3.13.4.3), tested on
its own (seed 001 §3.4).

The node runs :data:`~atcs.model.curves.GRADIENT_ACCELERATION`, the very function the larger nodes call, with all
its data symbolic.
"""

from __future__ import annotations

from atcs.model.curves import GRADIENT_ACCELERATION
from atcs.properties.curves import seed_gradient_acceleration_mps2
from atcs.properties.property import Assumption, Property

ROTATING_MASSES = Assumption(
    "rotating_masses",
    "both rotating masses within [0, 100] % (train data)",
    lambda o, p, s, i: o.and_(
        *(
            o.and_(o.const(0) <= m, m <= o.const(100))
            for m in (p.rotating_mass_uphill_percent, p.rotating_mass_downhill_percent)
        )
    ),
)


def _gradient_from_the_seed(o, p, s, i, out, nxt):
    """A_gradient = g * gradient / (1000 + 10 * M_rotating), the uphill mass on a rising gradient and the downhill
    one on a falling gradient (0 on level track, with either)."""
    return o.eq(out.a_gradient_mps2, seed_gradient_acceleration_mps2(o, p, i.gradient_permille))


PROPERTIES = (
    Property(
        name="gradient_acceleration.from_the_seed",
        requirement="CRV-09",
        seed="000 §2.3 (equation 2), Subset-026 3.13.4.3",
        text="A_gradient = g * gradient / (1000 + 10 * M_rotating), g = 9.81 m/s^2, with the train's uphill "
        "rotating mass on a rising gradient and its downhill one on a falling gradient (stated from the "
        "seed, not through the model's function); 0 on level track.",
        node=GRADIENT_ACCELERATION,
        holds=_gradient_from_the_seed,
        assumptions=(ROTATING_MASSES,),
    ),
)
