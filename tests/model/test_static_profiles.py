"""Static speed profiles and safe deceleration (seed 001 §3.3, 002 §3.2, 000 §2.3).

Profile data validation; the train-length extension against seed 001's per-metre
array formulation; the MRSP and deceleration properties proved, and each one
falsified on a mutant whose counterexample replays.
"""

from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from atcs.model import deceleration, mrsp, profile, psl
from atcs.model.ops.exact import EXACT
from atcs.model.profile import Profile, ProfileError, gradient_profile, lowest_under_train, speed_profile, value_at
from atcs.model.psl import filter_convex_bumps, permanent_speed_limit
from atcs.model.restrictions import SpeedRestrictions, canonical, restriction
from atcs.proofs.cex.trace import replay, reproduce
from atcs.proofs.engine.prove import prove
from atcs.proofs.mutation.mutants import patched
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
        window = per_metre[max(0, front - train_m) : front + 1]
        assert lowest_under_train(EXACT, profiles, train_m, front) == min(window), front


def test_short_bump_disappears():
    """Seed 002 Fig. 4(d)-(e): a higher segment shorter than the train never raises the limit."""
    p = speed_profile("PISL", [0, 100, 150], [40, 80, 40], 1000)
    limits = {lowest_under_train(EXACT, (p,), 200, x) for x in range(0, 1000, 10)}
    assert limits == {Fraction(40) / profile.KMH_PER_MPS}


# --- seed 002's preprocessing: materialized PSL, windowed restriction updates --------------------


class TestPreprocessing:
    def test_short_convex_bump_merges_into_the_higher_neighbour(self):
        """Fig. 4(d)-(e): a 50 m bump at 80 km/h between 40 and 60 km/h, under a 200 m train."""
        pisl = speed_profile("PISL", [0, 1000, 1050], [40, 80, 60], 3000)
        filtered = filter_convex_bumps(EXACT, pisl, 200)
        assert filtered.values == tuple(Fraction(v) / profile.KMH_PER_MPS for v in (40, 60, 60))
        assert canonical(filtered).starts_m == (0, 1000)
        # seed 002 merges the bump into the *preceding* segment: 40 km/h up to 1050 + 200 m instead of 1000 + 200 m
        ptsl = speed_profile("PTSL", [0], [100], 3000)
        expected = speed_profile("PSL", [0, 1200], [40, 60], 3000)
        assert canonical(permanent_speed_limit(EXACT, pisl, ptsl, 200)) == expected

    def test_long_bump_is_kept(self):
        pisl = speed_profile("PISL", [0, 1000, 1300], [40, 80, 60], 3000)
        assert filter_convex_bumps(EXACT, pisl, 200) == pisl

    @given(pisl=integer_profiles(), ptsl=integer_profiles(), train_m=st.integers(0, 25))
    def test_psl_is_the_definition_materialized(self, pisl, ptsl, train_m):
        psl_profile = permanent_speed_limit(EXACT, pisl, ptsl, train_m)
        tidy = canonical(psl_profile)
        assert canonical(tidy) == tidy
        for x in range(60):
            expected = lowest_under_train(EXACT, (pisl, ptsl), train_m, x)
            assert value_at(EXACT, psl_profile, x) == expected == value_at(EXACT, tidy, x), x


@st.composite
def long_lines(draw):
    """A line of 20 to 60 km with 10 to 300 speed limit changes, and a train of 0 to 400 m (the
    breakpoints come from a drawn seed: hypothesis draws the shape, not 300 numbers one by one)."""
    line_m = draw(st.integers(20_000, 60_000))
    count = draw(st.integers(10, 300))
    rng = draw(st.randoms(use_true_random=False))
    cuts = sorted(rng.sample(range(1, line_m), count))
    limits = [rng.choice([25, 30, 40, 60, 70, 80, 100]) for _ in range(count + 1)]
    pisl = speed_profile("PISL", [0, *cuts], limits, line_m)
    ptsl = speed_profile("PTSL", [0, line_m // 2], [draw(st.sampled_from([80, 90])), 70], line_m)
    return pisl, ptsl, draw(st.integers(0, 400))


@settings(max_examples=30)
@given(line=long_lines(), data=st.data())
def test_incremental_updates_equal_full_recomputation_on_long_lines(line, data):
    """MRSP-07 on long lines: after every apply and withdraw, the stored MRSP equals the whole-line
    recomputation segment for segment, and the definition (lowest limit under the train) point by point."""
    pisl, ptsl, train_m = line
    line_m = pisl.end_m
    store = SpeedRestrictions(pisl, ptsl, train_m)
    applied: dict[str, Profile] = {}
    for step in range(data.draw(st.integers(1, 8))):
        if applied and data.draw(st.booleans()):
            name = data.draw(st.sampled_from(sorted(applied)))
            store.withdraw(name)
            del applied[name]
        else:
            start = data.draw(st.integers(0, line_m - 1))
            end = data.draw(st.integers(start + 1, min(line_m, start + 3000)))
            limit = data.draw(st.sampled_from([10, 25, 30, 50]))
            name = f"tsr{step}"
            store.apply(name, restriction(name, start, end, limit, line_m))
            starts, limits = ([0], [600]) if start > 0 else ([], [])
            starts, limits = [*starts, start], [*limits, limit]
            if end < line_m:
                starts, limits = [*starts, end], [*limits, 600]
            applied[name] = speed_profile(name, starts, limits, line_m)
        assert store.mrsp() == store.full()
        profiles = (pisl, ptsl, *applied.values())
        for x in data.draw(st.lists(st.integers(0, line_m - 1), min_size=5, max_size=20)):
            assert value_at(EXACT, store.mrsp(), x) == lowest_under_train(EXACT, profiles, train_m, x), x


class TestRestrictionValidation:
    @pytest.mark.parametrize(
        ("args", "message"),
        [
            ((500, 400, 30, 1000), "TSR 7: [start_m, end_m) = [500, 400) is not a non-empty part of the line"),
            ((500, 500, 30, 1000), "TSR 7: [start_m, end_m) = [500, 500) is not a non-empty part"),
            ((-1, 400, 30, 1000), "TSR 7: [start_m, end_m) = [-1, 400) is not a non-empty part"),
            ((500, 1001, 30, 1000), "TSR 7: [start_m, end_m) = [500, 1001) is not a non-empty part"),
            ((100, 400, 0, 1000), "TSR 7: limit_kmh = 0 is outside (0, 600] km/h"),
            ((100, 400, float("nan"), 1000), "TSR 7: limit_kmh = nan is not finite"),
            ((100, "x", 30, 1000), "TSR 7: end_m = 'x' is not a number"),
        ],
    )
    def test_bad_restriction(self, args, message):
        with pytest.raises(ProfileError) as caught:
            restriction("TSR 7", *args)
        assert str(caught.value).startswith(message)

    def test_store_refuses_reapplying_and_unknown_withdrawal(self):
        line = speed_profile("PISL", [0], [80], 1000)
        store = SpeedRestrictions(line, line, 200)
        store.apply("works", restriction("works", 100, 200, 30, 1000))
        with pytest.raises(ProfileError, match="restriction 'works' is already applied"):
            store.apply("works", restriction("works", 300, 400, 30, 1000))
        with pytest.raises(ProfileError, match=r"restriction 'other' is not applied \(applied: 'works'\)"):
            store.withdraw("other")
        with pytest.raises(ProfileError, match="train_length_m = -1 is negative"):
            SpeedRestrictions(line, line, -1)


# --- proofs, and mutants that must be falsified -------------------------------------------------

STATIC_PROPERTIES = select("mrsp.*") + select("deceleration.*")

MUTANTS = {
    "mrsp.below_every_profile": (mrsp.mrsp_at, "(pisl, tisl, ptsl, ttsl)", "(pisl, tisl, ptsl)"),
    "mrsp.respects_limits_under_train": (
        profile.lowest_under_train,
        "front_m < end + train_length_m",
        "front_m < end",
    ),
    "mrsp.least_restrictive": (
        profile.lowest_under_train,
        "front_m < end + train_length_m",
        "front_m < end + train_length_m + train_length_m",
    ),
    "mrsp.psl_matches_definition": (psl.extend_by_train_length, "end + train_length_m", "end"),
    "mrsp.restricted_matches_definition": (psl.restricted, "r.end_m + train_length_m", "r.end_m"),
    # seed 002's literal Fig. 4(e): the bump takes the preceding segment's limit
    "mrsp.bump_filter_neutral": (psl.filter_convex_bumps, "o.max(before, after)", "before"),
    "mrsp.incremental_equals_full": (psl.affected_m, "r.end_m + train_length_m", "r.end_m"),
    # the stored breakpoints inside the window left where they are: the stored profile shows through it
    "mrsp.splice_equals_definition": (psl.splice, "keys.append(o.ite(inside, to_m, start))", "keys.append(start)"),
    # the bisection over every breakpoint, the first included: one segment late everywhere
    "mrsp.bisected_lookup_equals_chain": (profile.value_at_bisected, "profile.starts_m[1:]", "profile.starts_m"),
    "deceleration.compensated_gradient_below_real": (
        deceleration.compensated_gradient_permille,
        "(gradient,), train_length_m",
        "(gradient,), o.const(0)",
    ),
    "deceleration.compensated_gradient_is_lowest_under_train": (
        deceleration.compensated_gradient_permille,
        "(gradient,), train_length_m",
        "(gradient,), train_length_m + o.const(1)",
    ),
    "deceleration.safe_deceleration_conservative": (
        deceleration.safe_deceleration_mps2,
        "+ gradient_deceleration_mps2(",
        "- gradient_deceleration_mps2(",
    ),
    # the rotating mass left out of the divisor (a survivor of atcs mutate: DEC-03 reads the model's own formula)
    "deceleration.gradient_term_per_seed": (
        deceleration.gradient_deceleration_mps2,
        "(o.const(1000) + o.const(10) * mass)",
        "o.const(1000)",
    ),
}


def test_every_static_property_has_a_mutant():
    assert set(MUTANTS) == {p.name for p in STATIC_PROPERTIES}


@pytest.mark.parametrize("prop", STATIC_PROPERTIES, ids=lambda p: p.name)
def test_proved(prop, proof_suite_run):
    record = proof_suite_run.by_name[prop.name]  # the session's atcs prove run (conftest.py)
    assert (record["status"], record["engine"]) == ("proved", "k-induction"), record["message"]


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


@pytest.mark.parametrize(
    ("function", "old", "new"),
    [
        # the merge's own first value behind the start: the line's highest limit, or gradient (the unsafe side)
        (psl.extend_by_train_length, "(profile.values[0], *extended.values[1:])", "extended.values"),
        # the definition binding nothing behind the start
        (profile.lowest_under_train, "ahead if j == 0 else ", ""),
    ],
    ids=["extension", "definition"],
)
def test_behind_the_start_is_inside_the_psl_definition_proof(function, old, new):
    prop = PROPERTIES["mrsp.psl_matches_definition"]
    with patched(function, old, new):
        result = prove(prop, timeout_s=120)
        assert result.status == "falsified", result.message
        assert reproduce(prop, result.trace).first_violation == result.k
    assert replay(prop, result.trace).first_violation is None
