"""Headway at 80 km/h (seed 001 §3.2 Fig. 6, seed 000 §2.5): the separation invariant's bound, the
ATP-limited gap and the simulator's steady state, in both modes. The invariant's figure is checked against SEP-01's
own predicate; the measurement settles between the theory's best and worst phases of the route locking; a follower
with half the emergency brake moves every figure the expected way, out of the nominal bound. The measured
figures come from three closed-loop runs of about 2,000 cycles (``slow``)."""

import dataclasses
from fractions import Fraction

import pytest

from atcs.model.ops.exact import EXACT
from atcs.model.profile import KMH_PER_MPS
from atcs.model.train_data import seed000_train
from atcs.properties.separation import separation_properties
from atcs.sim.headway import (
    CYCLE_S,
    TAG_WINDOW_M,
    HeadwayError,
    headway_scenario,
    headway_setting,
    measured_minimum,
    run_options,
    scenario_text,
    sim_limited_gap,
    speed_range_kmh,
    steady_state,
    theoretical_minimum,
)

MODES = ("relative_braking", "brick_wall")
SPEED_KMH = 80
SPEED_MPS = Fraction(SPEED_KMH) / KMH_PER_MPS
RESOURCE_M = 50
SETTLE_SLACK_M = 10
"""How far the measured gap may lie outside the route-locking bracket of :func:`sim_limited_gap` (the report's
one-cycle delay and the tag read's lag, about 2 m each, and the settling)."""
WEAK = dataclasses.replace(seed000_train(), emergency_decelerations_mps2=(Fraction(2) / KMH_PER_MPS,))
"""The follower with half the seed 000 emergency brake (2 km/h/s)."""


@pytest.fixture(scope="module")
def theory():
    return {
        (mode, limit): theoretical_minimum(mode, SPEED_KMH, limit=limit)
        for mode in MODES
        for limit in ("invariant", "atp")
    }


@pytest.fixture(scope="module")
def measured():
    return {mode: measured_minimum(mode, SPEED_KMH, resource_length_m=RESOURCE_M) for mode in MODES}


@pytest.mark.parametrize("mode", MODES)
def test_theoretical_figures_are_ordered(theory, mode):
    invariant, atp = theory[mode, "invariant"], theory[mode, "atp"]
    assert 0 < invariant.gap_m < atp.gap_m
    d = atp.details
    # each curve lies behind the one before it; the EBI keeps the follower where the proved invariant holds
    assert invariant.gap_m <= d["ebi_m"] <= d["sbi_m"] <= d["warning_m"] <= d["permitted_m"] <= d["indication_m"]
    assert atp.gap_m == d["indication_m"] < d["traction_m"]
    for figure in (invariant, atp):
        assert figure.headway_s == pytest.approx((figure.gap_m + 200) / float(SPEED_MPS))
        assert figure.exact_gap_m is not None and float(figure.exact_gap_m) == figure.gap_m


def test_brick_wall_needs_more_than_relative_braking(theory):
    for limit in ("invariant", "atp"):
        bw, rbd = theory["brick_wall", limit], theory["relative_braking", limit]
        assert bw.gap_m > rbd.gap_m
    # the invariant's difference is exactly the leader's stopping distance at its highest deceleration
    credit = theory["relative_braking", "invariant"].details["leader_stopping_m"]
    d_leader = theory["brick_wall", "invariant"].details["leader_max_deceleration_mps2"]
    assert credit == pytest.approx(float(SPEED_MPS) ** 2 / (2 * d_leader))
    assert theory["brick_wall", "invariant"].exact_gap_m - theory[
        "relative_braking", "invariant"
    ].exact_gap_m == pytest.approx(credit, abs=1e-9)


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("front_m", [Fraction(0), Fraction(12345, 10)])
def test_invariant_figure_is_where_sep01_stops_holding(theory, mode, front_m):
    """SEP-01's own predicate, on the worst case at a steady 80 km/h (the follower not braking, the leader's report
    its true state), holds at exactly the figure's gap and fails 1 mm closer, wherever the follower is."""
    setting = headway_setting(headway_scenario(mode, SPEED_KMH))
    short = {"relative_braking": "rbd", "brick_wall": "bw"}[mode]
    properties = separation_properties("headway", setting.data, short)
    sep01 = next(p for p in properties if p.requirement == "SEP-01")
    no_collision = next(p for p in properties if p.requirement == "SEP-02")
    gap = theory[mode, "invariant"].exact_gap_m

    def holds(prop, g):
        state = steady_state(setting.params, g, SPEED_MPS, front_m)
        return bool(prop.holds(EXACT, setting.params, state, None, None, None))

    assert holds(sep01, gap)
    assert not holds(sep01, gap - Fraction(1, 1000))
    assert holds(sep01, gap + 100)
    assert holds(no_collision, gap)


@pytest.mark.slow
@pytest.mark.parametrize("mode", MODES)
def test_measured_gap_settles_between_the_route_locking_phases(theory, measured, mode):
    """The simulator's follower settles no closer than the ATP allows and within one resource of what the theory
    gives for its end of authority's best and worst phases (the first resource its leader holds starting at the
    leader's min safe rear, or one resource behind it)."""
    figure = measured[mode]
    d = figure.details
    assert d["spread_m"] <= 5 and d["held_back_cycles"] > 0 and d["emergency_brakes"] == 0
    assert theory[mode, "invariant"].gap_m < theory[mode, "atp"].gap_m <= figure.gap_m
    best = float(sim_limited_gap(mode, SPEED_KMH, resource_length_m=RESOURCE_M))
    worst = float(sim_limited_gap(mode, SPEED_KMH, locked_behind_m=RESOURCE_M, resource_length_m=RESOURCE_M))
    assert worst == pytest.approx(best + RESOURCE_M, abs=25)
    assert best - SETTLE_SLACK_M <= figure.gap_m <= worst + SETTLE_SLACK_M
    # over the ATP-limited figure: at most a resource and the slack, plus what the ATO's planning and the route
    # locking take (in relative braking, the whole credit for the leader's stopping distance)
    atp = theory[mode, "atp"].gap_m
    assert figure.gap_m - atp <= RESOURCE_M + SETTLE_SLACK_M + (best - atp)
    assert figure.headway_s == pytest.approx((figure.gap_m + 200) / float(SPEED_MPS))


@pytest.mark.slow
def test_weak_follower_brake_moves_every_figure_out_of_the_nominal_bound(theory, measured):
    """The mutant: the follower with half the emergency brake needs more gap by every figure, and its measured gap
    breaks the nominal bound (the check can fail), while staying within its own theory's bracket."""
    mode = "brick_wall"
    for limit in ("invariant", "atp"):
        weak = theoretical_minimum(mode, SPEED_KMH, limit=limit, follower_data=WEAK)
        assert weak.gap_m > theory[mode, limit].gap_m + 100
    # a departure close behind, and a looser settling (its gap drifts over a resource): the figure moves by hundreds
    # of metres
    figure = measured_minimum(
        mode,
        SPEED_KMH,
        resource_length_m=RESOURCE_M,
        follower_data=WEAK,
        duration_s=240,
        settle_m=20,
        follower_depart_s=32,
    )
    nominal_worst = float(sim_limited_gap(mode, SPEED_KMH, locked_behind_m=RESOURCE_M, resource_length_m=RESOURCE_M))
    assert figure.gap_m > measured[mode].gap_m + 100
    assert figure.gap_m > nominal_worst + SETTLE_SLACK_M  # the nominal check rejects it
    weak_best = float(sim_limited_gap(mode, SPEED_KMH, follower_data=WEAK, resource_length_m=RESOURCE_M))
    weak_worst = float(
        sim_limited_gap(mode, SPEED_KMH, locked_behind_m=RESOURCE_M, follower_data=WEAK, resource_length_m=RESOURCE_M)
    )
    assert weak_best - SETTLE_SLACK_M <= figure.gap_m <= weak_worst + SETTLE_SLACK_M


def test_too_short_a_run_has_no_steady_state():
    with pytest.raises(HeadwayError, match="no steady state"):
        measured_minimum("brick_wall", SPEED_KMH, duration_s=30, settle_s=20, follower_depart_s=0)


def test_the_run_scales_with_the_speed_above_80_kmh():
    assert speed_range_kmh() == (65, 350)
    assert (
        run_options(80)
        == run_options(65)
        == {
            "duration_s": 200,
            "max_ma_m": 1500,
            "resource_length_m": 50,
            "settle_m": 5,
            "speed_tolerance_kmh": Fraction(5, 2),
        }
    )
    assert run_options(160) == {
        "duration_s": 400,
        "max_ma_m": 6000,
        "resource_length_m": 100,
        "settle_m": 10,
        "speed_tolerance_kmh": 5,
    }
    scenario = headway_scenario("bw", 80)
    assert (scenario.cycle_s, scenario.tag_window_m) == (CYCLE_S, TAG_WINDOW_M)


@pytest.mark.slow
def test_at_160_kmh_the_measured_gap_settles_between_the_route_locking_phases():
    """Tags are read with the odometer reading at their passage, so the follower runs at 160 km/h (a cycle runs
    1.8 tag windows) with the position checked every cycle, and settles within the route-locking bracket."""
    options = run_options(160)
    figure = measured_minimum("relative_braking", 160, **options)
    resource_m, settle = options["resource_length_m"], options["settle_m"]
    shared = {"resource_length_m": resource_m, "max_ma_m": options["max_ma_m"]}
    best = float(sim_limited_gap("relative_braking", 160, **shared))
    worst = float(sim_limited_gap("relative_braking", 160, locked_behind_m=resource_m, **shared))
    assert figure.details["emergency_brakes"] == 0 and figure.details["held_back_cycles"] > 0
    assert best - 2 * settle <= figure.gap_m <= worst + 2 * settle


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: theoretical_minimum("absolute", 80), "mode must be one of .* got 'absolute'"),
        (lambda: theoretical_minimum("bw", 0), "speed_kmh must be a positive number, got 0"),
        (lambda: theoretical_minimum("bw", "fast"), "speed_kmh must be a positive number, got 'fast'"),
        (lambda: theoretical_minimum("bw", 80, limit="curve"), "limit must be 'invariant' or 'atp', got 'curve'"),
        (lambda: theoretical_minimum("rbd", 80, position_error_m=-1), "position_error_m must be a number >= 0, got -1"),
        (lambda: theoretical_minimum("rbd", 80, follower_data="weak"), "follower_data must be TrainData, got 'weak'"),
        (lambda: theoretical_minimum("rbd", 80, preset="seed009"), "preset must be one of .* got 'seed009'"),
        (lambda: sim_limited_gap("bw", 80, locked_behind_m=-5), "locked_behind_m must be a number >= 0, got -5"),
        (
            lambda: scenario_text("bw", 80, follower_depart_s="soon"),
            "follower_depart_s must be a number >= 0, got 'soon'",
        ),
        (lambda: scenario_text("bw", 80, resource_length_m=0), "resource_length_m must be a positive number, got 0"),
        (lambda: scenario_text("bw", 80, duration_s=100, follower_depart_s=100), "follower_depart_s must lie in"),
        (lambda: measured_minimum("bw", 80, duration_s=60, settle_s=60), "settle_s must be shorter than duration_s"),
        (lambda: measured_minimum("bw", 80, duration_s=100, follower_depart_s=50), "follower_depart_s must lie in"),
        (lambda: measured_minimum("bw", 80, settle_m=-1), "settle_m must be a positive number, got -1"),
    ],
)
def test_argument_errors(call, message):
    with pytest.raises(HeadwayError, match=message):
        call()
