"""Properties of the compensated gradient and the safe deceleration (seed 000 §2.3).

For every gradient profile of up to 4 segments, every 3-step braking model,
every train length and every rotating mass M_R in [0, 50] %.
"""

from __future__ import annotations

from fractions import Fraction

from atcs.model.deceleration import (
    DECELERATION,
    braking_deceleration_mps2,
    gradient_deceleration_mps2,
    gradient_profile_of,
)
from atcs.model.profile import is_well_formed, min_over, value_at
from atcs.properties.property import Assumption, Property
from atcs.properties.under_train import TRAIN_ON_LINE, rear_m


def _well_formed(o, p, s, i):
    g = gradient_profile_of(p)
    return o.and_(
        p.train_length_m >= o.const(0),
        o.const(0) <= p.rotating_mass_percent,
        p.rotating_mass_percent <= o.const(50),
        is_well_formed(o, g),
        *(o.and_(o.const(-100) <= v, v <= o.const(100)) for v in g.values),
    )


DATA_WELL_FORMED = Assumption(
    "data_well_formed",
    "the gradient profile starts at 0 with strictly increasing breakpoints and gradients in [-100, 100] per mille; "
    "train length >= 0; 0 <= M_R <= 50 %",
    _well_formed,
)


ASSUMPTIONS = (DATA_WELL_FORMED, TRAIN_ON_LINE)

PROPERTIES = (
    Property(
        name="deceleration.compensated_gradient_below_real",
        requirement="DEC-01",
        seed="000 §2.3 (Fig. 4)",
        text="The compensated gradient at the front is never above the real gradient anywhere under the train.",
        node=DECELERATION,
        holds=lambda o, p, s, i, out, nxt: (
            out.compensated_gradient_permille <= value_at(o, gradient_profile_of(p), i.probe_m)
        ),
        assumptions=ASSUMPTIONS,
    ),
    Property(
        name="deceleration.compensated_gradient_is_lowest_under_train",
        requirement="DEC-02",
        seed="000 §2.3 (Fig. 4)",
        text="The compensated gradient is not lower than needed: it is the lowest gradient under the train.",
        node=DECELERATION,
        holds=lambda o, p, s, i, out, nxt: o.eq(
            out.compensated_gradient_permille, min_over(o, gradient_profile_of(p), rear_m(o, p, i), i.front_m)
        ),
        assumptions=ASSUMPTIONS,
    ),
    Property(
        name="deceleration.safe_deceleration_conservative",
        requirement="DEC-03",
        seed="000 §2.3 (equations 1 and 2)",
        text=(
            "The safe deceleration never exceeds what the braking model and the real gradient under any "
            "part of the train give."
        ),
        node=DECELERATION,
        holds=lambda o, p, s, i, out, nxt: (
            out.safe_deceleration_mps2
            <= (
                braking_deceleration_mps2(o, p.brake_speeds_mps, p.brake_decelerations_mps2, i.speed_mps)
                + gradient_deceleration_mps2(o, value_at(o, gradient_profile_of(p), i.probe_m), p.rotating_mass_percent)
            )
        ),
        assumptions=ASSUMPTIONS,
    ),
    Property(
        name="deceleration.gradient_term_per_seed",
        requirement="DEC-04",
        seed="000 §2.3 (equation 2)",
        text=(
            "The safe deceleration is the braking model's plus g * Grad_c / (1000 + 10 * M_R) for the compensated "
            "gradient, g = 9.81 m/s^2, stated from the seed, not through the model's function."
        ),
        node=DECELERATION,
        holds=lambda o, p, s, i, out, nxt: o.eq(
            (
                out.safe_deceleration_mps2
                - braking_deceleration_mps2(o, p.brake_speeds_mps, p.brake_decelerations_mps2, i.speed_mps)
            )
            * (o.const(1000) + o.const(10) * p.rotating_mass_percent),
            o.const(Fraction(981, 100)) * out.compensated_gradient_permille,
        ),
        assumptions=ASSUMPTIONS,
    ),
)
