"""Supervision on preprocessed curves (:mod:`atcs.model.prepared_curves`) gives what the direct walk gives, on
floats and on exact numbers; an envelope's least is the least over its targets at every speed, from few of them;
the tables are kept while only the EoA moves."""

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


def test_the_same_supervision_at_standstill_braking():
    """No curve of any target below FAR_M: every envelope's least is FAR_M, as the direct walk's."""
    horizon = synthetic_horizon(np.random.default_rng(3), 20)
    direct, prepared = _both(FLOAT, TRAIN_F, NATIONAL_F, horizon, 10.0, 0.0, -1.0)
    assert prepared == direct and direct[1].ebd_m == prepared_curves.FAR_M


def _exact_horizon(seed: int, segments: int) -> Horizon:
    h = synthetic_horizon(np.random.default_rng(seed), segments)
    return Horizon(_exact(h.mrsp), _exact(h.gradient), Fraction(h.eoa_m), Fraction(0))


def _least_everywhere(envelope, speeds) -> bool:
    return all(
        prepared_curves.envelope_location_m(EXACT, envelope, u)
        == min(
            prepared_curves.tabled_ebd_location_m(EXACT, g, table, u)
            for g, table in zip(envelope.targets, envelope.tables, strict=True)
        )
        for u in speeds
    )


SPEEDS = (*(Fraction(k, 8) for k in range(0, 8 * 40)), Fraction(1000))
"""Every eighth of a m/s to 40 m/s (the grid's edges and the bands' insides), and one far above the grid."""


def test_an_envelope_is_the_least_of_its_targets_at_every_speed():
    prepared = prepare_horizon(EXACT, TRAIN, NATIONAL, _exact_horizon(13, 12))
    ahead = prepared_curves.targets_ahead(EXACT, prepared, 0)
    assert len(ahead.every.targets) > 3
    assert _least_everywhere(ahead.every, SPEEDS)
    assert all(_least_everywhere(e, SPEEDS[::7]) for e in (*ahead.alike, *ahead.alone))


def test_a_band_keeping_only_the_nearest_at_its_bottom_is_caught(monkeypatch):
    """Where two targets' curves cross inside a band, the band must keep both: the rule narrowed to the nearest
    at the band's bottom gives a wrong least, and the check above sees it."""
    monkeypatch.setattr(prepared_curves, "envelope_band", lambda o, bottom, top, slack: (bottom.index(min(bottom)),))
    prepared = prepare_horizon(EXACT, TRAIN, NATIONAL, _exact_horizon(13, 12))
    assert not _least_everywhere(prepared_curves.targets_ahead(EXACT, prepared, 0).every, SPEEDS)


def test_a_band_keeps_every_target_that_can_be_nearest_in_it():
    # at the bottom target 1 is nearest; at the top target 0 is within its reach, target 2 is not
    assert prepared_curves.envelope_band(EXACT, (5, 3, 9), (1, 2, 8), Fraction(0)) == (1, 0)
    # below every foot (FAR_M at the top): the first, wherever the others are
    far = prepared_curves.FAR_M
    assert prepared_curves.envelope_band(EXACT, (far, far), (far, far), Fraction(0)) == (0,)


def test_envelopes_keep_few_targets_per_band():
    horizon = synthetic_horizon(np.random.default_rng(11), 80)
    prepared = prepare_horizon(FLOAT, TRAIN_F, NATIONAL_F, horizon)
    every = prepared_curves.targets_ahead(FLOAT, prepared, 0).every
    kept = [len(band) for band in every.nearest]
    assert len(every.targets) > 10 and sum(kept) / len(kept) < 2


def test_tables_kept_while_only_the_eoa_moves():
    horizon = synthetic_horizon(np.random.default_rng(5), 20)
    first = prepare_horizon(FLOAT, TRAIN_F, NATIONAL_F, horizon)
    moved = prepare_horizon(FLOAT, TRAIN_F, NATIONAL_F, replace(horizon, eoa_m=horizon.eoa_m - 30), reuse=first)
    assert moved.tables[:-1] == first.tables[:-1] and all(
        a is b for a, b in zip(moved.tables[:-1], first.tables[:-1], strict=True)
    )
    assert moved.tables[-1] != first.tables[-1]  # the EoA's own, walked again
