"""The dynamic speed profile over the horizon (seed 000 §2.4): targets from the MRSP and the MA, the most
restrictive curve, the speed-at-a-location query and the sampled curves agree with the braking curves
they are built from, on both concrete backends."""

import itertools
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from atcs.model.curves import FAR_M, Target, curve_locations
from atcs.model.dynamic_profile import (
    CURVE_NAMES,
    Horizon,
    ceilings,
    curve_speeds_at,
    ebd_foot_mps,
    supervise_position,
    supervised_targets,
)
from atcs.model.ops.exact import EXACT
from atcs.model.ops.floating import FLOAT
from atcs.model.profile import KMH_PER_MPS, gradient_profile, speed_profile
from atcs.model.restrictions import as_float
from atcs.model.train_data import seed000_train, seed002_national, seed002_train, subset026_national
from atcs.sim.plots import sampled_curves

TRAIN, NATIONAL = seed000_train(), subset026_national()
MRSP = speed_profile("MRSP", [0, 600, 900, 1200], [80, 60, 70, 40], 2000)
GRADIENT = gradient_profile("gradient", [0, 500, 1100], [0, -10, 5], 2000)
HORIZON = Horizon(MRSP, GRADIENT, Fraction(1500), Fraction(0))
A_EST = Fraction(1)


def _kmh(v):
    return Fraction(v) / KMH_PER_MPS


# --- targets -------------------------------------------------------------------------------------


def test_targets_are_the_speed_decreases_ahead_and_the_end_of_authority():
    targets = supervised_targets(EXACT, NATIONAL, HORIZON, Fraction(100))
    assert [(t.location_m, t.speed_mps) for t in targets] == [
        (600, _kmh(60)),
        (1200, _kmh(40)),
        (1500, 0),
    ]  # the rise to 70 km/h at 900 m is no target
    assert targets[0].ebd_foot_mps == _kmh(60) + NATIONAL.dv_ebi_min_mps  # V_target + dV_ebi(V_target)
    assert targets[-1].ebd_foot_mps == 0


def test_a_decrease_at_or_behind_the_max_safe_front_is_left_to_the_ceiling():
    targets = supervised_targets(EXACT, NATIONAL, HORIZON, Fraction(600))
    assert [t.location_m for t in targets] == [1200, 1500]


def test_decreases_beyond_the_end_of_authority_are_not_targets():
    short = Horizon(MRSP, GRADIENT, Fraction(1000), Fraction(0))
    assert [t.location_m for t in supervised_targets(EXACT, NATIONAL, short, Fraction(0))] == [600, 1000]


def test_the_ma_target_speed_is_the_eoa_targets():
    """An EoA at standstill is the SvL: its EBD ends at 0 there (Subset-026 §3.13.8.3.2); one with a target speed
    (a limit of authority) is a speed decrease: its EBD passes V_target + dV_ebi at it (§3.13.8.3.1)."""
    radio = Horizon(MRSP, GRADIENT, Fraction(1500), _kmh(20))
    eoa = supervised_targets(EXACT, NATIONAL, radio, Fraction(0))[-1]
    assert (eoa.speed_mps, eoa.ebd_foot_mps) == (_kmh(20), _kmh(20) + NATIONAL.dv_ebi_min_mps)
    svl = supervised_targets(EXACT, NATIONAL, Horizon(MRSP, GRADIENT, Fraction(1500), Fraction(0)), Fraction(0))[-1]
    assert (svl.speed_mps, svl.ebd_foot_mps) == (0, 0)


def test_every_curve_of_a_limit_of_authority_ends_at_its_speed():
    """With the EoA at 20 km/h, no curve falls under 20 km/h before it (neither the forward query nor the plot)."""
    radio = Horizon(as_float(MRSP), as_float(GRADIENT), 1500.0, float(_kmh(20)))
    for x_m in (1400.0, 1480.0, 1499.0):
        speeds = curve_speeds_at(TRAIN, NATIONAL, radio, x_m, 1.0)
        assert all(getattr(speeds, f"{name}_mps") >= float(_kmh(20)) - 1e-5 for name in CURVE_NAMES), (x_m, speeds)
    sampled = sampled_curves(TRAIN, NATIONAL, radio, 0.0, 1.0)
    assert all(np.all(sampled.speeds_mps[name] >= float(_kmh(20)) - 1e-9) for name in CURVE_NAMES)


def test_ebd_foot_follows_the_speed_dependent_dv_ebi():
    n = seed002_national()
    for v in (Fraction(0), _kmh(100), _kmh(300)):
        assert ebd_foot_mps(EXACT, n, v) - v == ceilings(EXACT, n, v).ebi_mps - v


# --- the most restrictive curve at the train's position ------------------------------------------


@settings(max_examples=40)
@given(front_m=st.integers(0, 1499), speed_kmh=st.integers(0, 100))
def test_each_curve_is_the_nearest_targets(front_m, speed_kmh):
    front, speed = Fraction(front_m), _kmh(speed_kmh)
    _, curve, _ = supervise_position(EXACT, TRAIN, NATIONAL, HORIZON, front, speed, A_EST)
    singles = [
        curve_locations(EXACT, TRAIN, NATIONAL, GRADIENT, t, speed, A_EST)
        for t in supervised_targets(EXACT, NATIONAL, HORIZON, front)
    ]
    for name in CURVE_NAMES:
        assert getattr(curve, f"{name}_m") == min(getattr(c, f"{name}_m") for c in singles)


@settings(max_examples=40)
@given(front_m=st.integers(0, 1499), speed_kmh=st.integers(0, 100))
def test_float_and_exact_backends_agree_on_the_exceedances(front_m, speed_kmh):
    over_exact, curve, _ = supervise_position(
        EXACT, TRAIN, NATIONAL, HORIZON, Fraction(front_m), _kmh(speed_kmh), A_EST
    )
    over_float, _, _ = supervise_position(
        FLOAT, TRAIN, NATIONAL, _float_horizon(), float(front_m), float(_kmh(speed_kmh)), 1.0
    )
    near_a_curve = any(abs(getattr(curve, f"{name}_m") - front_m) < Fraction(1, 1000) for name in CURVE_NAMES)
    if not near_a_curve:  # rounding may tip a comparison within a millimetre of a curve
        assert over_float == over_exact


def test_a_train_on_a_fast_approach_is_over_the_ebi():
    over, curve, _ = supervise_position(EXACT, TRAIN, NATIONAL, HORIZON, Fraction(560), _kmh(80), A_EST)
    assert over.over_ebi and curve.ebi_m < 560


def test_the_ceilings_supervise_the_mrsp_at_the_front():
    over, _, ceiling = supervise_position(EXACT, TRAIN, NATIONAL, HORIZON, Fraction(700), _kmh(64), A_EST)
    assert ceiling.permitted_mps == _kmh(60)
    assert over.over_permitted and not over.over_ebi


def _float_horizon():
    return Horizon(as_float(MRSP), as_float(GRADIENT), 1500.0, 0.0)


# --- speed of each curve at a location, and the sampled curves -----------------------------------


@pytest.mark.parametrize("x_m", [0, 450, 590, 1000, 1190, 1450, 1499])
def test_curve_speed_is_the_highest_speed_not_over_the_curve(x_m):
    x = Fraction(x_m)
    tolerance = Fraction(1, 1000)
    speeds = curve_speeds_at(TRAIN, NATIONAL, HORIZON, x, A_EST, o=EXACT, tolerance_mps=tolerance)
    ceiling = ceilings(EXACT, NATIONAL, MRSP.values[max(j for j, s in enumerate(MRSP.starts_m) if s <= x)])
    targets = supervised_targets(EXACT, NATIONAL, HORIZON, x)

    def location(name, v):
        return min(
            getattr(curve_locations(EXACT, TRAIN, NATIONAL, GRADIENT, t, v, A_EST), f"{name}_m") for t in targets
        )

    caps = {"ebd": ceiling.ebi_mps, "ebi": ceiling.ebi_mps, "sbi": ceiling.sbi_mps, "warning": ceiling.warning_mps}
    for name in CURVE_NAMES:
        v = getattr(speeds, f"{name}_mps")
        assert v <= caps.get(name, ceiling.permitted_mps)
        assert v == 0 or location(name, v) >= x
        if v < caps.get(name, ceiling.permitted_mps):
            assert location(name, v + 2 * tolerance) < x


def test_curves_are_ordered_at_every_sampled_position():
    sampled = sampled_curves(TRAIN, NATIONAL, _float_horizon(), 0.0, 1.0)
    order = [sampled.speeds_mps[name] for name in reversed(CURVE_NAMES)]  # indication first
    for lower, higher in itertools.pairwise(order):
        assert np.all(lower <= higher + 1e-9)
    assert np.all(sampled.speeds_mps["permitted"] <= sampled.mrsp_mps + 1e-9)


@pytest.mark.parametrize("x_m", [300.0, 590.0, 1000.0, 1190.0, 1450.0])
def test_sampled_curves_match_the_point_query(x_m):
    sampled = sampled_curves(TRAIN, NATIONAL, _float_horizon(), 0.0, 1.0, samples=1501)
    i = int(np.argmin(np.abs(sampled.positions_m - x_m)))
    point = curve_speeds_at(TRAIN, NATIONAL, _float_horizon(), float(sampled.positions_m[i]), 1.0)
    for name in CURVE_NAMES:
        assert sampled.speeds_mps[name][i] == pytest.approx(getattr(point, f"{name}_mps"), abs=0.15), name


def test_a_seed002_train_gets_its_own_curves():
    t2 = seed002_train()
    s0 = curve_speeds_at(TRAIN, NATIONAL, _float_horizon(), 1400.0, 1.0)
    s2 = curve_speeds_at(t2, seed002_national(), _float_horizon(), 1400.0, 1.0)
    assert s2.ebd_mps > s0.ebd_mps  # EB 4.5 km/h/s against 4.0


def test_curves_never_constrain_a_speed_under_the_target():
    target = Target(Fraction(600), _kmh(60), _kmh(60) + NATIONAL.dv_ebi_min_mps)
    assert curve_locations(EXACT, TRAIN, NATIONAL, GRADIENT, target, _kmh(50), A_EST).ebd_m == FAR_M


# --- bad arguments ---------------------------------------------------------------------------------


def test_bad_query_arguments_are_named():
    with pytest.raises(ValueError, match="tolerance_mps must be positive, got 0"):
        curve_speeds_at(TRAIN, NATIONAL, HORIZON, Fraction(0), A_EST, o=EXACT, tolerance_mps=0)
    with pytest.raises(ValueError, match="samples and speed_steps must be at least 2, got 1"):
        sampled_curves(TRAIN, NATIONAL, _float_horizon(), 0.0, 1.0, samples=1)
    with pytest.raises(ValueError, match=r"from_m must lie before the end of authority 1500 m, got 1600\.0"):
        sampled_curves(TRAIN, NATIONAL, _float_horizon(), 1600.0, 1.0)
