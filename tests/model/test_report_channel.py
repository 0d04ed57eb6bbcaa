"""The leader's reports on their way (model/separation.py, REPORT_CHANNEL): what the two-train proofs assume of an
intact report (REPORT_REAR, REPORT_STOP) is proved of every report the leader's onboard unit sends (SEP-07,
SEP-08), carried as it is sent (SEP-09), each with a mutant falsified and its counterexample replayed; and the
channel's step delivers exactly the report on its way."""

from fractions import Fraction

import pytest

from atcs.model import separation
from atcs.model.ops.exact import EXACT
from atcs.model.separation import REPORT_CHANNEL, ChannelInputs, ChannelParams, ChannelState
from atcs.model.t2t_message import report_quantities
from atcs.proofs.mutation.mutants import falsify
from atcs.properties import PROPERTIES, select
from atcs.properties.report_channel import LEADER_POSITION
from atcs.properties.separation import REPORT_REAR, REPORT_STOP

CHANNEL_PROPERTIES = select("report_channel.*")

# property -> (function, text in it, faulty replacement)
MUTANTS = {
    # the leader's min front reported as its rear: ahead of its true rear by up to its length
    "report_channel.delivered_rear_behind_leader": (
        separation.report_channel_step,
        "sent_report(o, p.leader_length_m,",
        "sent_report(o, o.const(0),",
    ),
    # the speed estimate reported with its accuracy added: faster than the leader may be
    "report_channel.delivered_stop_behind_leader": (
        separation.report_channel_step,
        "sent_report(o, p.leader_length_m, i.front_min_m, i.speed_est_mps, i.speed_accuracy_mps, i.clock_s)",
        "sent_report(o, p.leader_length_m, i.front_min_m, i.speed_est_mps + i.speed_accuracy_mps, o.const(0), "
        "i.clock_s)",
    ),
    # the leader's earliest stopping point taken from its rear before this cycle's motion
    "report_channel.leader_stop_is_earliest": (
        separation.leader_moves,
        "earliest_stop_m(o, p, rear, i.leader_next_speed_mps)",
        "earliest_stop_m(o, p, s.leader_rear_m, i.leader_next_speed_mps)",
    ),
    # a channel that never delivers: SEP-07 and SEP-08 would hold of it vacuously
    "report_channel.sent_report_on_its_way": (
        separation.report_channel_step,
        "on_way=o.or_(s.on_way, i.sent_on)",
        "on_way=s.on_way",
    ),
}


def test_every_channel_property_has_a_mutant():
    assert set(MUTANTS) == {p.name for p in CHANNEL_PROPERTIES}


@pytest.mark.parametrize("prop", CHANNEL_PROPERTIES, ids=lambda p: p.name)
def test_proved_by_k_induction(prop, proof_suite_run):
    record = proof_suite_run.by_name[prop.name]  # the session's atcs prove run (conftest.py)
    assert (record["status"], record["engine"]) == ("proved", "k-induction"), record["message"]


@pytest.mark.parametrize("name", sorted(MUTANTS))
def test_mutant_falsified_and_counterexample_replays(name):
    run = falsify(PROPERTIES[name], *MUTANTS[name], max_k=4)
    assert run.killed, run


def test_the_properties_state_the_two_train_assumptions():
    """SEP-07 and SEP-08 apply the very predicates REPORT_REAR and REPORT_STOP apply to a delivered report."""
    assert "report_behind" in REPORT_REAR.holds.__code__.co_names
    assert "report_stop_behind" in REPORT_STOP.holds.__code__.co_names
    for name, predicate in (
        ("delivered_rear_behind_leader", "report_behind"),
        ("delivered_stop_behind_leader", "report_stop_behind"),
    ):
        assert predicate in PROPERTIES[f"report_channel.{name}"].holds.__code__.co_names
    assert LEADER_POSITION.name == "leader_position"


def test_a_report_is_delivered_as_sent_and_kept_until_replaced():
    p = ChannelParams(leader_length_m=Fraction(100), leader_max_deceleration_mps2=Fraction(3), cycle_s=Fraction(1, 10))
    s = ChannelState(Fraction(1000), Fraction(20), Fraction(1000) + Fraction(400, 6), False, Fraction(0), Fraction(0))
    assert REPORT_CHANNEL.init(EXACT, p, s)
    sent = ChannelInputs(
        leader_distance_m=Fraction(2),
        leader_next_speed_mps=Fraction(20),
        front_min_m=Fraction("1099.995"),
        speed_est_mps=Fraction("20.5"),
        speed_accuracy_mps=Fraction("0.505"),
        clock_s=Fraction(7),
        sent_on=True,
    )
    s, out = REPORT_CHANNEL.step(EXACT, p, s, sent)
    assert not out.delivered
    rear, speed, _ = report_quantities(EXACT, Fraction("999.995"), Fraction("19.995"), Fraction(7))
    assert (
        (s.on_way, s.on_way_rear_m, s.on_way_speed_mps)
        == (True, rear, speed)
        == (True, Fraction("999.99"), Fraction("19.99"))
    )
    for _ in range(3):  # repeated while nothing replaces it
        s, out = REPORT_CHANNEL.step(EXACT, p, s, ChannelInputs(**{**sent.__dict__, "sent_on": False}))
        assert (out.delivered, out.delivered_rear_m, out.delivered_speed_mps) == (True, rear, speed)
