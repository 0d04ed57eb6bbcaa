"""The ATS's line status as the train receives it (seed 000 §2.5, 002 §4.2; EN 50159): proved, able to fail, and
a worked example of each defence."""

from fractions import Fraction

import pytest

from atcs.model import ats_status
from atcs.model.ats_status import ATS_STATUS, AtsStatusInputs, AtsStatusParams, AtsStatusState
from atcs.model.ops.exact import EXACT
from atcs.proofs.mutation.mutants import falsify
from atcs.properties import PROPERTIES

ATS_STATUS_PROPERTIES = [p for p in PROPERTIES.values() if p.node is ATS_STATUS]

# property -> (function, text in it, faulty replacement)
MUTANTS = {
    # the time-out forgotten: a status heard once keeps the train running forever
    "ats_status.fresh_exactly_within_timeout": (
        ats_status.ats_status_step,
        "fresh = o.and_(kept.status_known, age <= p.status_timeout_s)",
        "fresh = kept.status_known",
    ),
    # a stale status not acted on: a zone set since may be run into
    "ats_status.stale_status_stops": (
        ats_status.ats_status_step,
        "zone_start = o.ite(fresh, kept.kept_zone_start_m, i.front_max_m)",
        "zone_start = kept.kept_zone_start_m",
    ),
    # zones only ever added: a newer status cannot lift one
    "ats_status.accepted_status_sets_zone": (
        ats_status.ats_status_step,
        "kept_zone_active=o.ite(accepted, i.status_zone_active, s.kept_zone_active)",
        "kept_zone_active=o.or_(s.kept_zone_active, i.status_zone_active)",
    ),
    # a repeated number accepted: a replayed old status lifts a zone set since
    "ats_status.rejected_status_changes_nothing": (
        ats_status.message_accepted,
        "seq > last_seq",
        "seq >= last_seq",
    ),
}


def test_every_ats_status_property_has_a_mutant():
    assert set(MUTANTS) == {p.name for p in ATS_STATUS_PROPERTIES}


@pytest.mark.parametrize("prop", ATS_STATUS_PROPERTIES, ids=lambda p: p.name)
def test_proved_by_k_induction(prop, proof_suite_run):
    record = proof_suite_run.by_name[prop.name]  # the session's atcs prove run (conftest.py)
    assert (record["status"], record["engine"], record["k"]) == ("proved", "k-induction", 0), record["message"]


@pytest.mark.parametrize("name", sorted(MUTANTS))
def test_mutant_falsified_and_counterexample_replays(name):
    run = falsify(PROPERTIES[name], *MUTANTS[name], max_k=1)
    assert run.killed, run


# --- a worked example ----------------------------------------------------------------------------------------------

PARAMS = AtsStatusParams(status_timeout_s=Fraction(2), clock_skew_max_s=Fraction(1, 10))
NOTHING = AtsStatusState(False, Fraction(0), Fraction(0), False, Fraction(0))
ZONE_AT_900 = AtsStatusState(True, Fraction(50), Fraction(99), True, Fraction(900))
"""Status 50, sent at 99 s, set a zone from 900 m."""


def _status(now_s=100, seq=51, sent_s=Fraction(999, 10), delivered=True, intact=True, zone=None) -> AtsStatusInputs:
    return AtsStatusInputs(
        now_s=Fraction(now_s),
        front_max_m=Fraction(300),
        status_delivered=delivered,
        status_intact=intact,
        status_seq=Fraction(seq),
        status_sent_s=Fraction(sent_s),
        status_zone_active=zone is not None,
        status_zone_start_m=Fraction(zone or 0),
    )


def _step(state, inputs):
    return ATS_STATUS.step(EXACT, PARAMS, state, inputs)


class TestWorkedExample:
    def test_not_fresh_until_a_status_arrives(self):
        _, out = _step(NOTHING, _status(delivered=False))
        assert not out.status_fresh and not out.status_accepted
        assert (out.zone_active, out.zone_start_m) == (True, 300)  # a zone from the max safe front: stay
        kept, out = _step(NOTHING, _status(seq=7, zone=400))
        assert out.status_fresh and out.status_accepted and (out.zone_active, out.zone_start_m) == (True, 400)
        assert kept.last_status_seq == 7

    def test_a_newer_status_lifts_the_zone(self):
        _, out = _step(ZONE_AT_900, _status())
        assert out.status_accepted and not out.zone_active

    def test_a_lost_status_lifts_nothing_until_the_timeout(self):
        # 99 s + 2 s timeout - 0.1 s skew: fresh up to 100.9 s by the onboard clock
        _, out = _step(ZONE_AT_900, _status(now_s=Fraction(1009, 10), delivered=False))
        assert out.status_fresh and (out.zone_active, out.zone_start_m) == (True, 900)
        _, out = _step(ZONE_AT_900, _status(now_s=101, delivered=False))
        assert not out.status_fresh and (out.zone_active, out.zone_start_m) == (True, 300)

    @pytest.mark.parametrize(
        "why, changes",
        [
            ("corrupted", dict(intact=False)),
            ("replayed", dict(seq=50)),
            ("overtaken", dict(seq=49, sent_s=Fraction(985, 10))),
            ("from the future", dict(sent_s=Fraction(1012, 10))),
        ],
    )
    def test_a_status_failing_a_check_is_ignored(self, why, changes):
        kept, out = _step(ZONE_AT_900, _status(now_s=101, **changes))
        assert not out.status_accepted, why
        assert kept == ZONE_AT_900 and not out.status_fresh and out.zone_start_m == 300, why
