"""The closed-loop theorem (seed 000 §2.4, §2.5): proved for the seed presets, falsified on mutants of the
ATP (each counterexample replays), and a worst-case driver in simulation stops before the EoA.

The mutants run on a coarse-cycle variant of seed 000 (0.8 s cycles, T_be 1.6 s), itself
proved first: fewer cycles between the EB command and the brake, so a counterexample
from standstill is a few steps deep. The issue's three named faults (EBI without the
build-up time, the gradient's sign flipped, the speed-measurement inaccuracy ignored) are
among them; each is falsified by BMC within five steps.
"""

import dataclasses
from fractions import Fraction

import pytest
from hypothesis import Phase, given, settings
from hypothesis import strategies as st

from atcs.model import closed_loop, curves, dynamic_profile, plant
from atcs.model.closed_loop import CLOSED_LOOP, ClosedLoopInputs, ClosedLoopParams, ClosedLoopState
from atcs.model.ops.exact import EXACT
from atcs.model.train_data import seed000_train, subset026_national
from atcs.proofs.cex.trace import replay, reproduce
from atcs.proofs.engine.prove import prove
from atcs.proofs.mutation.mutants import falsify, patched
from atcs.properties import select
from atcs.properties.closed_loop import PRESETS, closed_loop_properties, preset_data
from atcs.sim.drivers import worst_case_driver
from atcs.sim.monitor import Monitor, Traces

CLOSED_LOOP_PROPERTIES = select("closed_loop.*")

COARSE = {
    p.name: p
    for p in closed_loop_properties(
        "coarse",
        {
            **preset_data(
                dataclasses.replace(seed000_train(), t_be_s=Fraction(8, 5)),
                subset026_national(),
                cycle_s=Fraction(4, 5),
            ),
        },
    )
}


def _kind(name):
    return name.removeprefix("closed_loop.").rsplit("_", 1)[0]


# property kind -> mutants (function, text in it, faulty replacement)
MUTANTS = {
    "braking_invariant": [
        # the max safe front taken without the odometry error
        (closed_loop.max_safe_front_m, "i.measured_front_m + p.position_error_m", "i.measured_front_m"),
    ],
    "no_overrun": [
        # the max safe front taken without the odometry error
        (closed_loop.max_safe_front_m, "i.measured_front_m + p.position_error_m", "i.measured_front_m"),
        # EB at the EBD instead of the EBI
        (dynamic_profile.exceedances, "front_m > curve.ebi_m", "front_m > curve.ebd_m"),
        # EBI without the speed gained during the brake build-up time
        (curves.bec_speed_and_distance, "+ (v_cut + v_d2 / o.const(2)) * t_berem", ""),
        # the gradient's sign flipped: a downhill taken as helping the brake
        (
            curves.gradient_acceleration_mps2,
            "gradient_deceleration_mps2(o, gradient_permille, mass)",
            "-gradient_deceleration_mps2(o, gradient_permille, mass)",
        ),
        # the speed-measurement inaccuracy V_ura ignored
        (curves.bec_speed_deltas_mps, "o.ite(n.inhibit_speed_inaccuracy, zero, t.v_ura_mps)", "zero"),
    ],
    "under_ceiling": [
        # no EB ceiling: only the braking curves supervised
        (dynamic_profile.exceedances, "speed_mps > ceiling.ebi_mps", "speed_mps > o.const(1000) + ceiling.ebi_mps"),
    ],
    "eb_at_ebi": [
        # EB at the EBD instead of the EBI
        (dynamic_profile.exceedances, "front_m > curve.ebi_m", "front_m > curve.ebd_m"),
    ],
    "no_spurious_eb": [
        # the position taken as invalid: EB in every cycle (atcs mutate's const_bool in atp_cycle)
        (closed_loop.atp_cycle, "o.const_bool(True)", "o.const_bool(False)"),
    ],
    "supervises_eoa_and_ceilings": [
        # A_est with the steepest uphill's help instead of the downhill's (arith_sign at worst_acceleration_mps2:+4)
        (
            closed_loop.worst_acceleration_mps2,
            "downhill = (-gradient_acceleration_mps2(o, p, g)",
            "downhill = (gradient_acceleration_mps2(o, p, g)",
        ),
        # the EB ceiling without the MRSP: dV alone (arith_drop at ceilings:+5)
        (dynamic_profile.ceilings, "return mrsp_mps + ceiling_offset_mps(", "return ceiling_offset_mps("),
    ],
    "state_follows_plant_and_atp": [
        # the train never moves (delay_hold of the front)
        (plant.plant_next, "front_m=s.front_m + distance_m", "front_m=s.front_m"),
    ],
}


def test_every_closed_loop_property_has_a_mutant():
    assert {_kind(p.name) for p in CLOSED_LOOP_PROPERTIES} == set(MUTANTS)


@pytest.fixture(scope="module")
def coarse_results():
    """The closed-loop properties of the coarse variant, the lemma proved once."""
    shared = {}
    return {
        prop.name: shared.get(prop.name) or prove(prop, timeout_s=300, lemmas=COARSE, proved=shared)
        for prop in COARSE.values()
    }


@pytest.mark.parametrize("name", [p.name for p in CLOSED_LOOP_PROPERTIES], ids=str)
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
    ids=lambda v: v if isinstance(v, str) else v[1][:40],
)
def test_mutant_falsified_and_counterexample_replays(name, mutant):
    # without the lemma: the mutant's invariant does not hold, so only BMC can speak
    prop = dataclasses.replace(COARSE[name], lemmas=())
    function, old, new = mutant
    with patched(function, old, new):
        result = prove(prop, timeout_s=300, max_k=12)
        assert result.status == "falsified", result.message
        assert reproduce(prop, result.trace).first_violation == result.k
    real = replay(prop, result.trace)
    assert real.problems or real.first_violation is None, "the real model must not fail on the mutant's run"


@pytest.mark.parametrize(
    ("old", "new"),
    [
        ("eb_latched=supervision.eb_latched", "eb_latched=s.eb_latched"),
        ("sb_latched=supervision.sb_latched", "sb_latched=s.sb_latched"),
    ],
)
def test_latches_held_over_are_falsified(old, new):
    """The closed loop's own step keeping last cycle's latch (atcs mutate's delay_hold in _loop_step):
    CL-05 falsified, its counterexample replays on the mutant and not on the model."""
    run = falsify(COARSE["closed_loop.state_follows_plant_and_atp_coarse"], closed_loop._loop_step, old, new, max_k=2)
    assert run.killed, run


# --- simulation: the same step function and predicates on concrete numbers ------------------------


@pytest.mark.slow
@settings(max_examples=4, phases=(Phase.explicit, Phase.reuse, Phase.generate))  # a run takes seconds: no shrinking
@given(eoa_m=st.integers(300, 1500), breakpoint_m=st.integers(1, 1999), noise=st.randoms(use_true_random=False))
def test_worst_case_driver_stops_before_the_eoa(eoa_m, breakpoint_m, noise):
    fixed = PRESETS["seed000"]
    params = ClosedLoopParams(
        **{
            **fixed,
            "gradient_starts_m": (Fraction(0), Fraction(breakpoint_m)),
            "line_end_m": Fraction(2000),
            "mrsp_mps": Fraction(80) / Fraction("3.6"),
            "eoa_m": Fraction(eoa_m),
            "position_error_m": Fraction(5),
        }
    )
    start = ClosedLoopState(
        eb_latched=True,
        sb_latched=False,
        front_m=Fraction(0),
        speed_mps=Fraction(0),
        brake_cycles=fixed["brake_build_up_cycles"],
    )
    props = tuple(p for p in CLOSED_LOOP_PROPERTIES if p.name.endswith("_seed000"))
    monitor = Monitor(CLOSED_LOOP, params, start, props, ops=EXACT, traces=Traces())
    eb_cycles, s = 0, start
    for _ in range(1200):
        s = monitor.state
        error_m = Fraction(noise.randint(-50, 50), 10)
        error_mps = params.v_ura_mps * Fraction(noise.randint(-10, 10), 10)
        measured = ClosedLoopInputs(
            measured_front_m=s.front_m + error_m,
            measured_speed_mps=max(Fraction(0), s.speed_mps + error_mps),
            standstill=s.speed_mps == 0,
            eb_release=s.speed_mps == 0 and eb_cycles == 0,
            next_speed_mps=Fraction(0),
            distance_m=Fraction(0),
        )
        _, commands, _ = closed_loop.eoa_atp_cycle(EXACT, params, s, measured)
        eb_cycles += commands.emergency_brake
        next_speed, distance = worst_case_driver(
            params, s, measured.measured_speed_mps, params.mrsp_mps, commands.emergency_brake
        )
        monitor.step(dataclasses.replace(measured, next_speed_mps=next_speed, distance_m=distance))
        if eb_cycles and monitor.state.speed_mps == 0:
            break
    assert all(monitor.applies(p.name) for p in props), "the run left the assumptions: it checked nothing"
    assert eb_cycles > 0 and monitor.state.speed_mps == 0, "the train must have been stopped by the EB"
    # and not needlessly far before it: on a -40 permille downhill the guaranteed deceleration is about
    # 0.4 m/s2 and the ATP's worst case adds the build-up time's traction, about 140 m at 80 km/h
    assert eoa_m - 250 < monitor.state.front_m <= eoa_m, float(monitor.state.front_m)
