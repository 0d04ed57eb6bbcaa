"""The two trains with the leader's reports on their way (model/separation.py, TWO_TRAINS_REPORTED): the two-train
node's report assumptions proved of the reports the leader's onboard unit makes (SEP-11, SEP-12 on the product
node) and the properties that assumed them proved again with them as lemmas, each with a mutant falsified and its
counterexample replayed; the side conditions of carrying SEP-01 and SEP-02 over (the product's runs are the
two-train node's, SEP-11 and SEP-12 are REPORT_REAR and REPORT_STOP of the delivered report) checked."""

import dataclasses
from fractions import Fraction

import pytest
import z3

from atcs.model import separation
from atcs.model.ops.exact import EXACT
from atcs.model.ops.symbolic import SYMBOLIC, context, unwrap
from atcs.model.separation import (
    REPORT_CHANNEL,
    TWO_TRAINS,
    TWO_TRAINS_REPORTED,
    ChannelInputs,
    ReportedInputs,
    ReportedParams,
    ReportedState,
    TwoTrainState,
    delivered_report,
)
from atcs.proofs.engine.system import variables
from atcs.proofs.mutation.mutants import falsify
from atcs.properties import PROPERTIES, select
from atcs.properties.closed_loop import PRESETS
from atcs.properties.reported_separation import PRESET
from atcs.properties.separation import REPORT_REAR, REPORT_STOP

MODULE = "reported_separation"
REPORTED_PROPERTIES = select(f"{MODULE}.*")

# the leader's onboard unit reports its min front as its rear: ahead of its true rear by up to its length
_FRONT_AS_REAR = (separation.report_channel_step, "sent_report(o, p.leader_length_m,", "sent_report(o, o.const(0),")

# property -> (function, text in it, faulty replacement)
MUTANTS = {
    f"reported_separation.{kind}": mutant
    for kind, mutant in {
        # the leader's physics with half its highest deceleration
        f"leader_stop_is_earliest_{PRESET}": (
            separation.earliest_stop_m,
            "(o.const(2) * deceleration)",
            "deceleration",
        ),
        # the ghost stopping point taken from the rear before this cycle's motion
        f"leader_stop_never_recedes_{PRESET}": (
            separation.leader_moves,
            "earliest_stop_m(o, p, rear, i.leader_next_speed_mps)",
            "earliest_stop_m(o, p, s.leader_rear_m, i.leader_next_speed_mps)",
        ),
        f"report_on_way_behind_leader_rbd_{PRESET}": _FRONT_AS_REAR,
        # the speed estimate reported with its accuracy added: faster than the leader may be
        f"report_on_way_stop_behind_leader_rbd_{PRESET}": (
            separation.report_channel_step,
            "sent_report(o, p.leader_length_m, i.front_min_m, i.speed_est_mps, i.speed_accuracy_mps, i.clock_s)",
            "sent_report(o, p.leader_length_m, i.front_min_m, i.speed_est_mps + i.speed_accuracy_mps, o.const(0), "
            "i.clock_s)",
        ),
        # a channel that never carries a report on: SEP-11 to SEP-13 would hold of it vacuously
        f"sent_report_on_its_way_rbd_{PRESET}": (
            separation.reported_step,
            "on_way=channel.on_way,",
            "on_way=s.on_way,",
        ),
        # the authority computed on the measured front, without the odometry bound
        f"authority_on_safe_position_rbd_{PRESET}": (
            separation.follower_authority,
            "front_max = i.measured_front_m + p.position_error_m",
            "front_max = i.measured_front_m",
        ),
        # the leader never moves
        f"state_follows_rbd_{PRESET}": (
            separation.leader_moves,
            "rear = s.leader_rear_m + i.leader_distance_m",
            "rear = s.leader_rear_m",
        ),
        # a report delivered when none is on its way: whatever the slot held
        f"reports_behind_leader_rbd_{PRESET}": (
            separation.delivered_report,
            "report_delivered=s.on_way",
            "report_delivered=o.const_bool(True)",
        ),
    }.items()
}


def test_every_property_has_a_mutant():
    assert set(MUTANTS) == {p.name for p in REPORTED_PROPERTIES}


def test_the_report_assumptions_are_lemmas_here():
    """No property of the product assumes what it is to prove of the reports: REPORT_REAR and REPORT_STOP are gone,
    SEP-11 and SEP-12 of the product are SEP-13's lemmas."""
    for prop in REPORTED_PROPERTIES:
        assert not {REPORT_REAR.name, REPORT_STOP.name} & {a.name for a in prop.assumptions}, prop.name
    reports = PROPERTIES[f"reported_separation.reports_behind_leader_rbd_{PRESET}"]
    assert {PROPERTIES[n].requirement for n in reports.lemmas} == {"SEP-11", "SEP-12"}


@pytest.mark.parametrize("prop", REPORTED_PROPERTIES, ids=lambda p: p.name)
def test_proved_by_k_induction(prop, proof_suite_run):
    record = proof_suite_run.by_name[prop.name]  # the session's atcs prove run (conftest.py)
    assert (record["status"], record["engine"]) == ("proved", "k-induction"), record["message"]


@pytest.mark.parametrize("name", sorted(MUTANTS))
def test_mutant_falsified_and_counterexample_replays(name):
    run = falsify(PROPERTIES[name], *MUTANTS[name], max_k=4)
    assert run.killed, run


def test_the_report_lemmas_are_the_two_train_assumptions_of_the_delivered_report():
    """For every state and input (z3, no assumption): where SEP-11 and SEP-12 hold of the report on its way,
    REPORT_REAR and REPORT_STOP hold of the two-train node's inputs the product gives it; and every other assumption
    of SEP-02 is the two-train node's own predicate of those inputs."""
    node = TWO_TRAINS_REPORTED
    p, s = variables(ReportedParams, node, "params", "0"), variables(ReportedState, node, "state", "0")
    i = variables(ReportedInputs, node, "inputs", "0")
    delivered = delivered_report(SYMBOLIC, s, i)
    for lemma, assumption in (
        (f"{MODULE}.report_on_way_behind_leader_rbd_{PRESET}", REPORT_REAR),
        (f"{MODULE}.report_on_way_stop_behind_leader_rbd_{PRESET}", REPORT_STOP),
    ):
        claim = SYMBOLIC.implies(
            PROPERTIES[lemma].holds(SYMBOLIC, p, s, i, None, None), assumption.holds(SYMBOLIC, p, s, delivered)
        )
        solver = z3.Solver(ctx=context())
        solver.add(z3.Not(unwrap(claim)))
        assert solver.check() == z3.unsat, assumption.name
    no_collision = PROPERTIES[f"separation.no_collision_rbd_{PRESET}"]
    here = {a.name for a in PROPERTIES[f"{MODULE}.reports_behind_leader_rbd_{PRESET}"].assumptions}
    assert {a.name for a in no_collision.assumptions} - {REPORT_REAR.name, REPORT_STOP.name, "margin"} <= here


def test_the_step_is_the_two_nodes_steps():
    """One cycle of the product: the two-train node's step on the report on its way, the channel's on the leader's
    side; a report sent this cycle reaches the follower from the next."""
    fixed = {k: v for k, v in PRESETS[PRESET].items() if k != "eoa_m"}
    p = ReportedParams(
        **{
            **fixed,
            "gradient_starts_m": (Fraction(0), Fraction(9000)),
            "line_end_m": Fraction(10_000),
            "mrsp_mps": Fraction(20),
            "position_error_m": Fraction(5),
            "safety_margin_m": Fraction(20),
            "leader_max_deceleration_mps2": fixed["max_deceleration_mps2"],
            "report_timeout_s": Fraction(2),
            "clock_skew_max_s": Fraction(1, 10),
            "brick_wall": False,
            "resource_start_m": (Fraction(0), Fraction(5000)),
            "resource_end_m": (Fraction(5000), Fraction(10_000)),
            "resource_is_switch": (False, False),
            "switch_needs_reverse": (False, False),
            "max_ma_m": Fraction(10_000),
            "leader_length_m": Fraction(100),
        }
    )
    s = ReportedState(
        front_m=Fraction(0),
        speed_mps=Fraction(0),
        brake_cycles=fixed["brake_build_up_cycles"],
        eb_latched=True,
        sb_latched=False,
        leader_known=True,
        best_rear_m=Fraction(500),
        best_stop_m=Fraction(500),
        last_seq=Fraction(0),
        freshest_sent_s=Fraction(0),
        leader_rear_m=Fraction(600),
        leader_speed_mps=Fraction(0),
        leader_stop_m=Fraction(600),
        on_way=False,
        on_way_rear_m=Fraction(0),
        on_way_speed_mps=Fraction(0),
    )
    assert TWO_TRAINS_REPORTED.init(EXACT, p, s)
    i = ReportedInputs(
        measured_front_m=Fraction(0),
        measured_speed_mps=Fraction(0),
        standstill=True,
        eb_release=False,
        next_speed_mps=Fraction(0),
        distance_m=Fraction(0),
        held=(True, True),
        switch_locked=(False, False),
        switch_reversed=(False, False),
        zone_active=False,
        zone_start_m=Fraction(0),
        now_s=Fraction(1),
        report_intact=True,
        report_seq=Fraction(1),
        report_sent_s=Fraction(1),
        leader_distance_m=Fraction(0),
        leader_next_speed_mps=Fraction(0),
        front_min_m=Fraction("699.995"),
        speed_est_mps=Fraction(0),
        speed_accuracy_mps=Fraction(0),
        clock_s=Fraction(1),
        sent_on=True,
    )
    nxt, out = TWO_TRAINS_REPORTED.step(EXACT, p, s, i)
    two_trains, two_train_out = TWO_TRAINS.step(EXACT, p, s, delivered_report(EXACT, s, i))
    channel, _ = REPORT_CHANNEL.step(
        EXACT, p, s, ChannelInputs(**{f.name: getattr(i, f.name) for f in dataclasses.fields(ChannelInputs)})
    )
    assert out == two_train_out
    assert TwoTrainState(**{f.name: getattr(nxt, f.name) for f in dataclasses.fields(TwoTrainState)}) == two_trains
    assert (nxt.on_way, nxt.on_way_rear_m) == (channel.on_way, channel.on_way_rear_m) == (True, Fraction("599.99"))
    assert not delivered_report(EXACT, s, i).report_delivered
    assert delivered_report(EXACT, nxt, i).report_rear_m == Fraction("599.99")
