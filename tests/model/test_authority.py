"""Movement authority and onboard resource management (seed 001 §3.2-3.3): proved, able to fail, route data
validated."""

import dataclasses
from fractions import Fraction

import pytest

from atcs.model import ats_status, authority
from atcs.model.authority import AUTHORITY, AuthorityInputs, AuthorityParams, AuthorityState
from atcs.model.ops.exact import EXACT
from atcs.model.route import RouteError, read_route, route
from atcs.proofs.mutation.mutants import falsify
from atcs.properties import PROPERTIES

AUTHORITY_PROPERTIES = [p for p in PROPERTIES.values() if p.node is AUTHORITY]

_EOA = "eoa = o.min(d_locked, leader, zone, p.line_end_m, i.front_max_m + p.max_ma_m)"

# property -> (function, text in it, faulty replacement)
MUTANTS = {
    # a resource ahead that is not held is not a limit (only switches are)
    "authority.within_held_resources": (
        authority.locked_end_m,
        "blocked = o.or_(o.not_(i.held[r]), o.not_(confirmed(o, p, i, r)))",
        "blocked = o.not_(confirmed(o, p, i, r))",
    ),
    # a switch trusted before confirmation: the reported direction taken while it is not locked
    "authority.before_unconfirmed_switch": (
        authority.confirmed,
        "o.and_(i.switch_locked[r], in_direction)",
        "in_direction",
    ),
    "authority.before_protection_zone": (authority.authority_step, _EOA, _EOA.replace("zone, ", "")),
    "authority.within_line_and_max_ma": (authority.authority_step, _EOA, _EOA.replace("p.line_end_m, ", "")),
    # the stopping point's bound kept for the limit even in brick-wall mode
    "authority.behind_leader": (
        authority.leader_limit_m,
        "o.ite(certain_only, r.best_rear_m, r.best_stop_m)",
        "r.best_stop_m",
    ),
    # the leader's stopping point computed with a lower (guaranteed) deceleration than its highest
    "authority.leader_bounds_from_reports": (
        authority.stopping_point_m,
        "(o.const(2) * deceleration)",
        "deceleration",
    ),
    # the first report's rear kept as the rear bound only if it is larger than the stale initial value
    "authority.rear_bound_behind_stop_bound": (
        authority.leader_reports,
        "rear = o.ite(first, i.report_rear_m, o.max(s.best_rear_m, i.report_rear_m))",
        "rear = o.max(s.best_rear_m, i.report_rear_m)",
    ),
    # release at the front instead of the rear
    "resources.release_behind_rear": (
        authority.authority_step,
        "p.resource_end_m[r] <= i.rear_min_m",
        "p.resource_end_m[r] <= i.front_max_m",
    ),
    "resources.request_ahead": (
        authority.authority_step,
        "p.resource_start_m[r] < d_request",
        "o.const_bool(True)",
    ),
    "resources.switch_commanded_only_when_held": (
        authority.authority_step,
        "switch_command = tuple(o.and_(i.held[r], o.not_(confirmed(o, p, i, r))) for r in resources)",
        "switch_command = tuple(o.not_(confirmed(o, p, i, r)) for r in resources)",
    ),
    # survivors of atcs mutate, each killed by a property of its own:
    # a blocked resource that ends exactly at the max safe front taken for one ahead
    "authority.locked_end_is_first_blocked": (
        authority.locked_end_m,
        "p.resource_end_m[r] > i.front_max_m",
        "p.resource_end_m[r] >= i.front_max_m",
    ),
    # a later report's lower rear replaces the kept one
    "authority.leader_bounds_never_lowered": (
        authority.leader_reports,
        "o.max(s.best_rear_m, i.report_rear_m)",
        "o.min(s.best_rear_m, i.report_rear_m)",
    ),
    # the latest report's time stamp kept, not the latest time stamp: a late report makes the leader look fresh
    "authority.freshest_report_kept": (
        authority.leader_reports,
        "o.max(s.freshest_sent_s, i.report_sent_s)",
        "i.report_sent_s",
    ),
    # a report exactly as old as the timeout treated as lost
    "authority.stop_credit_while_fresh": (
        authority.leader_limit_m,
        "report_age_s(o, p, r, now_s) > p.report_timeout_s",
        "report_age_s(o, p, r, now_s) >= p.report_timeout_s",
    ),
    # the safety code not checked: a corrupted report, or another train's, is trusted
    "authority.corrupted_report_ignored": (
        authority.report_usable,
        "o.and_(i.report_delivered, i.report_intact)",
        "i.report_delivered",
    ),
    # a report numbered as the last one accepted taken again: a replay is accepted
    "authority.replayed_report_not_fresh": (
        ats_status.message_accepted,
        "seq > last_seq",
        "seq >= last_seq",
    ),
    # the clock skew counted twice over: a report stamped in the future is accepted
    "authority.future_report_not_fresh": (
        ats_status.message_accepted,
        "sent_s <= now_s + clock_skew_max_s",
        "sent_s <= now_s + clock_skew_max_s + clock_skew_max_s",
    ),
    # a resource ending exactly at the min safe rear kept
    "resources.release_when_behind_rear": (
        authority.authority_step,
        "p.resource_end_m[r] <= i.rear_min_m",
        "p.resource_end_m[r] < i.rear_min_m",
    ),
}


def test_every_authority_property_has_a_mutant():
    assert set(MUTANTS) == {p.name for p in AUTHORITY_PROPERTIES}


@pytest.mark.parametrize("prop", AUTHORITY_PROPERTIES, ids=lambda p: p.name)
def test_proved_by_k_induction(prop, proof_suite_run):
    record = proof_suite_run.by_name[prop.name]  # the session's atcs prove run (conftest.py)
    assert (record["status"], record["engine"]) == ("proved", "k-induction"), record["message"]


@pytest.mark.parametrize("name", sorted(MUTANTS))
def test_mutant_falsified_and_counterexample_replays(name):
    run = falsify(PROPERTIES[name], *MUTANTS[name], max_k=2)
    assert run.killed, run


def test_a_release_on_an_unconfirmed_position_is_caught():
    """RES-03's second mutant: resources released behind the rear of a position set again from one tag read."""
    run = falsify(
        PROPERTIES["resources.release_behind_rear"],
        authority.authority_step,
        "o.and_(i.rear_confirmed, i.held[r], p.resource_end_m[r] <= i.rear_min_m)",
        "o.and_(i.held[r], p.resource_end_m[r] <= i.rear_min_m)",
        max_k=2,
    )
    assert run.killed, run


# --- a worked example ----------------------------------------------------------------------------------------------

LINE = route(
    "example",
    [
        {"id": 1, "kind": "track", "start_m": 0, "end_m": 500},
        {"id": 2, "kind": "switch", "start_m": 500, "end_m": 560, "direction": "reverse"},
        {"id": 3, "kind": "track", "start_m": 560, "end_m": 1500},
        {"id": 4, "kind": "track", "start_m": 1500, "end_m": 3000},
    ],
    line_end_m=2900,
)


def _params(**changes) -> AuthorityParams:
    base = dict(
        resource_start_m=tuple(r.start_m for r in LINE.resources),
        resource_end_m=tuple(r.end_m for r in LINE.resources),
        resource_is_switch=tuple(r.is_switch for r in LINE.resources),
        switch_needs_reverse=tuple(r.direction == "reverse" for r in LINE.resources),
        line_end_m=LINE.line_end_m,
        max_ma_m=Fraction(1500),
        leader_max_deceleration_mps2=Fraction(2),
        safety_margin_m=Fraction(20),
        report_timeout_s=Fraction(2),
        clock_skew_max_s=Fraction(1, 10),
        brick_wall=False,
    )
    return AuthorityParams(**{**base, **changes})


def _inputs(**changes) -> AuthorityInputs:
    base = dict(
        front_max_m=Fraction(300),
        rear_min_m=Fraction(90),
        rear_confirmed=True,
        held=(True, True, True, True),
        switch_locked=(False, True, False, False),
        switch_reversed=(False, True, False, False),
        now_s=Fraction(100),
        report_delivered=True,
        report_intact=True,
        report_seq=Fraction(1000),
        report_sent_s=Fraction(999, 10),
        report_rear_m=Fraction(1400),
        report_speed_mps=Fraction(20),
        zone_active=False,
        zone_start_m=Fraction(0),
    )
    return AuthorityInputs(**{**base, **changes})


NO_REPORT = AuthorityState(
    leader_known=False,
    best_rear_m=Fraction(0),
    best_stop_m=Fraction(0),
    last_seq=Fraction(0),
    freshest_sent_s=Fraction(0),
)
KNOWN = AuthorityState(
    leader_known=True,
    best_rear_m=Fraction(1400),
    best_stop_m=Fraction(1500),
    last_seq=Fraction(990),
    freshest_sent_s=Fraction(98),
)
"""The leader known from report 990, sent 2 s before the example's clock (100 s)."""


def _eoa(params=None, inputs=None, state=NO_REPORT):
    _, out = AUTHORITY.step(EXACT, params or _params(), state, inputs or _inputs())
    return out


class TestWorkedExample:
    def test_relative_braking_credits_the_leaders_stopping_distance(self):
        # 1400 + 20^2 / (2 * 2) - 20 = 1480
        assert _eoa().eoa_m == 1480

    def test_brick_wall_and_stale_report_stop_at_the_reported_rear(self):
        assert _eoa(_params(brick_wall=True)).eoa_m == 1380
        # the freshest report sent 2 s ago, plus 0.1 s of clock skew: older than the 2 s timeout
        assert _eoa(inputs=_inputs(report_delivered=False), state=KNOWN).eoa_m == 1380
        fresh = dataclasses.replace(KNOWN, freshest_sent_s=Fraction(99))
        assert _eoa(inputs=_inputs(report_delivered=False), state=fresh).eoa_m == 1480

    def test_a_late_report_is_accepted_but_restores_no_credit(self):
        late = _inputs(report_sent_s=Fraction(95), report_rear_m=Fraction(1450), report_speed_mps=Fraction(0))
        state, out = AUTHORITY.step(EXACT, _params(), KNOWN, late)
        assert out.report_accepted and (state.best_rear_m, state.last_seq) == (1450, 1000)
        assert (out.report_age_s, out.eoa_m) == (Fraction(21, 10), 1430)  # the rear bound, less the margin

    def test_the_best_bounds_are_kept_against_an_older_report(self):
        ahead = dataclasses.replace(KNOWN, best_rear_m=Fraction(1450), best_stop_m=Fraction(1550))
        state, out = AUTHORITY.step(EXACT, _params(), ahead, _inputs())  # rear 1400, stop 1500
        assert (state.best_rear_m, state.best_stop_m, out.eoa_m) == (1450, 1550, 1530)

    def test_a_corrupted_report_is_dropped(self):
        dangerous = _inputs(report_intact=False, report_rear_m=Fraction(5000), report_speed_mps=Fraction(80))
        state, out = AUTHORITY.step(EXACT, _params(), KNOWN, dangerous)
        assert state == KNOWN and not out.report_accepted
        assert out.eoa_m == 1380  # no fresh report: the kept rear less the margin

    @pytest.mark.parametrize(
        "report",
        [
            {"report_seq": Fraction(990)},  # replayed
            {"report_seq": Fraction(989)},  # overtaken by a newer one
            {"report_sent_s": Fraction(1003, 10)},  # stamped 0.3 s ahead of the clock: skew is 0.1 s
        ],
        ids=["replayed", "reordered", "from_the_future"],
    )
    def test_a_report_out_of_sequence_or_time_renews_nothing(self, report):
        """Its bounds are merged (true when sent), but it is no sign of life: the time-out runs on."""
        state, out = AUTHORITY.step(EXACT, _params(), KNOWN, _inputs(report_rear_m=Fraction(1410), **report))
        assert (state.last_seq, state.freshest_sent_s) == (KNOWN.last_seq, KNOWN.freshest_sent_s)
        assert state.best_rear_m == 1410 and not out.report_accepted
        assert out.eoa_m == 1390  # stale: the rear less the margin

    def test_a_switch_not_locked_in_the_routes_direction_limits_the_ma(self):
        out = _eoa(inputs=_inputs(switch_reversed=(False, False, False, False)))
        assert (out.eoa_m, out.d_locked_m, out.switch_command) == (500, 500, (False, True, False, False))

    def test_a_resource_not_held_limits_the_ma_and_is_requested(self):
        out = _eoa(inputs=_inputs(held=(True, True, False, False)))
        assert out.eoa_m == 560 and out.request == (False, False, True, True)

    def test_release_behind_the_rear_only(self):
        assert _eoa(inputs=_inputs(rear_min_m=Fraction(499))).release == (False, False, False, False)
        assert _eoa(inputs=_inputs(rear_min_m=Fraction(500))).release == (True, False, False, False)

    def test_protection_zone_end_of_line_and_max_ma(self):
        assert _eoa(inputs=_inputs(zone_active=True, zone_start_m=Fraction(1000))).eoa_m == 1000
        assert _eoa(inputs=_inputs(report_delivered=False)).eoa_m == 1800  # front 300 + MAX_MA 1500
        assert _eoa(inputs=_inputs(report_delivered=False, front_max_m=Fraction(1600))).eoa_m == 2900


# --- route data ----------------------------------------------------------------------------------------------------


def _resource(**changes):
    return {"id": 1, "kind": "track", "start_m": 0, "end_m": 100, **changes}


class TestRouteData:
    @pytest.mark.parametrize(
        ("resources", "message"),
        [
            ([], "at least one resource"),
            ([_resource(id=True)], "resource 0: id = True is not a whole number"),
            (
                [_resource(), _resource(id=1, start_m=100, end_m=200)],
                "resource 1: id = 1 duplicates the id of resource 0",
            ),
            ([_resource(kind="tunnel")], "resource 0: kind = 'tunnel' is not one of track, switch"),
            ([_resource(), _resource(id=2, start_m=120, end_m=200)], "resource 1: start_m = 120 does not continue"),
            ([_resource(end_m=0)], "resource 0: end_m = 0 is not after start_m = 0"),
            ([_resource(kind="switch")], "resource 0: a switch needs direction = 'normal' or 'reverse', got None"),
            ([_resource(kind="switch", direction="left")], "got 'left'"),
            ([_resource(direction="normal")], "direction = 'normal' is given for a track resource"),
            ([_resource(start_m="x")], "resource 0: start_m = 'x' is not a number"),
            ([_resource(start_m=-5)], "resource 0: start_m = -5 is negative"),
            ([{"id": 1, "kind": "track", "start_m": 0}], "resource 0: end_m is missing"),
            ([_resource(speed=3)], "resource 0: unknown field 'speed'"),
        ],
    )
    def test_malformed_resources_rejected(self, resources, message):
        with pytest.raises(RouteError, match=message):
            route("r", resources, line_end_m=100)

    def test_line_end_within_the_route(self):
        with pytest.raises(RouteError, match=r"line_end_m = 150 is not within the route \(0, 100\]"):
            route("r", [_resource()], line_end_m=150)

    def test_toml_file(self, tmp_path):
        path = tmp_path / "route.toml"
        path.write_text(
            'line_end_m = 560\n[[resource]]\nid = 1\nkind = "track"\nstart_m = 0\nend_m = 500\n'
            '[[resource]]\nid = 2\nkind = "switch"\nstart_m = 500\nend_m = 560\ndirection = "reverse"\n'
        )
        r = read_route(path)
        assert [x.id for x in r.resources] == [1, 2] and r.resources[1].direction == "reverse"
        path.write_text(
            'line_end_m = 560\n[[resource]]\nid = 1\nkind = "track"\nstart_m = 0\nend_m = 500\n'
            '[[resource]]\nid = 2\nkind = "switch"\nstart_m = 500\nend_m = 560\n'
        )
        with pytest.raises(RouteError, match=r"route\.toml: resource 1: a switch needs direction"):
            read_route(path)
        path.write_text("line_end_m = [\n")
        with pytest.raises(RouteError, match=r"route\.toml: not valid TOML"):
            read_route(path)
        path.write_text("[[resource]]\n")
        with pytest.raises(RouteError, match="line_end_m is missing"):
            read_route(path)
        with pytest.raises(RouteError, match="cannot read the route"):
            read_route(tmp_path / "missing.toml")
