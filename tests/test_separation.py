"""Two trains (seed 001 §3.2 Fig. 6): brick-wall separation proved for the presets; relative braking's lemmas
proved; every property falsified on a mutant (each counterexample replays) on a coarse-cycle variant of seed 000
as in test_closed_loop.py; the leader's stopping point computed with a guaranteed deceleration gives a collision,
kept as a regression example."""

import dataclasses
import json
from fractions import Fraction
from pathlib import Path

import pytest

from atcs.model import separation
from atcs.model.train_data import seed000_train, subset026_national
from atcs.proofs.engine import prove
from atcs.proofs.mutants import mutant_property, patched
from atcs.proofs.trace import from_json, replay, reproduce, to_json
from atcs.properties import PROPERTIES, select
from atcs.properties.closed_loop import preset_data
from atcs.properties.separation import PENDING, separation_properties

SEPARATION_PROPERTIES = select("separation.*")

COARSE_DATA = preset_data(dataclasses.replace(seed000_train(), t_be_s=Fraction(8, 5)), subset026_national(),
                          cycle_s=Fraction(4, 5))
COARSE = {p.name: p for mode in ("bw", "rbd") for p in separation_properties("coarse", COARSE_DATA, mode)
          if not p.name.startswith(("separation.braking_invariant_rbd", "separation.no_collision_rbd"))}
COARSE_RBD_COLLISION = next(p for p in separation_properties("coarse", COARSE_DATA, "rbd")
                            if p.name == "separation.no_collision_rbd_coarse")

REGRESSION = Path(__file__).parent / "regression" / "falsified" / "leader_guaranteed_deceleration.json"


def _kind(name):
    return name.removeprefix("separation.").rsplit("_", 1)[0]


_BEST = "o.max(s.best_rear_m, i.report_rear_m)"
_EOA = "o.ite(certain_only, rear, stop) - p.safety_margin_m"
_REPORT_STOP = "stopping_point_m(o, p, i.report_rear_m, i.report_speed_mps)"
# the fault: the leader's stopping point computed with a guaranteed deceleration (here the follower's own,
# about 0.8 m/s^2) instead of the leader's highest (3 m/s^2)
GUARANTEED = (separation.follower_eoa_m, _REPORT_STOP,
              "i.report_rear_m + i.report_speed_mps * i.report_speed_mps"
              " / (o.const(2) * p.guaranteed_deceleration_mps2)")

# property kind -> mutants (function, text in it, faulty replacement)
MUTANTS = {
    # the leader's reported front taken for its rear
    "reports_behind_leader_bw": [(separation.follower_eoa_m, _BEST, f"{_BEST} + p.train_length_m")],
    "braking_invariant_bw": [(separation.follower_eoa_m, _EOA, "o.ite(certain_only, rear, stop)")],
    "no_collision_bw": [
        # no safety margin before the leader's rear
        (separation.follower_eoa_m, _EOA, "o.ite(certain_only, rear, stop)"),
        # the leader's reported front taken for its rear: a collision
        (separation.follower_eoa_m, _BEST, f"{_BEST} + p.train_length_m"),
        # the latest report trusted as it comes, with no bound kept
        (separation.follower_eoa_m, _BEST, "i.report_rear_m + p.safety_margin_m"),
    ],
    "reports_behind_leader_rbd": [GUARANTEED],
    # the leader's stopping distance computed with half its highest deceleration
    "leader_stop_is_earliest": [(separation.stopping_point_m, "(o.const(2) * deceleration)", "deceleration")],
    # the ghost stopping point taken from the rear before this cycle's motion
    "leader_stop_never_recedes": [(
        separation.two_train_step,
        "stopping_point_m(o, p, s.leader_rear_m + i.leader_distance_m, i.leader_next_speed_mps)",
        "stopping_point_m(o, p, s.leader_rear_m, i.leader_next_speed_mps)",
    )],
}


def test_every_separation_property_has_a_mutant():
    assert {_kind(p.name) for p in SEPARATION_PROPERTIES} == set(MUTANTS)
    assert {_kind(p.name) for p in COARSE.values()} == set(MUTANTS)


def test_pending_relative_braking_claims_are_not_registered():
    assert {p.name for p in PENDING} == {f"separation.{k}_rbd_{preset}" for k in ("braking_invariant", "no_collision")
                                         for preset in ("seed000", "seed002")}
    assert not set(PROPERTIES) & {p.name for p in PENDING}


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


def _falsify(prop, mutant, max_k=12):
    function, old, new = mutant
    if function is prop.node.step:
        mutated = mutant_property(prop, old, new)
        result = prove(mutated, timeout_s=300, max_k=max_k)
        return mutated, result
    with patched(function, old, new):
        result = prove(prop, timeout_s=300, max_k=max_k)
        assert result.status != "falsified" or reproduce(prop, result.trace).first_violation == result.k
    return prop, result


@pytest.mark.parametrize(
    ("name", "mutant"),
    [(name, m) for name in COARSE for m in MUTANTS[_kind(name)]],
    ids=lambda v: v if isinstance(v, str) else v[2][:40],
)
def test_mutant_falsified_and_counterexample_replays(name, mutant):
    prop = dataclasses.replace(COARSE[name], lemmas=())
    mutated, result = _falsify(prop, mutant)
    assert result.status == "falsified", result.message
    if mutated is not prop:
        assert reproduce(mutated, result.trace).first_violation == result.k
    real = replay(prop, result.trace)
    assert real.problems or real.first_violation is None, "the real model must not fail on the mutant's run"


class TestLeaderGuaranteedDeceleration:
    """The issue's mutant: relative braking with the leader's stopping point computed with a guaranteed
    deceleration instead of its highest. The follower then runs into a leader that stopped faster."""

    def test_collision_found(self):
        prop = dataclasses.replace(COARSE_RBD_COLLISION, lemmas=())
        with patched(*GUARANTEED):
            result = prove(prop, timeout_s=300, max_k=12)
            assert result.status == "falsified", result.message
            assert reproduce(prop, result.trace).first_violation == result.k
        after = result.trace.states[result.k + 1]
        assert after["front_m"] >= after["leader_rear_m"], "the counterexample must end in a collision"

    def test_regression_example_replays(self):
        """The stored collision (``leader_guaranteed_deceleration.json``, written by :func:`write_regression`)
        replays on the mutant, and the real model does not collide on its inputs."""
        prop, trace = from_json(REGRESSION, {COARSE_RBD_COLLISION.name: COARSE_RBD_COLLISION})
        with patched(*GUARANTEED):
            assert reproduce(prop, trace).first_violation == trace.violation_step
        last = trace.states[-1]
        assert last["front_m"] >= last["leader_rear_m"]
        real = replay(prop, trace)
        assert real.problems or real.first_violation is None


def write_regression() -> None:
    """Find the collision on the mutant and store it (run by hand when the model changes:
    ``python -c 'from tests.test_separation import write_regression; write_regression()'``)."""
    prop = dataclasses.replace(COARSE_RBD_COLLISION, lemmas=())
    with patched(*GUARANTEED):
        result = prove(prop, timeout_s=300, max_k=12)
        replayed = reproduce(prop, result.trace)
    REGRESSION.write_text(json.dumps(to_json(result.trace, replayed), indent=2) + "\n")
