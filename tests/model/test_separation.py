"""Two trains (seed 001 §3.2 Fig. 6): brick-wall and relative-braking separation proved for the presets and a
coarse-cycle variant of seed 000 (as in test_closed_loop.py); every property falsified on a mutant of that variant
(each counterexample replays); the leader's stopping point computed with a guaranteed deceleration gives a
collision, kept as a regression example."""

import dataclasses
import json
import random
from fractions import Fraction
from pathlib import Path

import pytest
from hypothesis import Phase, event, example, given, settings
from hypothesis import strategies as st

from atcs.model import authority, separation
from atcs.model.closed_loop import atp_cycle, eoa_target
from atcs.model.ops.exact import EXACT
from atcs.model.separation import TWO_TRAINS, TwoTrainInputs, TwoTrainParams, TwoTrainState
from atcs.model.train_data import seed000_train, subset026_national
from atcs.proofs.cex.trace import from_json, replay, reproduce, to_json
from atcs.proofs.engine.prove import prove
from atcs.proofs.mutation.mutants import falsify, patched
from atcs.properties import select
from atcs.properties.closed_loop import PRESETS, preset_data
from atcs.properties.separation import separation_properties
from atcs.sim.drivers import worst_case_driver
from atcs.sim.monitor import Monitor, Traces

SEPARATION_PROPERTIES = select("separation.*")

COARSE_DATA = preset_data(
    dataclasses.replace(seed000_train(), t_be_s=Fraction(8, 5)), subset026_national(), cycle_s=Fraction(4, 5)
)
COARSE = {p.name: p for mode in ("bw", "rbd") for p in separation_properties("coarse", COARSE_DATA, mode)}
COARSE_RBD_COLLISION = COARSE["separation.no_collision_rbd_coarse"]

REGRESSION = (
    Path(__file__).parents[1] / "proofs" / "engine" / "regression" / "falsified" / "leader_guaranteed_deceleration.json"
)


def _kind(name):
    return name.removeprefix("separation.").rsplit("_", 1)[0]


_BEST = "o.max(s.best_rear_m, i.report_rear_m)"
_LIMIT = "limit = o.ite(certain_only, r.best_rear_m, r.best_stop_m) - p.safety_margin_m"
# the fault: the leader's stopping point computed with a guaranteed deceleration (here the follower's own,
# about 0.8 m/s^2) instead of the leader's highest (3 m/s^2)
GUARANTEED = (
    authority.stopping_point_m,
    "(o.const(2) * deceleration)",
    "(o.const(2) * p.guaranteed_deceleration_mps2)",
)

_MEASURED_FRONT = (
    separation.follower_authority,
    "front_max = i.measured_front_m + p.position_error_m",
    "front_max = i.measured_front_m",
)

_LEADER_HELD = (
    separation.leader_moves,
    "rear = s.leader_rear_m + i.leader_distance_m",
    "rear = s.leader_rear_m",
)

# property kind -> mutants (function, text in it, faulty replacement)
MUTANTS = {
    # the leader's reported front taken for its rear
    "reports_behind_leader_bw": [(authority.leader_reports, _BEST, f"{_BEST} + p.train_length_m")],
    "braking_invariant_bw": [(authority.leader_limit_m, _LIMIT, _LIMIT.replace(" - p.safety_margin_m", ""))],
    "no_collision_bw": [
        # no safety margin before the leader's rear
        (authority.leader_limit_m, _LIMIT, _LIMIT.replace(" - p.safety_margin_m", "")),
        # the leader's reported front taken for its rear: a collision
        (authority.leader_reports, _BEST, f"{_BEST} + p.train_length_m"),
        # brick-wall mode ignored: the leader's stopping point taken for its rear
        (authority.leader_limit_m, "o.ite(certain_only, r.best_rear_m, r.best_stop_m)", "r.best_stop_m"),
    ],
    "reports_behind_leader_rbd": [GUARANTEED],
    # no safety margin before the best reported stopping point
    "braking_invariant_rbd": [(authority.leader_limit_m, _LIMIT, _LIMIT.replace(" - p.safety_margin_m", ""))],
    "no_collision_rbd": [GUARANTEED],
    # the authority computed on the measured front, without the odometry bound (arith_drop at follower_authority:+3)
    "authority_on_safe_position_bw": [_MEASURED_FRONT],
    "authority_on_safe_position_rbd": [_MEASURED_FRONT],
    # the leader never moves (arith_drop at leader_moves:+6)
    "state_follows_bw": [_LEADER_HELD],
    "state_follows_rbd": [_LEADER_HELD],
    # the leader's physics with half its highest deceleration
    "leader_stop_is_earliest": [(separation.earliest_stop_m, "(o.const(2) * deceleration)", "deceleration")],
    # the ghost stopping point taken from the rear before this cycle's motion
    "leader_stop_never_recedes": [
        (
            separation.leader_moves,
            "earliest_stop_m(o, p, rear, i.leader_next_speed_mps)",
            "earliest_stop_m(o, p, s.leader_rear_m, i.leader_next_speed_mps)",
        )
    ],
}


def test_every_separation_property_has_a_mutant():
    assert {_kind(p.name) for p in SEPARATION_PROPERTIES} == set(MUTANTS)
    assert {_kind(p.name) for p in COARSE.values()} == set(MUTANTS)


@pytest.fixture(scope="module")
def coarse_results():
    shared = {}
    return {
        prop.name: shared.get(prop.name) or prove(prop, timeout_s=300, lemmas=COARSE, proved=shared)
        for prop in COARSE.values()
    }


@pytest.mark.parametrize("name", [p.name for p in SEPARATION_PROPERTIES], ids=str)
def test_proved(proof_suite_run, name):
    record = proof_suite_run.by_name[name]  # the session's atcs prove run (conftest.py)
    assert (record["status"], record["engine"]) == ("proved", "k-induction"), record["message"]


@pytest.mark.slow
@pytest.mark.parametrize("name", list(COARSE), ids=str)
def test_proved_on_the_coarse_variant(coarse_results, name):
    result = coarse_results[name]
    assert (result.status, result.engine) == ("proved", "k-induction"), result.message


@pytest.mark.parametrize(
    ("name", "mutant"),
    [(name, m) for name in COARSE for m in MUTANTS[_kind(name)]],
    ids=lambda v: v if isinstance(v, str) else v[2][:40],
)
def test_mutant_falsified_and_counterexample_replays(name, mutant):
    run = falsify(COARSE[name], *mutant, timeout_s=300, max_k=12)
    assert run.killed, run


class TestLeaderGuaranteedDeceleration:
    """The issue's mutant: relative braking with the leader's stopping point computed with a guaranteed
    deceleration instead of its highest. The follower then runs into a leader that stopped faster."""

    def test_collision_found(self):
        prop = dataclasses.replace(COARSE_RBD_COLLISION, lemmas=())
        with patched(*GUARANTEED):
            result = prove(prop, timeout_s=300, max_k=12)
            assert result.status == "falsified", result.message
            assert reproduce(prop, result.trace).first_violation == result.k
        hit = result.trace.states[result.k]  # the property is about the state before step k
        assert hit["front_m"] >= hit["leader_rear_m"], "the counterexample must end in a collision"

    def test_regression_example_replays(self):
        """The stored collision (``leader_guaranteed_deceleration.json``, written by :func:`write_regression`)
        replays on the mutant, and the real model does not collide on its inputs."""
        prop, trace = from_json(REGRESSION, {COARSE_RBD_COLLISION.name: COARSE_RBD_COLLISION})
        with patched(*GUARANTEED):
            assert reproduce(prop, trace).first_violation == trace.violation_step
        hit = trace.states[trace.violation_step]
        assert hit["front_m"] >= hit["leader_rear_m"]
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


# --- simulation: the same step function and predicates on exact numbers -----------------


def _leader_motion(speed_mps, accel_mps2, dt):
    """One cycle of the leader at a constant acceleration, stopping within the cycle if it brakes to 0."""
    v_next = max(Fraction(0), speed_mps + accel_mps2 * dt)
    if v_next == 0 and accel_mps2 < 0:
        return v_next, speed_mps * speed_mps / (2 * -accel_mps2)
    return v_next, (speed_mps + v_next) / 2 * dt


@pytest.mark.slow
@settings(max_examples=2, phases=(Phase.explicit, Phase.reuse, Phase.generate))  # a run takes seconds
@example(mode="bw", gap_m=250, leader_kmh=80, seed=1)  # each mode once, at the closest start
@example(mode="rbd", gap_m=250, leader_kmh=80, seed=2)
@given(
    mode=st.sampled_from(["bw", "rbd"]),
    gap_m=st.integers(250, 600),
    leader_kmh=st.integers(30, 80),
    seed=st.integers(0, 2**16),
)
def test_worst_case_follower_behind_a_braking_leader(mode, gap_m, leader_kmh, seed):
    """The follower is driven at full traction whenever its ATP lets it (the service brake ignored, the weakest
    braking once EB is effective), the leader runs then brakes as hard as it can to a stop, and reports arrive
    late and out of order. Every separation predicate of the mode holds at every
    cycle, and the follower is stopped by its ATP behind the leader (released at each standstill, it closes in
    again until the leader has stopped)."""
    event(mode)
    noise = random.Random(seed)
    fixed = {k: v for k, v in PRESETS["seed000"].items() if k != "eoa_m"}
    d_max = fixed["max_deceleration_mps2"]
    params = TwoTrainParams(
        **{
            **fixed,
            "gradient_starts_m": (Fraction(0), Fraction(9000)),
            "line_end_m": Fraction(10_000),
            "mrsp_mps": Fraction(80) / Fraction("3.6"),
            "position_error_m": Fraction(5),
            "safety_margin_m": Fraction(20),
            "leader_max_deceleration_mps2": d_max,
            "report_timeout_s": Fraction(2),
            "clock_skew_max_s": Fraction(1, 10),
            "brick_wall": mode == "bw",
            # a plain line: two track resources, both held; MAX_MA beyond the line
            "resource_start_m": (Fraction(0), Fraction(5000)),
            "resource_end_m": (Fraction(5000), Fraction(10_000)),
            "resource_is_switch": (False, False),
            "switch_needs_reverse": (False, False),
            "max_ma_m": Fraction(10_000),
        }
    )
    dt = params.cycle_s
    leader_v = Fraction(leader_kmh) / Fraction("3.6")
    rear = Fraction(gap_m + 20)
    stop = separation.earliest_stop_m(EXACT, params, rear, leader_v)
    start = TwoTrainState(
        front_m=Fraction(0),
        speed_mps=Fraction(0),
        brake_cycles=fixed["brake_build_up_cycles"],
        eb_latched=True,
        sb_latched=False,
        leader_known=True,
        best_rear_m=rear,
        best_stop_m=stop,
        last_seq=Fraction(0),
        freshest_sent_s=Fraction(0),
        leader_rear_m=rear,
        leader_speed_mps=leader_v,
        leader_stop_m=stop,
    )
    props = tuple(
        p
        for p in SEPARATION_PROPERTIES
        if p.name.endswith(f"{mode}_seed000")
        or (mode == "rbd" and p.name.startswith("separation.leader_stop") and p.name.endswith("seed000"))
    )
    monitor = Monitor(TWO_TRAINS, params, start, props, ops=EXACT, traces=Traces())
    history = [(rear, leader_v)]
    brake_at = 100 + noise.randint(0, 200)  # the leader runs, then brakes as hard as it can
    eb_cycles, min_gap, settled = 0, rear, 0
    for k in range(3000):
        s = monitor.state
        accel = -d_max if k >= brake_at else Fraction(0)
        leader_next, leader_distance = _leader_motion(s.leader_speed_mps, accel, dt)
        delivered = noise.random() < 0.3
        sent = len(history) - 1 - min(noise.randint(0, 15), len(history) - 1)  # late, out of order, repeated
        sent_rear, sent_speed = history[sent]
        intact = noise.random() < 0.8
        if not intact:  # corrupted on the way: it may say anything
            sent_rear, sent_speed = sent_rear + noise.randint(0, 5000), Fraction(noise.randint(0, 100))
        error_m = Fraction(noise.randint(-50, 50), 10)
        error_mps = params.v_ura_mps * Fraction(noise.randint(-10, 10), 10)
        inputs = TwoTrainInputs(
            measured_front_m=s.front_m + error_m,
            measured_speed_mps=max(Fraction(0), s.speed_mps + error_mps),
            standstill=s.speed_mps == 0,
            eb_release=s.speed_mps == 0,
            next_speed_mps=Fraction(0),
            distance_m=Fraction(0),
            leader_distance_m=leader_distance,
            leader_next_speed_mps=leader_next,
            now_s=k * dt,
            report_delivered=delivered,
            report_intact=intact,
            report_seq=Fraction(sent),
            report_sent_s=sent * dt,
            report_rear_m=sent_rear,
            report_speed_mps=sent_speed,
            held=(True, True),
            switch_locked=(False, False),
            switch_reversed=(False, False),
            zone_active=False,
            zone_start_m=Fraction(0),
        )
        eoa = separation.follower_authority(EXACT, params, s, inputs)[1].eoa_m
        _, commands, _ = atp_cycle(EXACT, params, s, inputs, eoa_target(EXACT, eoa), params.mrsp_mps)
        eb_cycles += commands.emergency_brake and k > 0
        next_speed, distance = worst_case_driver(
            params, s, inputs.measured_speed_mps, params.mrsp_mps, commands.emergency_brake
        )
        monitor.step(dataclasses.replace(inputs, next_speed_mps=next_speed, distance_m=distance))
        history.append((monitor.state.leader_rear_m, monitor.state.leader_speed_mps))
        min_gap = min(min_gap, monitor.state.leader_rear_m - monitor.state.front_m)
        settled = settled + 1 if monitor.state.speed_mps == 0 and monitor.state.leader_speed_mps == 0 else 0
        if settled > 20:  # both stopped for 2 s: the follower's ATP holds it there
            break
    assert all(monitor.applies(p.name) for p in props), "the run left the assumptions: it checked nothing"
    assert settled > 20, "the run must end with both trains stopped"
    assert eb_cycles > 0, "the follower's ATP must have intervened"
    assert 0 < min_gap < 300, float(min_gap)  # it came close: the claim was put to the test
