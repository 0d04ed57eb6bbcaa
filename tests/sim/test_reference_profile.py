"""The minimum-running-time reference profile (sim/reference_profile.py): the optimum against the analytic
bang-bang solutions, the ceiling and traction/braking limits kept, the model's indication curve kept
(seed 002 train, 80 km/h), errors, and the ATO's interpolated target speed."""

import dataclasses
import math
from fractions import Fraction

import numpy as np
import pytest

from atcs.model.dynamic_profile import Horizon, curve_speeds_at
from atcs.model.profile import gradient_profile, speed_profile
from atcs.model.restrictions import as_float
from atcs.model.train_data import seed002_train, subset026_national
from atcs.sim.reference_profile import (
    ReferenceProfile,
    ReferenceProfileError,
    atp_ceiling,
    minimum_time_profile,
    reference_profiles,
)

REL = 1e-6
"""Solver accuracy, relative."""


def constant(speed_mps):
    return lambda x_m: speed_mps


def trapezoid_time_s(length_m, ceiling_mps, accel_mps2, decel_mps2):
    """Accelerate at a to V, cruise, brake at b (L long enough to reach V)."""
    assert length_m >= ceiling_mps**2 / 2 * (1 / accel_mps2 + 1 / decel_mps2)
    return length_m / ceiling_mps + ceiling_mps / (2 * accel_mps2) + ceiling_mps / (2 * decel_mps2)


def triangle_peak_mps(length_m, accel_mps2, decel_mps2):
    """Peak speed of accelerate-then-brake over L: E* / a + E* / b = L."""
    return math.sqrt(2 * length_m * accel_mps2 * decel_mps2 / (accel_mps2 + decel_mps2))


def assert_within_limits(p: ReferenceProfile, ceiling, accel_mps2, decel_mps2):
    ceilings = np.array([ceiling(float(x)) for x in p.positions_m])
    assert (p.speeds_mps <= ceilings * (1 + REL) + REL).all()
    assert p.speeds_mps[0] == 0 and p.speeds_mps[-1] == 0
    ds = np.diff(p.positions_m)
    rise = np.diff(p.speeds_mps**2 / 2) / ds
    assert rise.max() <= accel_mps2 * (1 + REL) + REL
    assert -rise.min() <= decel_mps2 * (1 + REL) + REL


# --- against the analytic optimum --------------------------------------------------------------------------


def test_trapezoid_with_corners_on_the_grid_is_exact():
    # V^2/(2a) = 250 m and V^2/(2b) = 200 m are grid points: the continuous optimum is on the grid
    p = minimum_time_profile(constant(20.0), 0.0, 2000.0, accel_mps2=0.8, decel_mps2=1.0, step_m=5.0)
    assert p.solver_status == "optimal"
    assert p.running_time_s == pytest.approx(122.5, rel=REL)
    assert p.speeds_mps.max() == pytest.approx(20.0, rel=REL)
    assert_within_limits(p, constant(20.0), 0.8, 1.0)


@pytest.mark.parametrize(
    ("start_m", "length_m", "v_mps", "a_mps2", "b_mps2"),
    [
        (0.0, 2003.0, 20.0, 0.8, 1.0),
        (1234.5, 1871.0, 80 / 3.6 - 0.5, 3 / 3.6, 3.5 / 3.6),  # seed 002 train, off-grid corners
    ],
)
def test_trapezoid_off_grid_within_a_tenth_of_a_percent(start_m, length_m, v_mps, a_mps2, b_mps2):
    p = minimum_time_profile(constant(v_mps), start_m, start_m + length_m, accel_mps2=a_mps2, decel_mps2=b_mps2)
    exact = trapezoid_time_s(length_m, v_mps, a_mps2, b_mps2)
    assert exact * (1 - REL) <= p.running_time_s <= exact * 1.001  # a grid profile is a feasible profile
    assert p.positions_m[0] == start_m and p.positions_m[-1] == pytest.approx(start_m + length_m)
    assert np.diff(p.positions_m).max() <= 5.0 + 1e-9
    assert_within_limits(p, constant(v_mps), a_mps2, b_mps2)


def test_triangle_when_the_ceiling_is_never_reached():
    # peak where E / a + E / b = 450 m: E = 200, v = 20 m/s at 250 m (a grid point), under the ceiling 25
    p = minimum_time_profile(constant(25.0), 0.0, 450.0, accel_mps2=0.8, decel_mps2=1.0)
    assert triangle_peak_mps(450.0, 0.8, 1.0) == pytest.approx(20.0)
    assert p.running_time_s == pytest.approx(20 / 0.8 + 20 / 1.0, rel=REL)
    assert p.speeds_mps.max() == pytest.approx(20.0, rel=REL)
    assert p.positions_m[np.argmax(p.speeds_mps)] == pytest.approx(250.0)


def test_triangle_off_grid():
    a, b, length = 3 / 3.6, 3.5 / 3.6, 777.0
    peak = triangle_peak_mps(length, a, b)
    p = minimum_time_profile(constant(peak + 5), 0.0, length, accel_mps2=a, decel_mps2=b)
    exact = peak / a + peak / b
    assert exact * (1 - REL) <= p.running_time_s <= exact * 1.001
    assert p.speeds_mps.max() <= peak * (1 + REL)


def test_a_single_zero_ceiling_point_is_a_stop_and_go():
    # grid points only (not conservative): stop at 1000 m and go again, two trapezoids
    def ceiling(x_m):
        return 0.0 if x_m == 1000.0 else 20.0

    p = minimum_time_profile(ceiling, 0.0, 2000.0, accel_mps2=0.8, decel_mps2=1.0, conservative=False)
    assert p.speed_at(1000.0) == 0.0
    assert p.running_time_s == pytest.approx(2 * trapezoid_time_s(1000.0, 20.0, 0.8, 1.0), rel=REL)


def test_running_time_is_recomputed_from_the_speeds():
    p = minimum_time_profile(constant(15.0), 0.0, 900.0, accel_mps2=0.7, decel_mps2=0.9, step_m=7.0)
    ds = np.diff(p.positions_m)
    assert p.running_time_s == pytest.approx(float(np.sum(2 * ds / (p.speeds_mps[:-1] + p.speeds_mps[1:]))))


# --- limits kept -------------------------------------------------------------------------------------------


def stepped(x_m):
    """An MRSP-like ceiling with changes between grid points (5 m grid)."""
    return 20.0 if x_m < 802.5 else 12.0 if x_m < 1302.5 else 25.0


def test_profile_keeps_a_stepped_ceiling_and_the_limits():
    p = minimum_time_profile(stepped, 0.0, 3000.0, accel_mps2=0.8, decel_mps2=1.0)
    assert_within_limits(p, stepped, 0.8, 1.0)
    assert p.speeds_mps.max() == pytest.approx(25.0, rel=REL)


def test_conservative_keeps_the_ceiling_between_grid_points():
    fine = np.arange(0.0, 3000.0, 0.5)
    limit = np.array([stepped(x) for x in fine])
    kept = minimum_time_profile(stepped, 0.0, 3000.0, accel_mps2=0.8, decel_mps2=1.0)
    assert (kept.speed_at(fine) <= limit * (1 + REL)).all()
    loose = minimum_time_profile(stepped, 0.0, 3000.0, accel_mps2=0.8, decel_mps2=1.0, conservative=False)
    assert (loose.speed_at(fine) > limit * (1 + 1e-3)).any()  # grid points only: over the drop at 802.5 m
    assert loose.running_time_s < kept.running_time_s < loose.running_time_s * 1.01


def test_unlimited_ceiling_is_bounded_by_traction_and_braking():
    p = minimum_time_profile(constant(math.inf), 0.0, 450.0, accel_mps2=0.8, decel_mps2=1.0)
    assert p.running_time_s == pytest.approx(45.0, rel=REL)


# --- the model's ceiling: seed 002 train, 80 km/h, a stop 2 km away ------------------------------------------


def float_record(record):
    return dataclasses.replace(
        record,
        **{
            f.name: (tuple(map(float, v)) if isinstance(v, tuple) else float(v) if isinstance(v, Fraction) else v)
            for f in dataclasses.fields(record)
            for v in [getattr(record, f.name)]
        },
    )


TRAIN, NATIONAL = seed002_train(), subset026_national()
STOP_M, EOA_M = 2000.0, 2050.0
HORIZON = Horizon(
    mrsp=speed_profile("mrsp", [0], [80], 5000),
    gradient=gradient_profile("gradient", [0], [0], 5000),
    eoa_m=Fraction(2050),
    eoa_speed_mps=Fraction(0),
)
ACCEL = float(TRAIN.max_acceleration_mps2)
DECEL = float(TRAIN.service_decelerations_mps2[0])


def indication_mps(x_m):
    """The indication curve at ``x_m``, straight from the model on floats."""
    horizon = Horizon(as_float(HORIZON.mrsp), as_float(HORIZON.gradient), EOA_M, 0.0)
    return curve_speeds_at(float_record(TRAIN), float_record(NATIONAL), horizon, x_m, ACCEL).indication_mps


@pytest.fixture(scope="module")
def station_run():
    return minimum_time_profile(atp_ceiling(TRAIN, NATIONAL, HORIZON), 0.0, STOP_M, accel_mps2=ACCEL, decel_mps2=DECEL)


def test_model_profile_stays_under_the_indication_curve_at_grid_points(station_run):
    p = station_run
    curve = np.array([indication_mps(float(x)) for x in p.positions_m])
    assert (p.speeds_mps <= curve - np.minimum(0.5, curve / 2) + 1e-9).all()
    assert p.speeds_mps.max() == pytest.approx(80 / 3.6 - 0.5, rel=REL)
    assert_within_limits(p, lambda x: 80 / 3.6, ACCEL, DECEL)


def test_model_profile_stays_under_the_indication_curve_between_grid_points(station_run):
    p = station_run
    mids = (p.positions_m[:-2] + p.positions_m[1:-1]) / 2  # all steps but the last (standstill at the stop)
    mids = mids[mids > 1000.0]  # where the curve bends
    curve = np.array([indication_mps(float(x)) for x in mids])
    assert (p.speed_at(mids) <= curve).all()


def test_model_profile_costs_time_only_near_the_stop(station_run):
    flat = trapezoid_time_s(STOP_M, 80 / 3.6 - 0.5, ACCEL, DECEL)
    assert flat < station_run.running_time_s < flat + 30


def test_atp_ceiling_takes_the_margin_and_the_curve():
    plain = atp_ceiling(TRAIN, NATIONAL, HORIZON, margin_mps=0.0)
    assert plain(100.0) == pytest.approx(80 / 3.6)
    assert atp_ceiling(TRAIN, NATIONAL, HORIZON, margin_mps=1.0)(100.0) == pytest.approx(80 / 3.6 - 1)
    near = indication_mps(1990.0)
    assert plain(1990.0) == pytest.approx(near, abs=1e-4) and plain(1990.0) <= near
    assert atp_ceiling(TRAIN, NATIONAL, HORIZON)(1990.0) == pytest.approx(plain(1990.0) - 0.5, abs=1e-4)
    assert atp_ceiling(TRAIN, NATIONAL, HORIZON, curve="permitted", margin_mps=0.0)(1990.0) > near
    assert plain(EOA_M) == 0.0


# --- consecutive stops --------------------------------------------------------------------------------------


def test_reference_profiles_one_per_stretch():
    asked = []

    def ceiling_for(start_m, stop_m):
        asked.append((start_m, stop_m))
        return constant(20.0)

    profiles = reference_profiles([0, 1000, 2500], ceiling_for, accel_mps2=0.8, decel_mps2=1.0)
    assert asked == [(0.0, 1000.0), (1000.0, 2500.0)]
    assert [p.running_time_s for p in profiles] == pytest.approx(
        [trapezoid_time_s(1000.0, 20.0, 0.8, 1.0), trapezoid_time_s(1500.0, 20.0, 0.8, 1.0)], rel=REL
    )
    assert profiles[1].positions_m[0] == 1000.0 and profiles[1].positions_m[-1] == 2500.0


# --- errors ---------------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("kwargs", "names"),
    [
        ({"stop_m": 0.0}, "stop_m"),
        ({"stop_m": -5.0}, "stop_m"),
        ({"start_m": math.nan}, "start_m"),
        ({"stop_m": math.inf}, "stop_m"),
        ({"step_m": 0.0}, "step_m"),
        ({"step_m": -1.0}, "step_m"),
        ({"accel_mps2": 0.0}, "accel_mps2"),
        ({"accel_mps2": math.nan}, "accel_mps2"),
        ({"decel_mps2": -1.0}, "decel_mps2"),
        ({"decel_mps2": "1"}, "decel_mps2"),
        ({"ceiling_mps": 20.0}, "ceiling_mps"),
        ({"ceiling_mps": constant(-1.0)}, "ceiling_mps"),
        ({"ceiling_mps": constant(math.nan)}, "ceiling_mps"),
    ],
)
def test_bad_arguments_name_the_argument_and_value(kwargs, names):
    args = {
        "ceiling_mps": constant(20.0),
        "start_m": 0.0,
        "stop_m": 1000.0,
        "accel_mps2": 0.8,
        "decel_mps2": 1.0,
        "step_m": 5.0,
        **kwargs,
    }
    with pytest.raises(ValueError, match=names) as err:
        minimum_time_profile(**args)
    bad = next(iter(kwargs.values()))
    if not callable(bad):
        assert repr(bad) in str(err.value)


@pytest.mark.parametrize("conservative", [True, False])
def test_zero_ceiling_stretch_is_infeasible(conservative):
    def blocked(x_m):
        return 0.0 if 900 <= x_m <= 1100 else 20.0

    with pytest.raises(ReferenceProfileError, match="status 'infeasible'") as err:
        minimum_time_profile(blocked, 0.0, 2000.0, accel_mps2=0.8, decel_mps2=1.0, conservative=conservative)
    assert err.value.status == "infeasible"
    assert (err.value.start_m, err.value.stop_m) == (0.0, 2000.0)
    assert "0 .. stop_m = 2000" in str(err.value)


def test_a_solver_status_other_than_optimal_is_an_error():
    # a 1 mm/s crawl over 200 m: the solver only gets an inaccurate answer, which must not come back as a profile
    def crawl(x_m):
        return 1e-6 if 900 <= x_m <= 1100 else 20.0

    with pytest.raises(ReferenceProfileError) as err:
        minimum_time_profile(crawl, 100.0, 2000.0, accel_mps2=0.8, decel_mps2=1.0)
    assert err.value.status != "optimal"
    assert f"status {err.value.status!r}" in str(err.value) and "start_m = 100 .. stop_m = 2000" in str(err.value)


def test_bad_stops_and_ceiling_options():
    with pytest.raises(ValueError, match=r"stops_m\[2\] = 500"):
        reference_profiles([0, 1000, 500], lambda a, b: constant(20.0), accel_mps2=0.8, decel_mps2=1.0)
    with pytest.raises(ValueError, match="at least two"):
        reference_profiles([0], lambda a, b: constant(20.0), accel_mps2=0.8, decel_mps2=1.0)
    with pytest.raises(ValueError, match=r"curve must be one of .* got 'brake'"):
        atp_ceiling(TRAIN, NATIONAL, HORIZON, curve="brake")
    with pytest.raises(ValueError, match=r"margin_mps must be >= 0, got -0\.1"):
        atp_ceiling(TRAIN, NATIONAL, HORIZON, margin_mps=-0.1)


# --- the ATO's target speed -----------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def triangle():
    return minimum_time_profile(constant(25.0), 0.0, 450.0, accel_mps2=0.8, decel_mps2=1.0)


def test_speed_at_grid_points_is_the_profile(triangle):
    for x, v in zip(triangle.positions_m[::7], triangle.speeds_mps[::7], strict=True):
        assert triangle.speed_at(float(x)) == pytest.approx(v, abs=1e-12)


def test_speed_at_is_linear_in_energy_between_grid_points(triangle):
    p = triangle
    mids = (p.positions_m[:-1] + p.positions_m[1:]) / 2
    expected = np.sqrt((p.speeds_mps[:-1] ** 2 + p.speeds_mps[1:] ** 2) / 2)
    assert p.speed_at(mids) == pytest.approx(expected, abs=1e-9)
    # constant acceleration from standstill: v = sqrt(2 a x) anywhere in the traction phase, not only at grid points
    for x in (1.0, 2.5, 13.7, 249.9):
        assert p.speed_at(x) == pytest.approx(math.sqrt(2 * 0.8 * x), rel=1e-5)


def test_speed_at_is_standstill_outside_and_rejects_nan(triangle):
    assert triangle.speed_at(-1.0) == 0.0 and triangle.speed_at(451.0) == 0.0
    assert isinstance(triangle.speed_at(100.0), float)
    assert triangle.speed_at(np.array([-1.0, 100.0])).shape == (2,)
    with pytest.raises(ValueError, match="x_m must be a number, got nan"):
        triangle.speed_at(math.nan)
