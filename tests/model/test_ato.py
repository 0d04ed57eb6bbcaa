"""ATO target-speed selection (seed 003 §2.1, §2.2): each rule on a concrete example under every backend,
validation, the MRSP convenience, hypothesis properties on Fractions and floats; the selection's bounds are the
registered properties ATO-01 to ATO-04, each falsified on a mutant whose counterexample replays, and the bare
"at most the MA speed near the MA" is shown false by the seed's own rule.

Numbers in the examples are the seeds': 80 km/h trains and a 3.0 km/h/s service brake (seed 000 §2.5)
as the ATO's planning deceleration.
"""

import dataclasses
import inspect
from fractions import Fraction

import numpy as np
import pytest
import z3
from hypothesis import given, settings
from hypothesis import strategies as st

from atcs.model import ato
from atcs.model.ato import (
    FAR,
    MA_END,
    REASON_NAMES,
    SPEED_LIMIT,
    AtoError,
    AtoTarget,
    LimitsAhead,
    ato_preconditions,
    ato_target_speed,
    choose_target,
    limits_ahead,
)
from atcs.model.curves import FAR_M
from atcs.model.ops import backends
from atcs.model.ops.exact import EXACT
from atcs.model.ops.floating import FLOAT
from atcs.model.ops.symbolic import SYMBOLIC, Real, unwrap
from atcs.model.profile import KMH_PER_MPS, speed_profile, value_at
from atcs.proofs.mutation.mutants import falsify
from atcs.properties import PROPERTIES
from atcs.properties.ato import PROPERTIES as ATO_PROPERTIES

INPUTS = tuple(name for name in inspect.signature(choose_target).parameters if name != "o")


def kmh(value) -> Fraction:
    return Fraction(value) / KMH_PER_MPS


PLANNING = kmh(3)  # 3.0 km/h/s service brake (seed 000 §2.5) = 5/6 m/s^2
MARGIN = Fraction(20)


def inputs(**changes) -> dict:
    """A train at 80 km/h at 0 m, line 100 km/h, train max 80 km/h, nothing near: a 40 km/h limit at
    2 km and a balise MA at 5 km."""
    base = dict(
        front_m=Fraction(0),
        speed_mps=kmh(80),
        line_limit_mps=kmh(100),
        train_max_mps=kmh(80),
        next_limit_m=Fraction(2000),
        next_limit_mps=kmh(40),
        ma_end_m=Fraction(5000),
        ma_speed_mps=Fraction(0),
        planning_decel_mps2=PLANNING,
        margin_m=MARGIN,
    )
    return base | changes


def braking_m(v_mps, u_mps) -> Fraction:
    """Braking distance at the planning deceleration, margin included (the rule's threshold)."""
    return (v_mps * v_mps - u_mps * u_mps) / (2 * PLANNING) + MARGIN


def sym_value(value):
    """A closed symbolic term as a Fraction."""
    return z3.simplify(unwrap(value)).as_fraction()


def run(backend: str, values: dict) -> AtoTarget:
    """``ato_target_speed`` on ``backend``, read back as Fractions (the float run's doubles exactly)."""
    o = backends()[backend]
    if backend == "exact":
        return ato_target_speed(o, **values)
    if backend == "float":
        result = ato_target_speed(o, **{k: float(v) for k, v in values.items()})
        return AtoTarget(*(Fraction(getattr(result, f.name)) for f in dataclasses.fields(AtoTarget)))
    result = ato_target_speed(o, **{k: o.const(v) for k, v in values.items()})
    return AtoTarget(*(sym_value(getattr(result, f.name)) for f in dataclasses.fields(AtoTarget)))


def same(backend: str, values: dict, expected: AtoTarget) -> bool:
    """``values`` give ``expected`` on ``backend``: the same rule exactly, and the same speed and location
    (to rounding on floats: km/h are not binary fractions of m/s)."""
    got = run(backend, values)
    if backend != "float":
        return got == expected
    return got.reason == expected.reason and all(
        float(getattr(got, name)) == pytest.approx(float(getattr(expected, name)), rel=1e-12, abs=1e-12)
        for name in ("speed_mps", "location_m")
    )


BACKENDS = ["float", "exact", "symbolic"]


# --- the seed's rules, each on a concrete example (every backend) -----------------------------------------


@pytest.mark.parametrize("backend", BACKENDS)
class TestSeedRules:
    def test_far_from_everything_the_smaller_of_line_limit_and_train_max(self, backend):
        """Seed 003 §2.1 / §2.2 first bullets."""
        assert same(backend, inputs(), AtoTarget(kmh(80), Fraction(0), FAR))  # train max 80 < line 100
        assert same(backend, inputs(line_limit_mps=kmh(70)), AtoTarget(kmh(70), Fraction(0), FAR))

    def test_approaching_a_lower_limit_that_limit(self, backend):
        """Seed 003 §2.1 / §2.2 second bullets, §2.1.1, §2.2.1: inside the limit's braking distance (its
        yellow zone) the target is the limit; just outside it is not."""
        edge_m = braking_m(kmh(80), kmh(40))  # 222.2 m + 20 m margin
        inside_m = edge_m - Fraction(1, 8)
        assert same(backend, inputs(next_limit_m=inside_m), AtoTarget(kmh(40), inside_m, SPEED_LIMIT))
        assert run(backend, inputs(next_limit_m=edge_m + Fraction(1, 8))).reason == FAR
        if backend != "float":  # the edge itself belongs to the zone (exactly; floats round km/h)
            assert run(backend, inputs(next_limit_m=edge_m)) == AtoTarget(kmh(40), edge_m, SPEED_LIMIT)

    def test_a_lower_limit_matters_only_to_a_faster_train(self, backend):
        """Seed 003 §2.1 / §2.2 second bullets: "current speed above the next track's limit"."""
        slow = inputs(speed_mps=kmh(30), next_limit_m=Fraction(5))
        assert same(backend, slow, AtoTarget(kmh(80), Fraction(0), FAR))

    def test_a_limit_at_or_behind_the_front_is_in_force(self, backend):
        """A limit at distance <= 0 needs an infinite deceleration: it is the target whatever the speed."""
        for at_m in (Fraction(0), Fraction(-5)):
            assert same(backend, inputs(speed_mps=kmh(30), next_limit_m=at_m), AtoTarget(kmh(40), at_m, SPEED_LIMIT))

    def test_near_a_balise_ma_zero(self, backend):
        """Seed 003 §2.1 third bullet, §2.1.2 Fig. 5: not far enough from the MA -> 0 km/h."""
        edge_m = braking_m(kmh(80), 0)  # 296.3 m + 20 m
        inside_m = edge_m - Fraction(1, 8)
        assert same(backend, inputs(ma_end_m=inside_m), AtoTarget(Fraction(0), inside_m, MA_END))
        assert run(backend, inputs(ma_end_m=edge_m + Fraction(1, 8))).reason == FAR
        if backend != "float":
            assert run(backend, inputs(ma_end_m=edge_m)) == AtoTarget(Fraction(0), edge_m, MA_END)

    def test_near_a_radio_ma_the_preceding_trains_speed(self, backend):
        """Seed 003 §2.2 third bullet, §2.2.2: near the preceding train -> its speed."""
        leader = kmh(30)
        edge_m = braking_m(kmh(80), leader)  # 254.6 m + 20 m
        inside_m = edge_m - Fraction(1, 8)
        assert same(backend, inputs(ma_end_m=inside_m, ma_speed_mps=leader), AtoTarget(leader, inside_m, MA_END))
        assert run(backend, inputs(ma_end_m=edge_m + Fraction(1, 8), ma_speed_mps=leader)).reason == FAR

    def test_near_a_radio_ma_the_smallest_of_all_limits(self, backend):
        """Seed 003 §2.2 third bullet: min(preceding train, train max, current limit, next limit)."""
        near = inputs(ma_end_m=Fraction(100), ma_speed_mps=kmh(60))
        assert same(backend, near, AtoTarget(kmh(40), Fraction(100), MA_END))  # the 40 km/h next limit
        lower_line = near | {"next_limit_mps": kmh(70), "line_limit_mps": kmh(50)}
        assert same(backend, lower_line, AtoTarget(kmh(50), Fraction(100), MA_END))  # the 50 km/h line limit

    def test_both_near_the_larger_deceleration_wins(self, backend):
        """Seed 003 §2.1.2 Fig. 6: compute each deceleration, follow the larger."""
        # the limit needs (v^2 - u^2) / 2d = 1.23 m/s^2 at 150 m, the MA v^2 / 2d = 0.80 m/s^2 at 310 m
        limit_first = inputs(next_limit_m=Fraction(150), ma_end_m=Fraction(310))
        assert same(backend, limit_first, AtoTarget(kmh(40), Fraction(150), SPEED_LIMIT))
        # the limit needs 0.77 m/s^2 at 240 m, the MA 0.82 m/s^2 at 300 m
        ma_first = inputs(next_limit_m=Fraction(240), ma_end_m=Fraction(300))
        assert same(backend, ma_first, AtoTarget(Fraction(0), Fraction(300), MA_END))

    def test_equal_decelerations_the_ma_wins(self, backend):
        # (20^2 - 10^2) / (2 * 30) = 20^2 / (2 * 40) = 5 m/s^2
        tie = inputs(
            speed_mps=Fraction(20),
            line_limit_mps=Fraction(30),
            train_max_mps=Fraction(30),
            next_limit_mps=Fraction(10),
            next_limit_m=Fraction(30),
            ma_end_m=Fraction(40),
        )
        assert same(backend, tie, AtoTarget(Fraction(0), Fraction(40), MA_END))

    def test_infinite_decelerations(self, backend):
        """Distance <= 0 needs an infinite deceleration: it wins, and the MA wins a tie of two."""
        limit_behind = inputs(next_limit_m=Fraction(-1), ma_end_m=Fraction(250))
        assert same(backend, limit_behind, AtoTarget(kmh(40), Fraction(-1), SPEED_LIMIT))
        both_behind = inputs(next_limit_m=Fraction(-1), ma_end_m=Fraction(0))
        assert same(backend, both_behind, AtoTarget(Fraction(0), Fraction(0), MA_END))


def test_a_batch_of_trains_in_one_float_call():
    """The float backend steps numpy arrays: far, approaching the limit, near the MA."""
    values = {k: float(v) for k, v in inputs().items()}
    values["next_limit_m"] = np.array([2000.0, 200.0, 2000.0])
    values["ma_end_m"] = np.array([5000.0, 5000.0, 300.0])
    result = ato_target_speed(FLOAT, **values)
    assert result.reason.tolist() == [FAR, SPEED_LIMIT, MA_END]
    assert np.allclose(result.speed_mps, [float(kmh(80)), float(kmh(40)), 0.0])
    assert result.location_m.tolist() == [0.0, 200.0, 300.0]


def test_reason_names():
    assert REASON_NAMES == {FAR: "far", SPEED_LIMIT: "speed limit", MA_END: "MA end"}


# --- validation of concrete planning data ---------------------------------------------------------------


class TestValidation:
    @pytest.mark.parametrize(
        ("changes", "message"),
        [
            (
                {"planning_decel_mps2": Fraction(0)},
                "planning_decel_mps2 must be positive and finite, got Fraction(0, 1)",
            ),
            ({"planning_decel_mps2": -0.5}, "planning_decel_mps2 must be positive and finite, got -0.5"),
            ({"planning_decel_mps2": float("nan")}, "planning_decel_mps2 must be positive and finite, got nan"),
            ({"planning_decel_mps2": float("inf")}, "planning_decel_mps2 must be positive and finite, got inf"),
            ({"planning_decel_mps2": True}, "planning_decel_mps2 must be a positive number, got True"),
            ({"margin_m": Fraction(-1)}, "margin_m must be non-negative and finite, got Fraction(-1, 1)"),
            (
                {"planning_decel_mps2": np.array([1.0, -2.0])},
                "planning_decel_mps2[1] must be positive and finite, got np.float64(-2.0)",
            ),
        ],
    )
    def test_bad_planning_data_named(self, changes, message):
        with pytest.raises(ValueError) as caught:
            ato_target_speed(EXACT, **inputs(**changes))
        assert isinstance(caught.value, AtoError)
        assert message in str(caught.value)

    def test_zero_margin_is_accepted(self):
        assert ato_target_speed(EXACT, **inputs(margin_m=0)).reason == FAR

    def test_symbolic_planning_data_is_left_to_the_proof(self):
        values = {k: SYMBOLIC.const(v) for k, v in inputs().items()}
        values["planning_decel_mps2"] = Real(z3.Real("a"))
        values["margin_m"] = Real(z3.Real("margin"))
        ato_target_speed(SYMBOLIC, **values)  # no exception: the preconditions constrain them instead

    def test_below_mps_of_limits_ahead(self):
        with pytest.raises(AtoError, match=r"below_mps must be positive and finite, got 0"):
            limits_ahead(speed_profile("mrsp", [0], [80], 100), 0, below_mps=0)


# --- the MRSP convenience ----------------------------------------------------------------------------------


class TestLimitsAhead:
    MRSP = speed_profile("mrsp", [0, 1000, 2000, 3000], [80, 100, 60, 40], 5000)

    @pytest.mark.parametrize(
        ("front_m", "expected"),
        [
            (500, LimitsAhead(kmh(80), 2000, kmh(60))),  # the rise to 100 is skipped: not lower than 80
            (-100, LimitsAhead(kmh(80), 2000, kmh(60))),  # before the profile: its first segment's limit
            (1000, LimitsAhead(kmh(100), 2000, kmh(60))),  # a segment starting at the front binds
            (2000, LimitsAhead(kmh(60), 3000, kmh(40))),
            (3500, LimitsAhead(kmh(40), FAR_M, kmh(40))),  # nothing lower ahead
            (9000, LimitsAhead(kmh(40), FAR_M, kmh(40))),  # past the profile: its last segment's limit
        ],
    )
    def test_current_and_next_lower_limit(self, front_m, expected):
        assert limits_ahead(self.MRSP, Fraction(front_m)) == expected

    def test_a_drop_above_the_train_max_does_not_hide_a_lower_one(self):
        mrsp = speed_profile("mrsp", [0, 1000, 2000], [120, 100, 60], 3000)
        assert limits_ahead(mrsp, 0) == LimitsAhead(kmh(120), 1000, kmh(100))
        assert limits_ahead(mrsp, 0, below_mps=kmh(80)) == LimitsAhead(kmh(120), 2000, kmh(60))

    def test_feeds_the_target_selection(self):
        """80 km/h towards the 60 km/h drop at 2000 m (braking distance 129.6 m + 20 m): far at 1800, near at 1880 m."""
        for front_m, reason in ((Fraction(1800), FAR), (Fraction(1880), SPEED_LIMIT)):
            limits = limits_ahead(self.MRSP, front_m, below_mps=kmh(80))
            values = inputs(front_m=front_m, **dataclasses.asdict(limits))
            result = ato_target_speed(EXACT, **values)
            assert result.reason == reason
            assert result.speed_mps == (kmh(60) if reason == SPEED_LIMIT else kmh(80))

    @given(
        data=st.lists(st.tuples(st.integers(1, 50), st.integers(1, 30)), min_size=1, max_size=8),
        front=st.integers(-50, 1500),
    )
    @settings(max_examples=50)
    def test_the_first_lower_limit_ahead(self, data, front):
        """Against the definition: the next lower limit lies ahead, is below the limit in force, and no
        profile value between the front and it is."""
        starts = [0]
        for length, _ in data[:-1]:
            starts.append(starts[-1] + 10 * length)
        mrsp = speed_profile("mrsp", starts, [10 * limit for _, limit in data], starts[-1] + 100)
        front_m = Fraction(front)
        found = limits_ahead(mrsp, front_m)
        assert found.line_limit_mps == value_at(EXACT, mrsp, front_m)
        between = [s for s in mrsp.starts_m if front_m < s < found.next_limit_m]
        assert all(value_at(EXACT, mrsp, s) >= found.line_limit_mps for s in between)
        if found.next_limit_m == FAR_M:
            assert found.next_limit_mps == found.line_limit_mps
        else:
            assert found.next_limit_m > front_m
            assert found.next_limit_mps == value_at(EXACT, mrsp, found.next_limit_m) < found.line_limit_mps


# --- hypothesis properties ---------------------------------------------------------------------------------

# A 1/8 grid (m, m/s, m/s^2) small enough that every product the selection forms is exact in a double:
# the float run then takes the same branches as the exact one, and the results agree exactly.
positions = st.integers(-8 * 1000, 8 * 6000).map(lambda k: Fraction(k, 8))
speeds = st.integers(0, 8 * 100).map(lambda k: Fraction(k, 8))
limits = st.integers(1, 8 * 100).map(lambda k: Fraction(k, 8))
input_values = st.fixed_dictionaries(
    {
        "front_m": positions,
        "speed_mps": speeds,
        "line_limit_mps": limits,
        "train_max_mps": limits,
        "next_limit_m": positions,
        "next_limit_mps": speeds,
        "ma_end_m": positions,
        "ma_speed_mps": speeds,
        "planning_decel_mps2": st.integers(1, 8 * 2).map(lambda k: Fraction(k, 8)),
        "margin_m": st.integers(0, 8 * 50).map(lambda k: Fraction(k, 8)),
    }
)


class TestProperties:
    @given(values=input_values)
    @settings(max_examples=50)
    def test_target_never_exceeds_line_limit_or_train_max(self, values):
        result = ato_target_speed(EXACT, **values)
        assert 0 <= result.speed_mps <= min(values["line_limit_mps"], values["train_max_mps"])
        expected_location = {FAR: values["front_m"], SPEED_LIMIT: values["next_limit_m"], MA_END: values["ma_end_m"]}
        assert result.location_m == expected_location[result.reason]

    @given(values=input_values)
    @settings(max_examples=50)
    def test_floats_agree_with_fractions(self, values):
        assert run("float", values) == ato_target_speed(EXACT, **values)


# --- z3: proofs over all inputs satisfying the preconditions, and mutants ------------------------------------

SYMBOLS = {name: Real(z3.Real(name)) for name in INPUTS}
"""Every input a z3 real: the proofs quantify over positions, speeds, limits, deceleration and margin."""


def ma_within_braking_distance(o, i):
    """The brief's "within the braking distance of the MA": ``d_MA <= (v^2 - v_MA^2) / (2 a) + margin``."""
    v, u = i["speed_mps"], i["ma_speed_mps"]
    return o.const(2) * i["planning_decel_mps2"] * (i["ma_end_m"] - i["front_m"] - i["margin_m"]) <= v * v - u * u


def limit_strictly_ahead(o, i):
    return i["next_limit_m"] > i["front_m"]


def ma_speed_bounds_target(o, i, r):
    return r.speed_mps <= i["ma_speed_mps"]


def ma_speed_or_steeper_limit(o, i, r):
    """The target is at most the MA speed, or it is a speed limit that needs at least the MA's deceleration
    (``(v^2 - u^2) / d_lim >= (v^2 - v_MA^2) / d_MA``, infinite for ``d_lim <= 0``): its constant-deceleration
    pattern passes the MA's location at or below the MA speed."""
    v2 = i["speed_mps"] * i["speed_mps"]
    d_ma, d_lim = i["ma_end_m"] - i["front_m"], i["next_limit_m"] - i["front_m"]
    steeper = (v2 - r.speed_mps * r.speed_mps) * d_ma >= (v2 - i["ma_speed_mps"] * i["ma_speed_mps"]) * d_lim
    return o.or_(
        r.speed_mps <= i["ma_speed_mps"],
        o.and_(o.eq(r.reason, o.const(SPEED_LIMIT)), o.or_(d_lim <= o.const(0), steeper)),
    )


def solve(target_fn, hypotheses, claim):
    """Check ``preconditions and hypotheses and not claim`` over :data:`SYMBOLS` with the step function
    ``target_fn``: returns z3's verdict and, when sat, the counterexample as Fractions."""
    o = SYMBOLIC
    result = target_fn(o, **SYMBOLS)
    solver = z3.Solver()
    solver.set(timeout=5000)
    solver.add(unwrap(ato_preconditions(o, **SYMBOLS)), *(unwrap(h(o, SYMBOLS)) for h in hypotheses))
    solver.add(z3.Not(unwrap(claim(o, SYMBOLS, result))))
    verdict = solver.check()
    if verdict != z3.sat:
        return verdict, None
    model = solver.model()
    return verdict, {n: model.eval(unwrap(s), model_completion=True).as_fraction() for n, s in SYMBOLS.items()}


def replay(target_fn, hypotheses, claim, values) -> bool:
    """A counterexample on Fractions: the preconditions and hypotheses hold, and whether the claim does."""
    o = EXACT
    assert ato_preconditions(o, **values) and all(h(o, values) for h in hypotheses)
    return claim(o, values, target_fn(o, **values))


# property -> (function, text in it, faulty replacement): each falsified, its counterexample replayed
MUTANTS = {
    # max(line limit, train max) taken as the cap
    "ato.within_the_cap": (
        ato.choose_target,
        "o.min(line_limit_mps, train_max_mps)",
        "o.max(line_limit_mps, train_max_mps)",
    ),
    # the margin taken off the braking distance instead of added: a limit found near too late
    "ato.within_a_near_limit": (ato.within_braking_distance, "(distance_m - margin_m)", "(distance_m + margin_m)"),
    # the target needing the *smaller* deceleration followed
    "ato.ma_speed_or_a_steeper_limit": (
        ato.needs_at_least_the_deceleration_of,
        "first_needs >= second_needs",
        "first_needs <= second_needs",
    ),
    # the MA's target speed the larger of the MA speed and the limit
    "ato.ma_speed_with_no_nearer_limit": (
        ato.choose_target,
        "o.min(ma_speed_mps, limit_target_mps)",
        "o.max(ma_speed_mps, limit_target_mps)",
    ),
    # a limit the train runs exactly at taken as near: the ATO brakes for it with nothing near
    "ato.far_mode": (ato.choose_target, "speed_mps > limit_target_mps", "speed_mps >= limit_target_mps"),
    # the MA chosen only when it needs strictly more deceleration: a tie goes to the limit
    "ato.ma_mode": (
        ato.needs_at_least_the_deceleration_of,
        "first_needs >= second_needs",
        "first_needs > second_needs",
    ),
    # a limit starting exactly at the front not taken as in force: the ATO drives on at the cap
    "ato.limit_mode": (ato.choose_target, "limit_distance_m <= o.const(0)", "limit_distance_m < o.const(0)"),
}


def test_every_ato_property_has_a_mutant():
    assert set(MUTANTS) == {p.name for p in ATO_PROPERTIES}


@pytest.mark.parametrize("prop", ATO_PROPERTIES, ids=lambda p: p.name)
def test_proved_by_k_induction(prop, proof_suite_run):
    record = proof_suite_run.by_name[prop.name]  # the session's atcs prove run (conftest.py)
    assert (record["status"], record["engine"], record["k"]) == ("proved", "k-induction", 0), record["message"]


@pytest.mark.parametrize("name", sorted(MUTANTS))
def test_mutant_falsified_and_counterexample_replays(name):
    run = falsify(PROPERTIES[name], *MUTANTS[name], max_k=1)
    assert run.killed, run


class TestZ3:
    def test_ma_speed_alone_does_not_bound_the_target_near_the_ma(self):
        """Without "no limit nearer than the MA" the bare claim is false, by the seed's own rule (§2.1.2
        Fig. 6): a limit ahead of the MA that needs a larger deceleration is the target, above the MA speed."""
        hypotheses = [ma_within_braking_distance, limit_strictly_ahead]
        verdict, values = solve(ato_target_speed, hypotheses, ma_speed_bounds_target)
        assert verdict == z3.sat
        assert not replay(ato_target_speed, hypotheses, ma_speed_bounds_target, values)
        result = ato_target_speed(EXACT, **values)
        assert result.reason == SPEED_LIMIT and result.speed_mps > values["ma_speed_mps"]
        assert replay(ato_target_speed, hypotheses, ma_speed_or_steeper_limit, values)
