"""Speed supervision (seed 000 §2.4.3): the properties are proved, can fail, and hold in simulation.

Each property has a mutant: the real ``supervision_step`` with one deliberate
fault, made from its source. The engine must falsify the property on the mutant,
and the counterexample must replay exactly on the mutant (and not be a run of
the real model).
"""

import json
from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, initialize, invariant, rule

from atcs.model.supervision import SUPERVISION, SupervisionInputs, SupervisionParams, SupervisionState, supervise
from atcs.proofs.cex.trace import from_json, replay, reproduce, to_json
from atcs.proofs.engine.prove import prove
from atcs.proofs.mutation.mutants import mutant_property
from atcs.properties import PROPERTIES, select
from atcs.sim.monitor import Monitor, PropertyViolation

SUPERVISION_PROPERTIES = select("supervision.*")

# property -> (text in supervision_step or in the decision it calls, its faulty replacement[, that helper])
MUTANTS = {
    "supervision.eb_above_ebi": (
        "over_ebi=i.speed_mps > i.ebi_mps",
        "over_ebi=i.speed_mps > i.ebi_mps + o.const(1)",
    ),
    "supervision.eb_latched_until_standstill": (
        "eb_released = o.and_(standstill, eb_release)",
        "eb_released = eb_release",
        supervise,
    ),
    "supervision.brake_above_sbi": (
        "o.and_(over.over_sbi, o.not_(p.service_brake_fitted))",
        "o.and_(over.over_sbi, o.const_bool(False))",
        supervise,
    ),
    "supervision.sb_held_above_permitted": (
        "o.and_(s.sb_latched, over.over_permitted)",
        "o.and_(s.sb_latched, over.over_warning)",
        supervise,
    ),
    "supervision.warning_above_warning_limit": (
        "warning=over.over_warning",
        "warning=o.and_(over.over_warning, o.not_(over.over_sbi))",
        supervise,
    ),
    "supervision.traction_cut_when_braking": (
        "traction_cut = o.or_(emergency_brake, service_brake)",
        "traction_cut = emergency_brake",
        supervise,
    ),
    "supervision.no_intervention_below_permitted": (
        "over_sbi=i.speed_mps > i.sbi_mps",
        "over_sbi=i.speed_mps >= i.permitted_mps",
    ),
    "supervision.sb_only_if_fitted": ("        p.service_brake_fitted,\n", "", supervise),
    "supervision.eb_without_position": ("        o.not_(position_valid),\n", "", supervise),
    # the survivors of atcs mutate, each killed by a property of its own
    "supervision.no_spurious_eb": (
        "o.and_(s.eb_latched, o.not_(eb_released))",
        "o.or_(s.eb_latched, o.not_(eb_released))",
        supervise,
    ),
    "supervision.state_records_commands": (
        "SupervisionState(eb_latched=emergency_brake,",
        "SupervisionState(eb_latched=s.eb_latched,",
        supervise,
    ),
    "supervision.warning_only_above_warning_limit": (
        "over_warning=i.speed_mps > i.warning_mps",
        "over_warning=i.speed_mps >= i.warning_mps",
    ),
}


def make_mutant(name):
    old, new, *helper = MUTANTS[name]
    return mutant_property(PROPERTIES[name], old, new, helper=helper[0] if helper else None)


def test_every_supervision_property_has_a_mutant():
    assert set(MUTANTS) == {p.name for p in SUPERVISION_PROPERTIES}


class TestProved:
    @pytest.mark.parametrize("prop", SUPERVISION_PROPERTIES, ids=lambda p: p.name)
    def test_proved_by_k_induction(self, prop, proof_suite_run):
        record = proof_suite_run.by_name[prop.name]  # the session's atcs prove run (conftest.py)
        assert (record["status"], record["engine"]) == ("proved", "k-induction"), record["message"]
        assert record["counterexample"] is None

    def test_parametric_over_the_service_brake(self):
        # not k-inductive at k = 0 for a symbolic parameter: needs one step of history
        result = prove(PROPERTIES["supervision.sb_held_above_permitted"], timeout_s=120)
        assert (result.status, result.k) == ("proved", 1)


class TestMutantsAreFalsified:
    @pytest.mark.parametrize("name", sorted(MUTANTS))
    def test_mutant_falsified_and_counterexample_replays(self, name, tmp_path):
        mutant = make_mutant(name)
        result = prove(mutant, timeout_s=120)
        assert result.status == "falsified", result.message
        assert result.engine == "bmc"
        trace = result.trace
        assert trace.violation_step == result.k == len(trace.inputs) - 1
        # replays exactly on the mutant, violating at the recorded step and not before
        replayed = reproduce(mutant, trace)
        assert replayed.holds[-1] is False and all(replayed.holds[:-1])
        # and survives the trip through its JSON file
        path = tmp_path / "cex.json"
        path.write_text(json.dumps(to_json(trace, replayed)))
        prop, again = from_json(path, {name: mutant})
        assert again == trace
        assert reproduce(prop, again).first_violation == trace.violation_step
        # the fault is what matters: the real model does not violate the property on these inputs
        assert replay(PROPERTIES[name], trace).first_violation is None

    def test_sb_release_mutant_needs_two_steps(self):
        name = "supervision.sb_held_above_permitted"
        result = prove(make_mutant(name), timeout_s=120)
        assert result.status == "falsified" and result.k == 1
        assert result.trace.states[1]["sb_latched"] is True

    def test_brake_above_sbi_mutant_needs_no_service_brake(self):
        name = "supervision.brake_above_sbi"
        result = prove(make_mutant(name), timeout_s=120)
        assert result.trace.params == {"service_brake_fitted": False}


# --- the same predicates in simulation -----------------------------------------------------------

speed = st.fractions(min_value=0, max_value=40, max_denominator=8)
gap = st.fractions(min_value=0, max_value=3, max_denominator=8)


@st.composite
def ordered_inputs(draw):
    permitted = draw(speed)
    warning = permitted + draw(gap)
    sbi = warning + draw(gap)
    ebi = sbi + draw(gap)
    v = draw(st.one_of(speed, st.sampled_from([permitted, warning, sbi, ebi]), st.just(Fraction(0))))
    return SupervisionInputs(
        speed_mps=float(v),
        permitted_mps=float(permitted),
        warning_mps=float(warning),
        sbi_mps=float(sbi),
        ebi_mps=float(ebi),
        standstill=draw(st.booleans()) if v == 0 else False,
        eb_release=draw(st.booleans()),
        position_valid=draw(st.booleans()),
    )


class SupervisionMachine(RuleBasedStateMachine):
    """Drive the node on the float backend; the Monitor checks every supervision property each cycle."""

    @initialize(fitted=st.booleans())
    def power_up(self, fitted):
        self.monitor = Monitor(
            SUPERVISION,
            SupervisionParams(service_brake_fitted=fitted),
            SupervisionState(eb_latched=True, sb_latched=False),
            SUPERVISION_PROPERTIES,
        )
        self.fitted = fitted

    @rule(inputs=ordered_inputs())
    def cycle(self, inputs):
        out = self.monitor.step(inputs)
        assert out.traction_cut == (out.emergency_brake or out.service_brake)

    @invariant()
    def no_service_brake_state_without_interface(self):
        assert self.fitted or not self.monitor.state.sb_latched


TestSupervisionStateful = pytest.mark.slow(SupervisionMachine.TestCase)
TestSupervisionStateful.settings = settings(max_examples=50, stateful_step_count=25)


class TestMonitorCatchesMutants:
    @settings(max_examples=100)
    @given(fitted=st.booleans(), steps=st.lists(ordered_inputs(), min_size=1, max_size=20))
    def test_real_model_never_trips_the_monitor(self, fitted, steps):
        monitor = Monitor(SUPERVISION, SupervisionParams(fitted), SupervisionState(True, False), SUPERVISION_PROPERTIES)
        for inputs in steps:
            monitor.step(inputs)

    def test_mutant_trips_the_monitor_on_its_counterexample(self):
        name = "supervision.eb_latched_until_standstill"
        mutant = make_mutant(name)
        trace = prove(mutant, timeout_s=120).trace
        monitor = Monitor(
            mutant.node,
            SupervisionParams(**trace.params),
            SupervisionState(**trace.states[0]),
            (mutant,),
        )
        with pytest.raises(PropertyViolation, match=name) as caught:
            for inputs in trace.inputs:
                monitor.step(
                    SupervisionInputs(**{k: float(v) if isinstance(v, Fraction) else v for k, v in inputs.items()})
                )
        assert caught.value.step == trace.violation_step
