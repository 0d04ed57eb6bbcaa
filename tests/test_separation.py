"""Two trains never collide in brick-wall mode (seed 001 §3.2 Fig. 6): proved for the presets, falsified on
mutants (each counterexample replays), on a coarse-cycle variant of seed 000 as in test_closed_loop.py."""

import dataclasses
from fractions import Fraction

import pytest

from atcs.model import separation
from atcs.model.train_data import seed000_train, subset026_national
from atcs.proofs.engine import prove
from atcs.proofs.mutants import patched
from atcs.proofs.trace import replay, reproduce
from atcs.properties import PROPERTIES, select
from atcs.properties.closed_loop import preset_data
from atcs.properties.separation import separation_properties

SEPARATION_PROPERTIES = select("separation.*")

COARSE = {p.name: p for p in separation_properties("coarse", {
    **preset_data(dataclasses.replace(seed000_train(), t_be_s=Fraction(8, 5)), subset026_national(),
                  cycle_s=Fraction(4, 5)),
})}


def _kind(name):
    return name.removeprefix("separation.").rsplit("_", 1)[0]


_BEST = "o.max(s.best_rear_m, i.report_rear_m)"
_EOA = "best - p.safety_margin_m"

# property kind -> mutants (function, text in it, faulty replacement)
MUTANTS = {
    # the leader's reported front taken for its rear
    "report_behind_leader": [(separation.follower_eoa_m, _BEST, "o.max(s.best_rear_m, i.report_rear_m + "
                                                                  "p.train_length_m)")],
    "braking_invariant_bw": [(separation.follower_eoa_m, _EOA, "best")],
    "no_collision_bw": [
        # no safety margin before the leader's rear
        (separation.follower_eoa_m, _EOA, "best"),
        # the leader's reported front taken for its rear: a collision
        (separation.follower_eoa_m, _BEST, "o.max(s.best_rear_m, i.report_rear_m + p.train_length_m)"),
        # the latest report trusted over the best one (a late report overtaken by a newer one lowers nothing, but
        # here a report is taken as it comes)
        (separation.follower_eoa_m, _BEST, "i.report_rear_m + p.safety_margin_m"),
    ],
}


def test_every_separation_property_has_a_mutant():
    assert {_kind(p.name) for p in SEPARATION_PROPERTIES} == set(MUTANTS)


@pytest.fixture(scope="module")
def proved_results():
    registry = {**PROPERTIES, **COARSE}
    shared = {}
    return {prop.name: shared.get(prop.name) or prove(prop, timeout_s=300, lemmas=registry, proved=shared)
            for prop in (*SEPARATION_PROPERTIES, *COARSE.values())}


@pytest.mark.parametrize("name", [*(p.name for p in SEPARATION_PROPERTIES), *COARSE], ids=str)
def test_proved(proved_results, name):
    result = proved_results[name]
    assert (result.status, result.engine) == ("proved", "k-induction"), result.message


@pytest.mark.parametrize(
    ("name", "mutant"),
    [(name, m) for name in COARSE for m in MUTANTS[_kind(name)]],
    ids=lambda v: v if isinstance(v, str) else v[2][:40],
)
def test_mutant_falsified_and_counterexample_replays(name, mutant):
    prop = dataclasses.replace(COARSE[name], lemmas=())
    function, old, new = mutant
    with patched(function, old, new):
        result = prove(prop, timeout_s=300, max_k=12)
        assert result.status == "falsified", result.message
        assert reproduce(prop, result.trace).first_violation == result.k
    real = replay(prop, result.trace)
    assert real.problems or real.first_violation is None, "the real model must not fail on the mutant's run"
