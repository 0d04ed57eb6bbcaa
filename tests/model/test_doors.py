"""Door-opening protection (seed 004 §2.1): the door properties are proved, can fail, and hold in simulation,
with the platform table decoded from a packet as the wayside sends it."""

from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from atcs.model import doors
from atcs.model.doors import (
    DCU,
    DOOR_ENABLE,
    DOOR_LOOP,
    DcuInputs,
    DcuState,
    DoorEnableInputs,
    DoorLoopInputs,
    DoorParams,
)
from atcs.model.node import Stateless
from atcs.model.ops.exact import EXACT
from atcs.model.platform_packets import encode_packet69
from atcs.model.platforms import Platform, packet_for_platforms, platform_data, platform_inputs
from atcs.proofs.mutation.mutants import falsify, mutant_node
from atcs.properties import PROPERTIES, select
from atcs.sim.monitor import Monitor, PropertyViolation

DOOR_PROPERTIES = select("doors.*")

# property -> faults, each (function, text in its source, faulty replacement); every one must be killed
MUTANTS = {
    "doors.enable_left_only_at_platform_stop": [
        # the rearmost door checked at the foremost front: a rear door may open off the platform's start
        (
            doors.platform_covers_doors,
            "i.platform_start_m[j] <= i.front_min_m - p.last_door_m",
            "i.platform_start_m[j] <= i.front_max_m - p.last_door_m",
        ),
        # zero-speed detection with a threshold
        (doors.door_enable, "i.speed_mps <= o.const(0)", "i.speed_mps <= o.const(1)"),
        # the standstill signal not checked
        (doors.door_enable, "held = o.and_(i.standstill, ", "held = o.and_("),
        # immobilisation not checked
        (doors.door_enable, "i.immobilised, stopped_at_stopping_point", "stopped_at_stopping_point"),
    ],
    "doors.enable_right_only_at_platform_stop": [
        # sides mixed up: the right doors released onto a left platform
        (
            doors.door_enable,
            "platform_covers_doors(o, p, i, i.platform_right)",
            "platform_covers_doors(o, p, i, i.platform_left)",
        ),
        # the estimate's end instead of the interval's: the stopping tolerance checked at one end only
        (
            doors.stopped_at_stopping_point,
            "i.front_max_m <= i.stopping_point_m + i.stop_tolerance_m",
            "i.front_min_m <= i.stopping_point_m + i.stop_tolerance_m",
        ),
        # a train that does not know its position
        (doors.stopped_at_stopping_point, "        i.position_valid,\n", ""),
    ],
    "doors.traction_cut_while_unlocked": [
        # the DCU reports the left side only
        (doors.closed_and_locked, "o.or_(s.door_open_left, s.door_open_right)", "s.door_open_left"),
        # the interlock's cut-off not passed on to traction
        (
            doors.door_loop_step,
            "traction_cut = o.or_(atp.traction_cut, i.supervision_traction_cut)",
            "traction_cut = i.supervision_traction_cut",
        ),
        # the interlock reads one detection loop: a lying sensor on it lets the train drive with a door open
        (
            doors.door_enable,
            "traction_cut=o.not_(o.and_(closed_loop_a, closed_loop_b))",
            "traction_cut=o.not_(closed_loop_a)",
        ),
    ],
    "doors.open_only_with_enable_and_command": [
        (doors.door_next, "opens = o.and_(enable, command)", "opens = command"),
        (doors.door_next, "opens = o.and_(enable, command)", "opens = enable"),
    ],
    "doors.close_when_enable_drops": [
        (doors.door_next, "closing = o.or_(o.not_(enable), close)", "closing = close"),
    ],
    "doors.enable_at_platform_stop": [
        # the stopping tolerance checked strictly: a train stopped exactly at its edge is refused (atcs mutate)
        (
            doors.stopped_at_stopping_point,
            "i.front_max_m <= i.stopping_point_m + i.stop_tolerance_m",
            "i.front_max_m < i.stopping_point_m + i.stop_tolerance_m",
        ),
        # every platform of the table required to span the doors, not one
        (doors.platform_covers_doors, "return o.or_(", "return o.and_("),
    ],
    "doors.traction_as_requested_unless_cut": [
        # traction applied whenever it is not cut, requested or not (atcs mutate)
        (
            doors.door_loop_step,
            "o.and_(i.traction_request, o.not_(traction_cut))",
            "o.or_(i.traction_request, o.not_(traction_cut))",
        ),
        # the doors taken as closed on either loop's word: a loop stuck closed hides an open door (atcs mutate)
        (doors.door_loop_step, "closed_locked=o.and_(loop_a, loop_b)", "closed_locked=o.or_(loop_a, loop_b)"),
        # a loop that reports closed only when stuck: closed doors cut traction (atcs mutate)
        (doors.door_loop_step, "o.or_(closed, i.loop_a_stuck_closed)", "o.and_(closed, i.loop_a_stuck_closed)"),
    ],
    "doors.dcu_follows_commands": [
        # a door that opens only if it is open already: it never opens (atcs mutate)
        (doors.door_next, "return o.or_(opens, ", "return o.and_(opens, "),
        # an open door closes as soon as it is not obstructed, though still enabled
        (doors.door_next, "o.or_(o.not_(closing), obstructed)", "o.and_(o.not_(closing), obstructed)"),
    ],
    "doors.open_only_at_platform_stop": [
        # the DCU wired to the ATO's request instead of the ATP's enable
        (
            doors.door_loop_step,
            "enable_left=atp.enable_left,\n            enable_right",
            "enable_left=i.request_left,\n            enable_right",
        ),
    ],
}
CASES = [(name, j) for name, faults in sorted(MUTANTS.items()) for j in range(len(faults))]


def test_every_door_property_has_a_mutant():
    assert set(MUTANTS) == {p.name for p in DOOR_PROPERTIES}


class TestProved:
    @pytest.mark.parametrize("prop", DOOR_PROPERTIES, ids=lambda p: p.name)
    def test_proved_by_k_induction(self, prop, proof_suite_run):
        record = proof_suite_run.by_name[prop.name]  # the session's atcs prove run (conftest.py)
        assert (record["status"], record["engine"]) == ("proved", "k-induction"), record["message"]

    def test_platform_table_and_door_geometry_are_symbolic(self):
        prop = PROPERTIES["doors.enable_left_only_at_platform_stop"]
        assert prop.fixed_params == {} and DOOR_ENABLE.sizes["platform_start_m"] == doors.PROOF_PLATFORMS >= 2


class TestMutantsAreFalsified:
    @pytest.mark.parametrize(("name", "j"), CASES, ids=[f"{n}-{j}" for n, j in CASES])
    def test_mutant_falsified_and_counterexample_replays(self, name, j):
        run = falsify(PROPERTIES[name], *MUTANTS[name][j], max_k=4)
        assert run.killed, run


# --- a platform stop, with the platform table from a packet ----------------------------------------------

REFERENCE_M = Fraction(4500)
PLATFORMS = (
    Platform(Fraction(4600), Fraction(4850), "right", 760),
    Platform(Fraction(5800), Fraction(6050), "left", 760),
)
PACKET_HEX = encode_packet69(packet_for_platforms(PLATFORMS, REFERENCE_M)).hex()
TRAIN = DoorParams(first_door_m=Fraction(5), last_door_m=Fraction(195))  # a 200 m train
STOP_M, TOLERANCE_M = Fraction(4840), Fraction(1, 2)
LOOP_PROPERTIES = tuple(p for p in DOOR_PROPERTIES if p.node is DOOR_LOOP)


def loop_inputs(
    table=PLATFORMS,
    *,
    front=STOP_M,
    spread=Fraction(1, 10),
    speed=0,
    immobilised=True,
    request_left=False,
    request_right=True,
    open_left=False,
    open_right=False,
    close=False,
    obstructed=False,
    traction=False,
):
    return DoorLoopInputs(
        position_valid=True,
        front_min_m=front - spread,
        front_max_m=front + spread,
        speed_mps=Fraction(speed),
        standstill=speed == 0,
        immobilised=immobilised,
        stopping_point_m=STOP_M,
        stop_tolerance_m=TOLERANCE_M,
        **platform_inputs(table, doors.PROOF_PLATFORMS),
        request_left=request_left,
        request_right=request_right,
        probe_front_m=front - spread,
        probe_door_m=TRAIN.last_door_m,
        open_left=open_left,
        open_right=open_right,
        close=close,
        obstructed_left=obstructed,
        obstructed_right=obstructed,
        loop_a_stuck_closed=False,
        loop_b_stuck_closed=False,
        traction_request=traction,
        supervision_traction_cut=False,
    )


def platform_stop_monitor(node=DOOR_LOOP):
    return Monitor(node, TRAIN, DcuState(door_open_left=False, door_open_right=False), LOOP_PROPERTIES, ops=EXACT)


class TestPlatformStop:
    def test_the_table_comes_from_the_packet(self):
        section = {"packet": PACKET_HEX, "reference_m": 4500}
        assert platform_data(section, "scenario.toml") == PLATFORMS

    def test_doors_cycle_at_the_platform(self):
        table = platform_data({"packet": PACKET_HEX, "reference_m": 4500}, "scenario.toml")
        monitor = platform_stop_monitor()
        out = monitor.step(loop_inputs(table, front=STOP_M - 30, speed=5, immobilised=False, traction=True))
        assert not out.enable_right and out.traction_applied  # running in: no enable
        out = monitor.step(loop_inputs(table, open_right=True))  # stopped and held at the stopping point
        assert out.enable_right and not out.enable_left and monitor.state.door_open_right
        out = monitor.step(loop_inputs(table, traction=True))  # dwell: the doors are open
        assert out.traction_cut and not out.traction_applied and not out.closed_locked
        monitor.step(loop_inputs(table, close=True))
        assert not monitor.state.door_open_right
        out = monitor.step(loop_inputs(table, immobilised=False, traction=True))
        assert out.closed_locked and out.traction_applied and not out.enable_right

    def test_no_enable_on_the_side_without_a_platform(self):
        out = platform_stop_monitor().step(loop_inputs(request_left=True, request_right=False, open_left=True))
        assert not out.enable_left

    def test_no_enable_when_the_position_interval_is_too_wide(self):
        # the estimate is at the stopping point, but the front may be 2 m from it
        out = platform_stop_monitor().step(loop_inputs(spread=Fraction(2), open_right=True))
        assert not out.enable_right

    def test_no_enable_when_the_rear_doors_could_be_off_the_platform(self):
        short = (Platform(Fraction(4650), Fraction(4850), "right", 760),)  # starts 5 m after the rear door
        out = platform_stop_monitor().step(loop_inputs(short, open_right=True))
        assert not out.enable_right

    def test_a_stuck_door_keeps_traction_cut(self):
        monitor = platform_stop_monitor()
        monitor.step(loop_inputs(open_right=True))
        monitor.step(loop_inputs(close=True, obstructed=True))
        out = monitor.step(loop_inputs(immobilised=False, obstructed=True, traction=True))
        assert monitor.state.door_open_right and out.traction_cut and not out.traction_applied
        out = monitor.step(loop_inputs(immobilised=False, traction=True))  # the obstacle cleared
        assert not monitor.state.door_open_right
        assert out.traction_cut  # reported at the start of the cycle: traction returns one cycle later
        assert monitor.step(loop_inputs(immobilised=False, traction=True)).traction_applied

    def test_the_monitor_catches_a_door_opening_off_the_platform(self):
        faulty = mutant_node(
            DOOR_LOOP,
            "enable_right=atp.enable_right,\n            open_left",
            "enable_right=i.request_right,\n            open_left",
        )
        with pytest.raises(PropertyViolation, match=r"doors\.open_only_at_platform_stop") as caught:
            platform_stop_monitor(faulty).step(loop_inputs(front=STOP_M - 300, open_right=True))
        assert caught.value.step == 0


# --- the same predicates on random runs (float backend) --------------------------------------------------

metres = st.fractions(min_value=0, max_value=400, max_denominator=4)
likely = st.sampled_from((True, True, True, False))


@st.composite
def platform_tables(draw):
    rows = []
    for _ in range(draw(st.integers(0, 3))):
        start = draw(metres)
        rows.append(Platform(start, start + draw(metres), draw(st.sampled_from(("left", "right", "both")))))
    return rows


FAULTS = (
    None,
    "speed",
    "standstill",
    "immobilised",
    "position",
    "tolerance",
    "platform_start",
    "platform_end",
    "side",
    "random",
)


@st.composite
def conditions(draw):
    """Door-enable inputs at a stopping point with every condition met but at most one (``FAULTS``), or random;
    probes at the ends and the middle of the interval and the door span."""
    fault = draw(st.sampled_from(FAULTS))
    stop, tolerance = draw(metres), draw(st.fractions(0, 2, max_denominator=4))
    step = Fraction(1, 4)
    if fault == "random":
        front_min = stop + draw(st.fractions(-3, 3, max_denominator=4))
        front_max = front_min + draw(st.fractions(0, 3, max_denominator=4))
    else:
        front_min = stop - tolerance + draw(st.sampled_from((Fraction(0), tolerance)))
        front_max = draw(st.sampled_from((front_min, stop + tolerance)))
        if fault == "tolerance":
            front_min, front_max = draw(
                st.sampled_from(((stop - tolerance - step, front_max), (front_min, stop + tolerance + step)))
            )
    first, last = sorted((draw(st.fractions(0, 200, max_denominator=2)), draw(st.fractions(0, 200, max_denominator=2))))
    side = draw(st.sampled_from(("left", "right")))
    if fault == "random":
        table = draw(platform_tables())
    else:  # one platform that spans the doors (with up to a quarter metre to spare), or misses one end
        start = front_min - last - (-step if fault == "platform_start" else draw(st.sampled_from((0, step))))
        end = front_max - first + (-step if fault == "platform_end" else draw(st.sampled_from((0, step))))
        table = [Platform(start, end, {"left": "right", "right": "left"}[side] if fault == "side" else side)]
    fields = dict(
        position_valid=fault != "position",
        front_min_m=front_min,
        front_max_m=front_max,
        speed_mps=Fraction(1, 100) if fault == "speed" else Fraction(0),
        standstill=fault != "standstill",
        immobilised=fault != "immobilised",
        stopping_point_m=stop,
        stop_tolerance_m=tolerance,
        **platform_inputs(table, 3),
        request_left=side == "left",
        request_right=side == "right",
        probe_front_m=draw(st.sampled_from((front_min, front_max, (front_min + front_max) / 2))),
        probe_door_m=draw(st.sampled_from((first, last, (first + last) / 2))),
    )
    return DoorParams(first_door_m=first, last_door_m=last), fields, fault


def as_float(value):
    if isinstance(value, tuple):
        return tuple(as_float(v) for v in value)
    return float(value) if isinstance(value, Fraction) else value


class TestRandomRuns:
    @settings(max_examples=200)
    @given(case=conditions(), loop_a=st.booleans(), loop_b=st.booleans())
    def test_door_enable_never_trips_the_monitor(self, case, loop_a, loop_b):
        """On exact numbers: the cases sit on the conditions' edges, which float rounding may put either side."""
        params, fields, fault = case
        enable_properties = tuple(p for p in DOOR_PROPERTIES if p.node is DOOR_ENABLE)
        monitor = Monitor(DOOR_ENABLE, params, Stateless(), enable_properties, ops=EXACT)
        out = monitor.step(DoorEnableInputs(**fields, closed_loop_a=loop_a, closed_loop_b=loop_b))
        assert out.traction_cut == (not (loop_a and loop_b))
        if fault is None:  # not over-restrictive: every condition met gives the enable
            assert out.enable_left or out.enable_right
        elif fault != "random":
            assert not (out.enable_left or out.enable_right), fault

    @settings(max_examples=60)
    @given(first=conditions(), data=st.data())
    def test_door_loop_never_trips_the_monitor(self, first, data):
        params, _, _ = first
        monitor = Monitor(DOOR_LOOP, params, DcuState(False, False), LOOP_PROPERTIES)
        for _ in range(data.draw(st.integers(1, 15))):
            _, fields, _ = data.draw(conditions())
            commands = {
                name: data.draw(st.booleans())
                for name in (
                    "open_left",
                    "open_right",
                    "close",
                    "obstructed_left",
                    "obstructed_right",
                    "loop_a_stuck_closed",
                    "loop_b_stuck_closed",
                    "traction_request",
                    "supervision_traction_cut",
                )
            }
            commands["loop_b_stuck_closed"] &= not commands["loop_a_stuck_closed"]  # one lying loop at most
            probe_door = data.draw(st.sampled_from((params.first_door_m, params.last_door_m)))
            fields = {**fields, "probe_door_m": probe_door}
            monitor.step(DoorLoopInputs(**{k: as_float(v) for k, v in fields.items()}, **commands))
        assert all(monitor.applies(p.name) for p in LOOP_PROPERTIES)

    @settings(max_examples=100)
    @given(steps=st.lists(st.tuples(*[st.booleans()] * 7), min_size=1, max_size=20))
    def test_dcu_never_trips_the_monitor(self, steps):
        monitor = Monitor(DCU, Stateless(), DcuState(False, False), tuple(p for p in DOOR_PROPERTIES if p.node is DCU))
        for flags in steps:
            before = monitor.state
            out = monitor.step(DcuInputs(*flags))
            assert out.closed_locked == (not (before.door_open_left or before.door_open_right))


# --- with the position node: the interval at the stop decides ------------------------------------------------


def position_at_stop(tacho_error):
    """Run the position node (exact) for a train that starts on tag 4700 m, runs at up to 5 m/s and stops at
    4840 m, reading each tag as its front passes it; return the position outputs of the cycle it stands at the
    stopping point."""
    from atcs.model.position import POSITION, PositionInputs, PositionState, position_params, tag_table

    table = tag_table("platform line", [461, 471, 481, 491], [4600, 4700, 4800, 4900])
    params = position_params(
        table,
        tag_window_m="0.5",
        tacho_error=tacho_error,
        train_length_m=200,
        cycle_s="0.1",
        max_acceleration_mps2=1,
        max_deceleration_mps2=1,
    )
    step = Fraction(5, 1000)  # 0.5 m/s^2 for a cycle of 0.1 s: the increment changes by 5 mm per cycle
    increments = (
        [Fraction(0)]
        + [step * k for k in range(1, 101)]
        + [Fraction(1, 2)] * 180
        + [step * k for k in range(99, -1, -1)]
        + [Fraction(0)] * 3
    )
    monitor = Monitor(POSITION, params, PositionState(False, Fraction(0), Fraction(0), Fraction(0), False), ops=EXACT)
    front, unread = Fraction(4700), [4700, 4800, 4900]
    for d in increments:
        front += d
        read = bool(unread) and front >= unread[0] - params.tag_window_m
        out = monitor.step(
            PositionInputs(
                tag_read=read,
                tag_id=Fraction(unread[0] // 10 + 1) if read else Fraction(0),
                since_tag_m=max(Fraction(0), front - unread[0]) if read else Fraction(0),
                tacho_m=d,
            )
        )
        if read:
            unread.pop(0)
        assert out.position_valid
    assert front == STOP_M and out.standstill
    return out


class TestWithPositionDetermination:
    @pytest.mark.parametrize(("tacho_error", "enabled"), [("0.01", True), ("0.03", False)])
    def test_odometry_error_at_the_stop_decides_the_enable(self, tacho_error, enabled):
        """The train stands at the stopping point either way; the tag 40 m back was read up to the 0.5 m window
        early, and the interval is the estimate +-(0.5 m + e * 40 m): within a 1.5 m tolerance at e = 1 %, not
        at e = 3 %."""
        position = position_at_stop(tacho_error)
        inputs = DoorEnableInputs(
            position_valid=position.position_valid,
            front_min_m=position.front_min_m,
            front_max_m=position.front_max_m,
            speed_mps=position.speed_est_mps,
            standstill=position.standstill,
            immobilised=True,
            stopping_point_m=STOP_M,
            stop_tolerance_m=Fraction(3, 2),
            **platform_inputs(PLATFORMS, 3),
            request_left=False,
            request_right=True,
            probe_front_m=position.front_min_m,
            probe_door_m=TRAIN.last_door_m,
            closed_loop_a=True,
            closed_loop_b=True,
        )
        enable_properties = tuple(p for p in DOOR_PROPERTIES if p.node is DOOR_ENABLE)
        out = Monitor(DOOR_ENABLE, TRAIN, Stateless(), enable_properties, ops=EXACT).step(inputs)
        assert out.enable_right is enabled and not out.enable_left
