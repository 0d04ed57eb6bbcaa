"""Supervision on preprocessed curves (:mod:`atcs.model.prepared_curves`) gives what the direct walk gives, on
floats and on exact numbers, its two shortcuts included; the tables are kept while only the EoA moves."""

from dataclasses import replace
from fractions import Fraction

import numpy as np
import pytest

from atcs.model import prepared_curves
from atcs.model.dynamic_profile import Horizon, supervise_position
from atcs.model.ops.exact import EXACT
from atcs.model.ops.floating import FLOAT
from atcs.model.prepared_curves import prepare_horizon, supervise_prepared
from atcs.model.profile import Profile
from atcs.model.train_data import seed000_train, subset026_national
from atcs.proofs.bench.cycle import _floats, synthetic_horizon

TRAIN, NATIONAL = seed000_train(), subset026_national()
TRAIN_F, NATIONAL_F = _floats(TRAIN), _floats(NATIONAL)


def _both(o, t, n, horizon, front_m, speed_mps, a_est_mps2):
    direct = supervise_position(o, t, n, horizon, front_m, speed_mps, a_est_mps2)
    prepared = supervise_prepared(o, t, n, prepare_horizon(o, t, n, horizon), front_m, speed_mps, a_est_mps2)
    return direct, prepared


@pytest.mark.parametrize("segments", [1, 5, 20, 80])
def test_the_same_supervision_on_floats(segments):
    rng = np.random.default_rng(segments)
    for _ in range(40):
        horizon = synthetic_horizon(rng, segments)
        front, speed = float(rng.uniform(-50, 1550)), float(rng.uniform(0, 30))
        a_est = float(rng.choice([-0.5, 0.0, 0.8]))
        direct, prepared = _both(FLOAT, TRAIN_F, NATIONAL_F, horizon, front, speed, a_est)
        assert prepared == direct, (segments, front, speed, a_est)


def _exact(profile: Profile) -> Profile:
    return Profile(
        tuple(Fraction(x) for x in profile.starts_m), tuple(Fraction(v) for v in profile.values), profile.end_m
    )


def test_the_same_supervision_on_exact_numbers():
    rng = np.random.default_rng(7)
    for _ in range(10):
        h = synthetic_horizon(rng, 12)
        horizon = Horizon(_exact(h.mrsp), _exact(h.gradient), Fraction(h.eoa_m), Fraction(0))
        front, speed = Fraction(int(rng.integers(0, 1400))), Fraction(int(rng.integers(0, 250)), 10)
        direct, prepared = _both(EXACT, TRAIN, NATIONAL, horizon, front, speed, Fraction(4, 5))
        assert prepared == direct


def test_set_aside_targets_are_looked_up_when_nothing_else_constrains():
    """At standstill braking (no curve of any target below FAR_M, less D_bec), every target set aside is looked up
    in the end, so the curves are the direct walk's to the last digit."""
    horizon = synthetic_horizon(np.random.default_rng(3), 20)
    direct, prepared = _both(FLOAT, TRAIN_F, NATIONAL_F, horizon, 10.0, 0.0, -1.0)
    assert prepared == direct and direct[1].ebd_m == prepared_curves.FAR_M


def test_the_walk_over_targets_stops_early(monkeypatch):
    """The nearest constraint found, the targets beyond a braking distance of it are not looked up."""
    looked_up = []
    real = prepared_curves.prepared_curve_locations
    monkeypatch.setattr(prepared_curves, "prepared_curve_locations", lambda *a: looked_up.append(a[3]) or real(*a))
    horizon = synthetic_horizon(np.random.default_rng(11), 80)
    prepared = prepare_horizon(FLOAT, TRAIN_F, NATIONAL_F, horizon)
    supervise_prepared(FLOAT, TRAIN_F, NATIONAL_F, prepared, 0.0, 20.0, 0.8)
    assert 0 < len(looked_up) < len(prepared.targets)


def test_tables_kept_while_only_the_eoa_moves():
    horizon = synthetic_horizon(np.random.default_rng(5), 20)
    first = prepare_horizon(FLOAT, TRAIN_F, NATIONAL_F, horizon)
    moved = prepare_horizon(FLOAT, TRAIN_F, NATIONAL_F, replace(horizon, eoa_m=horizon.eoa_m - 30), reuse=first)
    assert moved.tables[:-1] == first.tables[:-1] and all(
        a is b for a, b in zip(moved.tables[:-1], first.tables[:-1], strict=True)
    )
    assert moved.tables[-1] != first.tables[-1]  # the EoA's own, walked again
