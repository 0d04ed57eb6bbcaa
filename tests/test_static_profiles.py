"""Static speed profiles and safe deceleration (seed 001 §3.3, 002 §3.2, 000 §2.3).

Profile data validation; the train-length extension against seed 001's per-metre
array formulation; the MRSP and deceleration properties proved, and each one
falsified on a mutant whose counterexample replays.
"""

from fractions import Fraction

import pytest
from hypothesis import given
from hypothesis import strategies as st

from atcs.model import deceleration, mrsp, profile
from atcs.model.ops.exact import EXACT
from atcs.model.profile import Profile, ProfileError, gradient_profile, lowest_under_train, speed_profile, value_at
from atcs.proofs.engine import prove
from atcs.proofs.mutants import patched
from atcs.proofs.trace import replay, reproduce
from atcs.properties import PROPERTIES, select


class TestProfileValidation:
    def test_speed_profile_in_kmh_is_stored_in_mps_exactly(self):
        p = speed_profile("PISL", [0, 500.5], [80, 30.6], 1000)
        assert p.values == (Fraction(200, 9), Fraction(17, 2))
        assert p.starts_m == (0, Fraction(1001, 2)) and p.end_m == 1000

    def test_gradient_profile(self):
        assert gradient_profile("gradient", [0, 100], [-5, 12.5], 300).values == (-5, Fraction(25, 2))

    @pytest.mark.parametrize(
        ("args", "message"),
        [
            (([0, 200, 100], [80, 60, 40], 500), "PISL: starts_m[2] = 100 is not after starts_m[1] = 200"),
            (([0, 100, 100], [80, 60, 40], 500), "PISL: starts_m[2] = 100 is not after starts_m[1] = 100"),
            (([0, 100], [80, 60], 100), "PISL: end_m = 100 is not after the last start starts_m[1] = 100"),
            (([0, float("nan")], [80, 60], 500), "PISL: starts_m[1] = nan is not finite"),
            (([0, 100], [80, float("inf")], 500), "PISL: limits_kmh[1] = inf is not finite"),
            (([0, 100], [80, -10], 500), "PISL: limits_kmh[1] = -10 is outside (0, 600] km/h"),
            (([0, 100], [80, 0], 500), "PISL: limits_kmh[1] = 0 is outside"),
            (([0, 100], [80, 700], 500), "PISL: limits_kmh[1] = 700 is outside"),
            (([0, 100], [80], 500), "PISL: needs one start per value"),
            (([], [], 500), "PISL: needs one start per value and at least one segment"),
            (([0, "x"], [80, 60], 500), "PISL: starts_m[1] = 'x' is not a number"),
            (([0, 100], [80, True], 500), "PISL: limits_kmh[1] = True is not a number"),
        ],
    )
    def test_bad_speed_profile(self, args, message):
        with pytest.raises(ProfileError) as caught:
            speed_profile("PISL", *args)
        assert str(caught.value).startswith(message)

    def test_bad_gradient(self):
        with pytest.raises(ProfileError, match=r"gradient: gradients_permille\[0\] = -150 is outside"):
            gradient_profile("gradient", [0], [-150], 10)


# --- the train-length extension against seed 001's per-metre formulation -----------------------


@st.composite
def integer_profiles(draw, line_m=60):
    cuts = sorted(draw(st.sets(st.integers(1, line_m - 1), max_size=6)))
    values = draw(st.lists(st.integers(1, 30), min_size=len(cuts) + 1, max_size=len(cuts) + 1))
    return Profile((0, *cuts), tuple(values), line_m)


@given(profiles=st.lists(integer_profiles(), min_size=1, max_size=4), train_m=st.integers(0, 25))
def test_lowest_under_train_equals_per_metre_window_minimum(profiles, train_m):
    """Seed 001 §3.3: MRSP[i] = min(vSP[i - L .. i]) on a 1 m grid (vSP the pointwise minimum)."""
    per_metre = [min(value_at(EXACT, p, x) for p in profiles) for x in range(60)]
    for front in range(60):
        window = per_metre[max(0, front - train_m): front + 1]
        assert lowest_under_train(EXACT, profiles, train_m, front) == min(window), front


def test_short_bump_disappears():
    """Seed 002 Fig. 4(d)-(e): a higher segment shorter than the train never raises the limit."""
    p = speed_profile("PISL", [0, 100, 150], [40, 80, 40], 1000)
    limits = {lowest_under_train(EXACT, (p,), 200, x) for x in range(0, 1000, 10)}
    assert limits == {Fraction(40) / profile.KMH_PER_MPS}


# --- proofs, and mutants that must be falsified -------------------------------------------------

STATIC_PROPERTIES = select("mrsp.*") + select("deceleration.*")

MUTANTS = {
    "mrsp.below_every_profile": (mrsp.mrsp_at, "(pisl, tisl, ptsl, ttsl)", "(pisl, tisl, ptsl)"),
    "mrsp.respects_limits_under_train": (
        profile.lowest_under_train, "front_m < end + train_length_m", "front_m < end",
    ),
    "mrsp.least_restrictive": (
        profile.lowest_under_train, "front_m < end + train_length_m", "front_m < end + train_length_m + train_length_m",
    ),
    "deceleration.compensated_gradient_below_real": (
        deceleration.compensated_gradient_permille, "(gradient,), train_length_m", "(gradient,), o.const(0)",
    ),
    "deceleration.compensated_gradient_is_lowest_under_train": (
        deceleration.compensated_gradient_permille, "(gradient,), train_length_m",
        "(gradient,), train_length_m + o.const(1)",
    ),
    "deceleration.safe_deceleration_conservative": (
        deceleration.safe_deceleration_mps2, "+ gradient_deceleration_mps2(o, grad_c",
        "- gradient_deceleration_mps2(o, grad_c",
    ),
}


def test_every_static_property_has_a_mutant():
    assert set(MUTANTS) == {p.name for p in STATIC_PROPERTIES}


@pytest.mark.parametrize("prop", STATIC_PROPERTIES, ids=lambda p: p.name)
def test_proved(prop):
    result = prove(prop, timeout_s=120, lemmas=PROPERTIES)
    assert result.status == "proved", result.message


@pytest.mark.parametrize("name", sorted(MUTANTS))
def test_mutant_falsified_and_counterexample_replays(name):
    prop = PROPERTIES[name]
    function, old, new = MUTANTS[name]
    with patched(function, old, new):
        result = prove(prop, timeout_s=120)
        assert result.status == "falsified", result.message
        assert reproduce(prop, result.trace).first_violation == result.k
    # the same inputs do not violate the property on the real model
    assert replay(prop, result.trace).first_violation is None
