"""Position determination (seed 001 §3.2, 002 §3.1): proved, able to fail, checked in simulation, tag tables validated.

Each property has a mutant: the real step (or a helper it calls) with one deliberate
fault, made from its source. The engine must falsify the property on the mutant, the
counterexample must replay on the mutant, and the real model must not violate the
property on the same run.
"""

import dataclasses
from fractions import Fraction

import pytest
from hypothesis import event, settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, initialize, invariant, precondition, rule

from atcs.model import position, position_loop
from atcs.model.ops.exact import EXACT
from atcs.model.position import (
    PositionParams,
    TagTableError,
    position_params,
    read_tag_table,
    seed000_tags,
    seed002_tags,
    tag_table,
)
from atcs.model.position_loop import POSITION_LOOP, PositionLoopInputs, PositionLoopParams, PositionLoopState
from atcs.proofs.engine.prove import prove
from atcs.proofs.mutation.mutants import falsify
from atcs.properties import PROPERTIES, select
from atcs.sim.monitor import Monitor, Traces

POSITION_PROPERTIES = select("position.*")
TRACES = Traces()
"""The position loop and its properties traced once for the runs of this module (the real model: no mutant runs
through a monitor)."""

_FAULTS = "unknown_tag, unexpected_tag, tag_passage_outside_cycle, tag_outside_window, missed_tag, implausible_tacho"


def _without(flag):
    """The fault that ``flag`` raises no longer invalidates the position."""
    return (position.position_step, _FAULTS, _FAULTS.replace(f"{flag}, ", "").replace(f", {flag}", ""))


# property -> (function, text in it, faulty replacement)
MUTANTS = {
    "position.lrt_in_table": (
        position.position_step,
        "lrt_index = o.ite(reset, read_index, s.lrt_index)",
        "lrt_index = o.ite(reset, read_index + one, s.lrt_index)",
    ),
    # the tachometer error not taken into the min safe front
    "position.front_in_interval": (
        position.odometry_interval,
        "(o.const(1) - p.tacho_error) * offset_m",
        "offset_m",
    ),
    # after a tag, the offset starts from 0 (the front taken to be at the tag at the cycle's end) instead of from
    # the tachometer's distance since the passage: wrong at speed
    "position.front_within_sensor_excess": (
        position.position_step,
        "offset = o.ite(reset, i.since_tag_m, offset)",
        "offset = o.ite(reset, zero, offset)",
    ),
    # the tachometer's stated error not allowed for: a tachometer within it counted as beyond it
    "position.nominal_sensors_add_no_excess": (
        position_loop.tacho_excess_m,
        "distance_m - tacho_m - allowed",
        "distance_m - tacho_m",
    ),
    # the interval still counted from the previous reference tag after a read: the new tag corrects nothing
    "position.genuine_tag_corrects": (
        position.position_step,
        "ref = o.select(p.tag_positions_m, lrt_index)",
        "ref = o.select(p.tag_positions_m, s.lrt_index)",
    ),
    # the window check with a tag window of slack on each side: a wrong tag accepted further off
    "position.misread_tag_bounded": (
        position.position_step,
        "o.or_(high < tag_low, low > tag_high)",
        "o.or_(high + w < tag_low, low > tag_high + w)",
    ),
    # confirmed by the tag that sets the position from an invalid one
    "position.confirmed_by_a_second_tag": (
        position.position_step,
        "o.or_(s.confirmed, o.and_(s.localised, reset))",
        "o.or_(s.confirmed, reset)",
    ),
    # never confirmed by a tag
    "position.confirmed_at_next_tag": (
        position.position_step,
        "o.or_(s.confirmed, o.and_(s.localised, reset))",
        "o.or_(s.confirmed, o.and_(s.localised, reset, s.confirmed))",
    ),
    # the rear taken from the estimated front, without the confidence interval
    "position.rear_in_interval": (
        position.position_step,
        "rear_min_m=front_min - p.train_length_m",
        "rear_min_m=ref + offset - p.train_length_m",
    ),
    # the mean speed of the cycle taken for the speed at its end
    "position.speed_within_accuracy": (position.speed_accuracy_mps, "a * p.cycle_s / o.const(2)", "o.const(0)"),
    "position.unexpected_tag_invalidates": _without("unexpected_tag"),
    "position.unknown_tag_invalidates": _without("unknown_tag"),
    "position.tag_outside_window_invalidates": _without("tag_outside_window"),
    "position.tag_passage_outside_cycle_invalidates": _without("tag_passage_outside_cycle"),
    "position.missed_tag_invalidates": _without("missed_tag"),
    "position.implausible_tacho_invalidates": _without("implausible_tacho"),
    # supervision not told that the position is lost
    "position.eb_while_invalid": (
        position_loop.position_loop_step,
        "i.eb_release, position.position_valid)",
        "i.eb_release, o.const_bool(True))",
    ),
    # the first tag after power-up taken for the tag after the last one read
    "position.front_between_lrt_and_next": (
        position.position_step,
        "lrt_index = o.ite(reset, read_index, s.lrt_index)",
        "lrt_index = o.ite(reset, next_index, s.lrt_index)",
    ),
    # the plausibility check without the tachometer error's slack: false alarms under tachometer noise
    "position.no_false_alarm": (
        position.implausible_increment,
        "slack = p.tacho_error * (tacho_m + last_m)",
        "slack = o.const(0)",
    ),
    # standstill detected below 1 m per cycle: EB released while creeping
    "position.eb_held_while_moving": (
        position.position_step,
        "standstill=o.eq(i.tacho_m, zero)",
        "standstill=i.tacho_m < o.const(1)",
    ),
    # survivors of atcs mutate: the estimate supervised without its accuracy
    "position.supervised_on_true_speed": (
        position_loop.position_loop_step,
        "speed = position.speed_est_mps + position.speed_accuracy_mps",
        "speed = position.speed_est_mps",
    ),
    # the service brake held at exactly the permitted speed
    "position.no_intervention_at_permitted": (
        position_loop.position_loop_step,
        "over_permitted=speed > i.permitted_mps",
        "over_permitted=speed >= i.permitted_mps",
    ),
    # every read taken for an unexpected one, so the position is never valid (atcs mutate's bool_swap at
    # position_step:+14)
    "position.localises_at_known_tag": (
        position.position_step,
        "unexpected_tag = o.and_(s.localised, i.tag_read, known, o.not_(expected))",
        "unexpected_tag = o.or_(s.localised, i.tag_read, known, o.not_(expected))",
    ),
    # the window's upper edge exclusive (cmp_strict at position_step:+15)
    "position.no_fault_within_window": (
        position.position_step,
        "o.or_(high < tag_low, low > tag_high)",
        "o.or_(high <= tag_low, low > tag_high)",
    ),
}


def test_every_position_property_has_a_mutant():
    assert set(MUTANTS) == {p.name for p in POSITION_PROPERTIES}


class TestProved:
    @pytest.mark.parametrize("prop", POSITION_PROPERTIES, ids=lambda p: p.name)
    def test_proved_by_k_induction(self, prop, proof_suite_run):
        record = proof_suite_run.by_name[prop.name]  # the session's atcs prove run (conftest.py)
        assert (record["status"], record["engine"]) == ("proved", "k-induction"), record["message"]

    def test_the_interval_claim_needs_no_motion_bounds(self):
        names = {a.name for a in PROPERTIES["position.front_in_interval"].assumptions}
        assert names == {"table", "tachometer", "tag_reader"}


class TestMutantsAreFalsified:
    @pytest.mark.parametrize("name", sorted(MUTANTS))
    def test_mutant_falsified_and_counterexample_replays(self, name):
        run = falsify(PROPERTIES[name], *MUTANTS[name], max_k=6)
        assert run.killed, run

    def test_the_error_convention_matters(self):
        """Tachometer error as a fraction of the *true* distance (not the measured one) breaks the interval:
        the formula's (1 + e) * d is then short of d / (1 - e)."""
        prop = PROPERTIES["position.front_in_interval"]
        true_fraction = dataclasses.replace(
            prop.assumptions[1],
            holds=lambda o, p, s, i: o.and_(
                i.distance_m - i.tacho_m <= p.tacho_error * i.distance_m,
                i.tacho_m - i.distance_m <= p.tacho_error * i.distance_m,
            ),
        )
        wrong = dataclasses.replace(prop, assumptions=(prop.assumptions[0], true_fraction, prop.assumptions[2]))
        result = prove(wrong, timeout_s=120, max_k=4)
        assert result.status == "falsified", result.message


# --- tag tables ------------------------------------------------------------------------------------------------


class TestTagTables:
    def test_seed_presets(self):
        t = seed000_tags()
        assert (len(t), t.ids[0], t.positions_m[0], t.ids[-1], t.positions_m[-1]) == (151, 1, 0, 1501, 15_000)
        g = seed002_tags()
        assert g.positions_m[:4] == (0, 5, 200, 205) and g.ids[:4] == (1, 2, 11, 12)
        assert g.positions_m[-1] <= 56_800

    def test_duplicate_id_rejected(self):
        with pytest.raises(TagTableError, match=r"line: tag 2: id = 7 duplicates the id of tag 0"):
            tag_table("line", [7, 8, 7], [0, 100, 200])

    @pytest.mark.parametrize("positions", [[0, 100, 100], [0, 200, 100]])
    def test_unsorted_positions_rejected(self, positions):
        with pytest.raises(TagTableError, match=rf"line: tag 2: position_m = {positions[2]} is not after tag 1's"):
            tag_table("line", [1, 2, 3], positions)

    @pytest.mark.parametrize(
        ("ids", "positions", "message"),
        [
            ([1, 2], [0], "2 ids but 1 positions"),
            ([1], [0], "at least 2 tags"),
            ([1, "x"], [0, 1], "tag 1: id = 'x' is not a number"),
            ([1, 2.5], [0, 1], "tag 1: id = 2.5 is not a whole number"),
            ([1, 2], [0, float("nan")], "tag 1: position_m = nan is not finite"),
        ],
    )
    def test_malformed_entries_rejected(self, ids, positions, message):
        with pytest.raises(TagTableError, match=message):
            tag_table("line", ids, positions)

    def test_csv_errors_name_the_file_and_line(self, tmp_path):
        path = tmp_path / "tags.csv"
        path.write_text("id,position_m\n1,0\n2,100\n2,200\n")
        with pytest.raises(TagTableError, match=r"tags\.csv: line 4: id = '2' duplicates the id of line 3"):
            read_tag_table(path)
        path.write_text("id,position_m\n1,0\n2,100\n3,50\n")
        with pytest.raises(TagTableError, match=r"tags\.csv: line 4: position_m = '50' is not after line 3's 100"):
            read_tag_table(path)
        path.write_text("tag,pos\n1,0\n")
        with pytest.raises(TagTableError, match="the header must be 'id,position_m'"):
            read_tag_table(path)
        path.write_text("id,position_m\n1,0,9\n")
        with pytest.raises(TagTableError, match="line 2: expected 2 fields"):
            read_tag_table(path)
        with pytest.raises(TagTableError, match="cannot read the tag table"):
            read_tag_table(tmp_path / "missing.csv")

    def test_pulses_to_distance(self):
        # 100 pulses per revolution on an 860 mm wheel: one revolution is pi * 0.86 m
        assert position.tacho_distance_m(250, 0.86, 100) == pytest.approx(2.5 * 3.141592653589793 * 0.86)

    def test_csv_round_trip(self, tmp_path):
        path = tmp_path / "tags.csv"
        path.write_text("id,position_m\n1,0\n11,100.5\n")
        assert read_tag_table(path) == tag_table("x", [1, 11], [0, Fraction(201, 2)])

    @pytest.mark.parametrize(
        ("field", "value", "message"),
        [
            ("tacho_error", 1, r"tacho_error = 1 is outside \[0, 1\)"),
            ("tag_window_m", -1, "tag_window_m = -1 is negative"),
            ("cycle_s", 0, "cycle_s = 0 is not positive"),
            ("train_length_m", "long", "train_length_m = 'long' is not a number"),
        ],
    )
    def test_position_params_validated(self, field, value, message):
        with pytest.raises(TagTableError, match=message):
            position_params(seed000_tags(), **{**POSITION_DATA, field: value})


# --- simulation: the same step and predicates on exact numbers ---------------------------------------------------

POSITION_DATA = dict(
    tag_window_m=3,
    tacho_error=Fraction(1, 50),
    train_length_m=200,
    cycle_s=Fraction(1, 10),
    max_acceleration_mps2=1,
    max_deceleration_mps2=Fraction(3, 2),
)
LINE = tag_table("test line", [x // 10 + 1 for x in range(0, 2001, 100)], list(range(0, 2001, 100)))
TOP_SPEED_MPS = Fraction(875, 9)  # 350 km/h: 9.7 m per cycle, over three times the 3 m tag window


def _params(table=LINE) -> PositionLoopParams:
    p: PositionParams = position_params(table, **POSITION_DATA)
    return PositionLoopParams(**dataclasses.asdict(p), service_brake_fitted=True)


def _power_up(front_m) -> PositionLoopState:
    """The loop at power-up, at standstill with its front at ``front_m``: no position, EB."""
    zero = Fraction(0)
    return PositionLoopState(
        localised=False,
        lrt_index=zero,
        offset_m=zero,
        last_tacho_m=zero,
        confirmed=False,
        eb_latched=True,
        sb_latched=False,
        front_m=front_m,
        speed_mps=zero,
        last_distance_m=zero,
        sensor_excess_m=zero,
    )


def _motion(p, speed_mps, accel_mps2):
    """One cycle at a constant acceleration (stopping within the cycle if it brakes to 0): (next speed,
    distance), capped at the top speed."""
    dt = p.cycle_s
    v_next = min(max(Fraction(0), speed_mps + accel_mps2 * dt), Fraction(TOP_SPEED_MPS))
    if v_next == 0 and accel_mps2 < 0:
        return v_next, speed_mps * speed_mps / (2 * -accel_mps2) if speed_mps else Fraction(0)
    return v_next, (speed_mps + v_next) / 2 * dt


def _free_running(read, tag_id, since_tag_m, tacho_m, distance_m, distance_since_tag_m, next_speed_mps):
    """One cycle's inputs with every supervision limit far above the speed; the EB released at standstill."""
    far = Fraction(1000)
    return PositionLoopInputs(
        tag_read=read,
        tag_id=tag_id,
        since_tag_m=since_tag_m,
        tacho_m=tacho_m,
        distance_m=distance_m,
        distance_since_tag_m=distance_since_tag_m,
        next_speed_mps=next_speed_mps,
        permitted_mps=far,
        warning_mps=far,
        sbi_mps=far,
        ebi_mps=far,
        eb_release=next_speed_mps == 0,
    )


class PositionMachine(RuleBasedStateMachine):
    """Drive the position loop on the exact backend with random motion and tachometer noise within the stated
    bounds, the tag reader reporting each tag in the cycle the front passes it. Every position property is
    checked each cycle by the Monitor (the very predicates of the proofs); the position, once found, is never
    lost (no false alarm). Fault rules break one sensor and check the ATP's reaction."""

    @initialize(start_m=st.integers(0, 1500))
    def power_up(self, start_m):
        p = _params()
        start = _power_up(Fraction(start_m))
        self.monitor = Monitor(POSITION_LOOP, p, start, tuple(POSITION_PROPERTIES), ops=EXACT, traces=TRACES)
        self.found = False  # a tag has been read since power-up
        self.faulty = False  # a sensor fault was injected: no-false-alarm no longer claimed
        self.skipped = None  # the position of a tag whose read was suppressed
        self.out = None

    def _cycle(self, accel_mps2, noise, *, tag=True, tag_id=None, slip=1):
        p, s = self.monitor.params, self.monitor.state
        v_next, distance = _motion(p, s.speed_mps, accel_mps2)
        tacho = distance * (1 + noise * p.tacho_error / 2) * slip
        passed = [j for j, x in enumerate(p.tag_positions_m) if s.front_m < x <= s.front_m + distance]
        read = (tag and bool(passed)) or tag_id is not None
        if passed and not tag:
            self.skipped = p.tag_positions_m[passed[0]]
        reported = tag_id if tag_id is not None else (p.tag_ids[passed[0]] if passed else Fraction(0))
        since = s.front_m + distance - p.tag_positions_m[passed[0]] if passed else Fraction(0)
        self.out = self.monitor.step(
            _free_running(read, reported, since * tacho / distance if passed else since, tacho, distance, since, v_next)
        )
        self.found = self.found or (read and not self.faulty)
        if read:
            event("tag read")
        return self.out

    @rule(accel=st.fractions(-Fraction(3, 2), 1, max_denominator=4), noise=st.fractions(-1, 1, max_denominator=8))
    def drive(self, accel, noise):
        self._cycle(accel, noise)

    @rule(accel=st.fractions(0, 1, max_denominator=4), cycles=st.integers(1, 250))
    def run(self, accel, cycles):
        """Many cycles at once, so the train reaches tags."""
        for _ in range(cycles):
            self._cycle(accel, Fraction((-1) ** self.monitor.step_count))

    @precondition(lambda self: self.found and not self.faulty)
    @rule(tag_id=st.sampled_from([0, 5, 1501, 1, 101, 201]))
    def spurious_tag(self, tag_id):
        """A tag that is not the next one (or not in the table at all): lost in that cycle, EB."""
        p, s = self.monitor.params, self.monitor.state
        next_id = p.tag_ids[int(s.lrt_index) + 1] if s.lrt_index + 1 < len(p.tag_ids) else None
        out = self._cycle(Fraction(0), Fraction(0), tag=False, tag_id=Fraction(tag_id))
        self.faulty = True
        event("spurious tag: the next tag's id" if tag_id == next_id else "spurious tag: tripped")
        assert tag_id == next_id or (not out.position_valid and out.emergency_brake)

    @precondition(lambda self: self.found and not self.faulty and self.monitor.state.speed_mps > 5)
    @rule(slip=st.sampled_from([0, Fraction(1, 2), 2]))
    def tachometer_fault(self, slip):
        """A stuck tachometer, a slide or a spin while running: lost in that cycle, EB."""
        out = self._cycle(Fraction(0), Fraction(0), slip=slip)
        self.faulty = True
        event("tachometer fault: tripped")
        assert not out.position_valid and out.emergency_brake

    @precondition(lambda self: self.found and not self.faulty and self.monitor.state.front_m < 1700)
    @rule()
    def miss_next_tag(self):
        """The reader misses the next tag: lost before (or in) the cycle the tag after it is read."""
        self.faulty = True
        self.skipped = None
        while self.skipped is None:
            self._cycle(Fraction(1, 2), Fraction(0), tag=False)
        while self.out.position_valid:
            s, p = self.monitor.state, self.monitor.params
            upcoming = [x for x in p.tag_positions_m if s.front_m < x]
            assert upcoming, "ran off the line with the position still valid"
            self._cycle(Fraction(1, 2), Fraction(0))
        assert self.out.emergency_brake
        event("missed tag: tripped")

    @invariant()
    def position_kept_without_faults(self):
        if self.out is not None and self.found and not self.faulty:
            assert self.out.position_valid, "a fault-free run lost its position"
            assert self.out.front_min_m <= self.monitor.state.front_m <= self.out.front_max_m

    @invariant()
    def properties_checked(self):
        if not self.faulty:
            assert all(self.monitor.applies(p.name) for p in POSITION_PROPERTIES), "left the assumptions"


TestPositionStateful = pytest.mark.slow(PositionMachine.TestCase)
TestPositionStateful.settings = settings(max_examples=25, stateful_step_count=12)  # a run drives hundreds of cycles


@pytest.mark.slow
def test_position_kept_from_standstill_to_350_kmh():
    """Tags reported with the tachometer's distance since their passage: the position stays valid and every
    position property holds each cycle while the train accelerates from standstill to 350 km/h (9.7 m a cycle,
    over three times the tag window) and runs on past tags at that speed."""
    table = tag_table("fast line", range(1, 22), range(0, 8001, 400))
    p = _params(table)
    start = _power_up(Fraction(-1))
    monitor = Monitor(POSITION_LOOP, p, start, tuple(POSITION_PROPERTIES), ops=EXACT, traces=TRACES)
    tags_read, top = 0, Fraction(0)
    while monitor.state.front_m < 7_900:
        s = monitor.state
        v_next, distance = _motion(p, s.speed_mps, Fraction(1))
        passed = [j for j, x in enumerate(p.tag_positions_m) if s.front_m < x <= s.front_m + distance]
        assert len(passed) <= 1
        since = s.front_m + distance - p.tag_positions_m[passed[0]] if passed else Fraction(0)
        noise = 1 + Fraction((-1) ** monitor.step_count, 100)  # the tachometer within its 2 % error
        tag_id = p.tag_ids[passed[0]] if passed else p.tag_ids[0]
        out = monitor.step(
            _free_running(bool(passed), tag_id, since * noise, distance * noise, distance, since, v_next)
        )
        assert all(monitor.applies(q.name) for q in POSITION_PROPERTIES), "left the assumptions"
        assert out.position_valid or tags_read == 0, f"position lost at {float(monitor.state.front_m):.1f} m"
        tags_read += bool(passed)
        assert out.position_confirmed == (tags_read >= 2)  # set at the first tag, confirmed by the second
        top = max(top, monitor.state.speed_mps)
    assert top == TOP_SPEED_MPS and tags_read == 20
