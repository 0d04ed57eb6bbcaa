"""The closed-loop simulator: many trains on one line, each running the model's own step functions (float
backend), with the plant, the resource manager, T2T reports and an ATO.

Each cycle, trains from the front:

1. position (:func:`~atcs.model.position.position_step`): the tags the front passed in the
   last cycle and the tachometer's distance;
2. movement authority (:data:`~atcs.model.authority.AUTHORITY` on exact numbers, every
   authority property checked each cycle by :func:`~atcs.sim.monitor.check_step`, on the part
   of the route the train needs): the resources held, the preceding train's last T2T report
   (its min safe rear and min speed, sent the cycle before), the active protection zones;
3. speed and distance supervision against the line's MRSP (the PSL of
   :func:`~atcs.model.psl.permanent_speed_limit`) and the EoA
   (:func:`~atcs.model.prepared_curves.supervise_prepared`: each target's curves tabled when the MA or the MRSP
   changes, CRV-13;
   :func:`~atcs.model.supervision.supervise`);
4. the ATO (:func:`~atcs.model.ato.ato_target_speed`, seed 003; seed 000: it follows the
   permitted curve): traction below the target speed while short of the ATP's indication
   point, full service braking past it, braking to the target above the target speed;
5. the plant: the train's nominal traction and brakes (EB after the brake build-up time),
   each cycle checked against :func:`~atcs.model.plant.plant_admits`, the proofs' plant.

Then the resource manager (:data:`~atcs.model.resources.RESOURCES`, its properties checked
each cycle, on the resources with something to do) handles the requests and releases;
every message is delivered in the next cycle. Any property violation stops the run with
the step (:class:`~atcs.sim.monitor.PropertyViolation`); so does a collision or an overrun
of a protection zone or the line's end (:class:`~atcs.sim.train_run.SafetyViolation`).

By role: this module holds the line (tags, resources, restrictions), the cycle and the wayside; a train's state
is in :mod:`.train_run`, its ATO in :mod:`.ato_driver`, its doors at a stop in :mod:`.station_stop`, the plant
in :mod:`.motion`, the trace file in :mod:`.trace_files`.
"""

from __future__ import annotations

import bisect
import dataclasses
from collections.abc import Callable
from fractions import Fraction

from atcs.model.ats_status import ATS_STATUS, AtsStatusInputs, AtsStatusParams, AtsStatusState
from atcs.model.authority import AUTHORITY, AuthorityInputs, AuthorityParams, AuthorityState
from atcs.model.doors import DoorParams
from atcs.model.dynamic_profile import Horizon
from atcs.model.node import Stateless
from atcs.model.ops.exact import EXACT
from atcs.model.ops.floating import FLOAT, float_record, floats
from atcs.model.plant import PlantParams
from atcs.model.platforms import platform_inputs
from atcs.model.position import POSITION, PositionInputs, PositionState, position_params, tag_table
from atcs.model.position_loop import sensor_excess_since_tag_m
from atcs.model.prepared_curves import prepare_horizon, supervise_prepared
from atcs.model.profile import KMH_PER_MPS, Profile
from atcs.model.psl import Restriction, extend_by_train_length
from atcs.model.resources import HELD, RESOURCES, ResourceInputs, ResourceState
from atcs.model.restrictions import SpeedRestrictions, as_float
from atcs.model.supervision import SupervisionParams, SupervisionState, supervise
from atcs.model.t2t_message import REPORT_BYTES, T2TReport, decode_report, encode_report, min_speed_mps
from atcs.model.train_data import preset_data
from atcs.sim.ato_driver import ato_commands
from atcs.sim.monitor import Monitor, Traces, check_step, registered_properties
from atcs.sim.motion import move
from atcs.sim.scenario import Scenario, TrainSpec
from atcs.sim.station_stop import station_doors
from atcs.sim.train_run import SafetyViolation, TrainRun

KMH = float(KMH_PER_MPS)
FLOAT_SLACK_M = 1e-6
"""The position interval is checked to contain the true front up to this (both are float sums)."""
CORRUPTED_BIT = (1 << (8 * REPORT_BYTES - 1 - 95)).to_bytes(REPORT_BYTES, "big")
"""The bit a ``t2t_corrupt`` fault flips: D_REAR's 2^24 cm bit, so a report read without its safety code would put
the leader 167.77 km further on."""
ROUTE_FIELDS = ("resource_start_m", "resource_end_m", "resource_is_switch", "switch_needs_reverse")
AUTHORITY_PROPERTIES = registered_properties(AUTHORITY)
ATS_STATUS_PROPERTIES = registered_properties(ATS_STATUS)
RESOURCE_PROPERTIES = registered_properties(RESOURCES)


POSITION_AT_POWER_UP = PositionState(False, 0.0, 0.0, 0.0, False)
"""The onboard states at power-up (and after an ``atp_reset``): no position, no leader known, EB latched."""
AUTHORITY_AT_POWER_UP = AuthorityState(False, *(Fraction(0),) * 4)
ATS_STATUS_AT_POWER_UP = AtsStatusState(False, Fraction(0), Fraction(0), False, Fraction(0))
SUPERVISION_AT_POWER_UP = SupervisionState(eb_latched=True, sb_latched=False)


def _same_horizon(horizon: Horizon, train: TrainRun, eoa_m: float) -> bool:
    """The train's curve tables are still those of its horizon: the same MRSP and gradient, the same EoA."""
    return horizon.mrsp is train.mrsp and horizon.gradient is train.gradient and horizon.eoa_m == eoa_m


class Simulation:
    """One scenario, stepped cycle by cycle (:meth:`step`) or to its end (:meth:`run`)."""

    def __init__(
        self, scenario: Scenario, *, on_cycle: Callable[[Simulation], None] | None = None, traced: bool = True
    ):
        self.scenario, self.on_cycle = scenario, on_cycle
        self.traces = Traces() if traced else None
        """The checked nodes and their properties run as the programs traced from them (the default), or with
        ``traced=False`` as the functions themselves (:func:`~atcs.sim.monitor.check_step`): the same run, to the
        bit."""
        self.dt = float(scenario.cycle_s)
        self.step_count = 0
        line = scenario.line_m
        self.laps = _laps(scenario)
        """How many times round the loop the route is laid out (1: an open line). Positions on a loop are unrolled
        (lap ``n`` from ``n * line_m``), so that the step functions see a line; a resource or a tag is the same on
        every lap."""
        self.route_end_m = line * self.laps
        lap = scenario.resources
        lap_starts, lap_ends = tuple(r.start_m for r in lap), tuple(r.end_m for r in lap)
        self.resources_per_lap = resources = len(lap)
        self.resource_starts = tuple(
            tuple(x + n * line for n in range(self.laps) for x in column) for column in (lap_starts, lap_ends)
        )
        self.resource_floats = tuple(tuple(float(x) for x in column) for column in self.resource_starts)
        layout = scenario.double_track
        self.resource_zone = tuple(layout.zone(x) if layout is not None else 1 for x in lap_starts)
        """The wayside zone whose manager handles each resource."""
        self.tags = scenario.tags
        lap_tags = self.tags.positions_m
        laid = range(self.laps + 1) if scenario.loop else range(1)  # a lap more: the last table reaches it
        self.tag_positions_m = tuple(float(x + n * line) for n in laid for x in lap_tags)
        self.tag_ids = tuple(float(i) for _ in laid for i in self.tags.ids)
        self.stops = tuple(
            dataclasses.replace(st, stop_m=st.stop_m + n * line) for n in range(self.laps) for st in scenario.stations
        )
        """Every station stop in the order a train meets them (on a loop, lap after lap)."""
        self.platforms = tuple(
            dataclasses.replace(p, start_m=p.start_m + n * line, end_m=p.end_m + n * line)
            for n in range(self.laps)
            for p in scenario.platforms
        )
        self.door_tables = tuple(self._door_table(stop) for stop in self.stops)
        """The platform table the door loop gets on the way to each stop: the platforms there."""
        self.no_platforms = {k: floats(v) for k, v in platform_inputs((), capacity=1).items()}
        self.trains = [self._train(spec) for spec in scenario.trains]
        slots = resources * len(self.trains)
        self.resource_state = ([0.0] * resources, [0.0] * slots, [0.0] * slots, [0.0] * slots)
        """The resource manager's state (owner, holding, up, down, as in :class:`ResourceState`), updated in
        place."""
        self.held = [[False] * resources for _ in self.trains]
        """Each train's resources held (by resource, as on the first lap)."""
        self.held_sets: list[set[int]] = [set() for _ in self.trains]
        self.switches = [r for r, resource in enumerate(lap) if resource.is_switch]
        """The switches (by resource, as on the first lap)."""
        self.switch_reversed = [False] * resources
        """The object controller's switch positions (all normal at the start)."""
        self.switch_thrown_at: dict[int, float] = {}
        """The switches being thrown and when each will be locked in its new position."""
        self.in_flight: set[int] = set()
        """The slots with a message on its way (up to the manager or down to the train)."""
        for k in range(len(self.trains)):
            self._hold_under(k)

    def _hold_under(self, k: int) -> None:
        """At power-up train ``k`` holds the resources its body stands on (the manager's record of the last session,
        or the trackside's detection): until its position is confirmed it sends no report and releases nothing, so
        these keep the train behind from running onto it."""
        train, (starts, ends) = self.trains[k], self.resource_floats
        line = float(self.scenario.line_m)
        front = train.front_m % line if self.scenario.loop else train.front_m
        rear = front - float(train.spec.data.train_length_m)
        owner, holding, *_ = self.resource_state
        count = len(owner)
        for r in range(count):
            under = [starts[r] < front and ends[r] > rear]
            if self.scenario.loop:  # a body across the loop's origin
                under.append(starts[r] < front + line and ends[r] > rear + line)
            if any(under):
                owner[r], holding[k * count + r] = float(k + 1), float(HELD)
                self.held[k][r] = True
                self.held_sets[k].add(r)

    @property
    def time_s(self) -> float:
        return self.step_count * self.dt

    @property
    def clock_s(self) -> Fraction:
        """The true time, exact: every train's onboard clock unless a ``clock_drift`` fault is active."""
        return self.step_count * self.scenario.cycle_s

    def onboard_clock_s(self, train: TrainRun) -> Fraction:
        """What the train's clock reads: the true time, or under ``clock_drift`` one running ``factor`` times as
        fast since the fault began."""
        now = self.clock_s
        drift = train.spec.fault("clock_drift", float(now))
        return now if drift is None else now + (drift.value - 1) * (now - drift.from_s)

    def _train(self, spec: TrainSpec) -> TrainRun:
        s, d = self.scenario, spec.data
        starts, ends = self.resource_starts
        data = preset_data(d, s.national, cycle_s=s.cycle_s)
        first_tag = self.tag_positions_m.index(float(spec.front_m))  # powered up on a tag: read in the first cycle
        length = d.train_length_m
        pisl = self._laid_out(s.speed_limits_kmh, KMH_PER_MPS)
        ptsl = Profile((Fraction(0),), (spec.max_speed_kmh / KMH_PER_MPS,), self.route_end_m)
        gradient = self._laid_out(s.gradients_permille, 1)
        compensated = extend_by_train_length(EXACT, gradient, length)
        plant = PlantParams(
            gradient_starts_m=compensated.starts_m,
            gradient_permille=compensated.values,
            line_end_m=self.route_end_m,
            **{
                k: data[k]
                for k in (
                    "rotating_mass_uphill_percent",
                    "rotating_mass_downhill_percent",
                    "max_acceleration_mps2",
                    "guaranteed_deceleration_mps2",
                    "max_deceleration_mps2",
                    "cycle_s",
                    "traction_cut_cycles",
                    "brake_build_up_cycles",
                )
            },
        )
        table = self._tag_window(first_tag) if s.loop else self.tags
        pos = position_params(
            table,
            tag_window_m=s.tag_window_m,
            tacho_error=s.tacho_error,
            train_length_m=length,
            cycle_s=s.cycle_s,
            max_acceleration_mps2=plant.max_acceleration_mps2 + Fraction(1, 2),
            max_deceleration_mps2=plant.max_deceleration_mps2,
        )
        authority = AuthorityParams(
            resource_start_m=starts,
            resource_end_m=ends,
            resource_is_switch=tuple(r.is_switch for _ in range(self.laps) for r in s.resources),
            switch_needs_reverse=tuple(r.direction == "reverse" for _ in range(self.laps) for r in s.resources),
            line_end_m=self.route_end_m,
            max_ma_m=s.max_ma_m,
            leader_max_deceleration_mps2=max(t.data.emergency_decelerations_mps2[0] for t in s.trains) + 1,
            safety_margin_m=s.safety_margin_m,
            report_timeout_s=s.report_timeout_s,
            clock_skew_max_s=s.clock_skew_s,
            brick_wall=s.brick_wall,
        )
        restrictions = SpeedRestrictions(pisl, ptsl, length)
        stations = [j for j, st in enumerate(self.stops) if st.stop_m > spec.front_m]
        return TrainRun(
            spec=spec,
            plant=float_record(plant),
            position=Monitor(POSITION, float_record(pos), POSITION_AT_POWER_UP, traces=self.traces),
            authority=AUTHORITY_AT_POWER_UP,
            authority_params=authority,
            ats_status=ATS_STATUS_AT_POWER_UP,
            ats_status_params=AtsStatusParams(s.status_timeout_s, s.clock_skew_s),
            supervision=SUPERVISION_AT_POWER_UP,
            front_m=float(spec.front_m),
            speed_mps=0.0,
            brake_cycles=float(plant.brake_build_up_cycles),
            restrictions=restrictions,
            mrsp=as_float(restrictions.mrsp()),
            gradient=as_float(compensated),
            train_data=float_record(d),
            national=float_record(s.national),
            tag_base=first_tag if s.loop else 0,
            last_tag=first_tag,
            door_params=DoorParams(float(spec.first_door_m), float(spec.last_door_m)),
            next_station=stations[0] if stations else len(self.stops),
        )

    def _laid_out(self, segments, unit) -> Profile:
        """A line profile (``value / unit`` from each segment's start) over the whole route, lap after lap."""
        line = self.scenario.line_m
        return Profile(
            tuple(g.start_m + n * line for n in range(self.laps) for g in segments),
            tuple(g.value / unit for _ in range(self.laps) for g in segments),
            self.route_end_m,
        )

    def _tag_window(self, base: int):
        """One lap of tags from index ``base`` (ids as on the track, positions unrolled): a loop train's tag
        table."""
        n = len(self.tags)
        return tag_table(
            self.scenario.source,
            self.tag_ids[base : base + n],
            [Fraction(x) for x in self.tag_positions_m[base : base + n]],
        )

    def _move_tag_table(self, train: TrainRun) -> None:
        """On a loop, once a train is half way through its tag table, the table moves on to start at its last
        relevant tag, and the position state's tag index with it (the same tag, the same position)."""
        state, n = train.position.state, len(self.tags)
        j = int(state.lrt_index)
        if not self.scenario.loop or j < n // 2:
            return
        b = train.tag_base = train.tag_base + j
        train.position.params = dataclasses.replace(
            train.position.params, tag_ids=self.tag_ids[b : b + n], tag_positions_m=self.tag_positions_m[b : b + n]
        )
        train.position.state = dataclasses.replace(state, lrt_index=0.0)

    def _door_table(self, stop) -> dict:
        """The door loop's platform table on the way to ``stop``: the platforms that reach within a train's
        length and the stop tolerance of its stopping point."""
        reach = max(t.data.train_length_m for t in self.scenario.trains) + self.scenario.stop_tolerance_m
        near = [p for p in self.platforms if p.end_m >= stop.stop_m - reach and p.start_m <= stop.stop_m + reach]
        return {k: floats(v) for k, v in platform_inputs(near, capacity=max(len(near), 1)).items()}

    # --- one cycle ---------------------------------------------------------------------------------------

    def step(self) -> None:
        t = self.time_s
        self._restrictions(t)
        self._lock_switches(t)
        sends, reports = set(), []
        count = len(self.resource_state[0])
        for k, train in enumerate(self.trains):
            train_sends, report = self._onboard(train, *self._leader(k), k, t)
            sends.update(k * count + r for r in train_sends)
            reports.append(report)
        for train, report in zip(self.trains, reports, strict=True):
            self._send_report(train, report, t)
        out = {w.zone for w in self.scenario.manager_outages if w.active_at(t)}
        self._manage(sends, deliver=lambda r: None not in out and self.resource_zone[r] not in out)
        self.step_count += 1
        self._check()
        if self.on_cycle is not None:
            self.on_cycle(self)

    def _leader(self, k: int) -> tuple[TrainRun | None, float]:
        """Train ``k``'s leader and how far ahead the leader's coordinates are to be taken: on a loop the front
        train's leader is the last one, a lap on."""
        if k:
            return self.trains[k - 1], 0.0
        return (self.trains[-1], float(self.scenario.line_m)) if self.scenario.loop else (None, 0.0)

    def _restrictions(self, t: float) -> None:
        """The ATS's temporary restrictions: each train's MRSP is updated where one comes into force or ends
        (seed 002 §3.2's incremental update, :class:`~atcs.model.restrictions.SpeedRestrictions`), once the ATS's
        status reaches the train (a train that stops hearing it is stopped, ATS-04)."""
        line = self.scenario.line_m
        for j, r in enumerate(self.scenario.restrictions):
            active = r.active_at(t)
            for train in (train for train in self.trains if self._ats_status_delivered(train, t)):
                changed = False
                for n in range(self.laps):
                    name = f"restriction {j}" + (f", lap {n}" if n else "")
                    applied = name in train.restrictions.active
                    if active and not applied:
                        train.restrictions.apply(
                            name, Restriction(r.start_m + n * line, r.end_m + n * line, r.kmh / KMH_PER_MPS)
                        )
                    elif applied and not active:
                        train.restrictions.withdraw(name)
                    else:
                        continue
                    changed = True
                if changed:
                    train.mrsp = as_float(train.restrictions.mrsp())

    def _send_report(self, train: TrainRun, report: bytes | None, t: float) -> None:
        """The T2T report, delivered to the follower in the next cycle, unless a fault of the channel
        (:data:`~atcs.sim.scenario.FAULTS`) loses, delays, reorders, replays or corrupts it. A follower's node takes
        one report a cycle: of those due together, the last sent."""
        fault = train.spec.fault
        if report is not None and fault("t2t_loss", t) is None and fault("t2t_replay", t) is None:
            late = 1
            if (delay := fault("t2t_delay", t)) is not None:
                late += round(float(delay.value) / self.dt)
            if fault("t2t_reorder", t) is not None and train.reports_sent % 2 == 0:
                late += 2
            if fault("t2t_corrupt", t) is not None:
                report = bytes(b ^ m for b, m in zip(report, CORRUPTED_BIT, strict=True))
            train.outbox.append((self.step_count + late, report))
        due = [r for step, r in train.outbox if step <= self.step_count + 1]
        train.outbox = [(step, r) for step, r in train.outbox if step > self.step_count + 1]
        if fault("t2t_replay", t) is not None:
            train.report = train.replayed
        else:
            train.report = due[-1] if due else None
            train.replayed = train.report or train.replayed

    def _manage(self, sends: set[int], *, deliver: Callable[[int], bool] = lambda r: True) -> None:
        """The resource manager's step (:data:`~atcs.model.resources.RESOURCES`, its properties checked), one
        resource at a time, on the slots with anything to do (a send, or a message in flight) and the owner's.

        This is the whole manager's step: in :func:`~atcs.model.resources.resource_step` the slots of different
        resources never interact, and an idle slot (nothing sent, nothing in flight) stays as it is and leaves
        the owner as it is. The manager grants simultaneous requests in slot order; here a resource's slots are
        numbered from the train nearest behind it (on an open line, train order), so that on a loop a train
        powered up over a resource gets it before the train a lap behind. The owner codes are renumbered for the
        trains taken. An idle slot of a train other than the owner is free, quiet and not
        the owner's, so the properties hold of it trivially. In an outage of a resource's manager (``deliver(r)``
        false) no message about it reaches the manager or a train. ``sends``: the slots (train * resources +
        resource) whose train sends."""
        owner = self.resource_state[0]
        count = len(owner)
        busy: dict[int, set[int]] = {}
        for j in sends | self.in_flight:
            busy.setdefault(j % count, set()).add(j // count)
        for r in sorted(busy):
            trains = busy[r]
            if owner[r]:
                trains.add(int(owner[r]) - 1)
            self._manage_resource(r, sorted(trains, key=lambda k: (self._behind_m(k, r), k)), sends, deliver)

    def _manage_resource(self, r: int, trains: list[int], sends: set[int], deliver) -> None:
        """:meth:`_manage` for resource ``r`` and its busy ``trains`` in slot order (the node's traced program and
        its properties', on floats)."""
        owner, holding, up, down = self.resource_state
        count, size = len(owner), len(trains)
        slots = [k * count + r for k in trains]
        code = {0.0: 0.0, **{float(k + 1): float(q + 1) for q, k in enumerate(trains)}}
        part = ResourceState(
            owner=(code[owner[r]],),
            holding=tuple(holding[j] for j in slots),
            up=tuple(up[j] for j in slots),
            down=tuple(down[j] for j in slots),
        )
        delivered = bool(deliver(r))
        inputs = ResourceInputs(
            send=tuple(j in sends for j in slots), deliver_up=(delivered,) * size, deliver_down=(delivered,) * size
        )
        nxt, out = check_step(
            RESOURCES, Stateless(), part, inputs, RESOURCE_PROPERTIES, self.step_count, traces=self.traces
        )
        holder = int(nxt.owner[0])
        owner[r] = float(trains[holder - 1] + 1) if holder else 0.0
        for q, (k, j) in enumerate(zip(trains, slots, strict=True)):
            holding[j], up[j], down[j] = float(nxt.holding[q]), float(nxt.up[q]), float(nxt.down[q])
            if up[j] or down[j]:
                self.in_flight.add(j)
            else:
                self.in_flight.discard(j)
            held = bool(out.held[q])
            self.held[k][r] = held
            (self.held_sets[k].add if held else self.held_sets[k].discard)(r)

    def _behind_m(self, k: int, r: int) -> float:
        """How far resource ``r`` starts ahead of train ``k``'s rear (on a loop, going round)."""
        train = self.trains[k]
        ahead = self.resource_floats[0][r] - (train.front_m - float(train.spec.data.train_length_m))
        return ahead % float(self.scenario.line_m) if self.scenario.loop else ahead

    def _onboard(self, train: TrainRun, leader: TrainRun | None, leader_ahead_m: float, k: int, t: float):
        """One cycle of train ``k``'s onboard functions and its plant: returns (the resources it sends a request or
        release for, the T2T report it sends)."""
        if train.spec.fault("atp_reset", t):
            self._power_up(train)
        pos = self._locate(train, t)
        auth, lo, report_status, ats_fresh = self._authority(train, pos, leader, leader_ahead_m, k, t)
        eoa_m = float(auth.eoa_m)
        commands, curves = self._supervise(train, pos, eoa_m, t)
        target, traction = self._drive(train, pos, eoa_m, curves, commands, t)
        self._record(train, pos, eoa_m, curves, target, commands, traction, t)
        train.last["leader_report"] = report_status
        train.last["ats_status"] = "fresh" if ats_fresh else "stale"
        report = None
        if self._rear_confirmed(train, pos, t):
            train.reports_sent += 1
            report = encode_report(
                T2TReport(
                    sender_id=k + 1,
                    seq=train.reports_sent,
                    sent_s=self.onboard_clock_s(train),
                    rear_m=Fraction(pos.rear_min_m),
                    speed_mps=Fraction(min_speed_mps(FLOAT, pos.speed_est_mps, pos.speed_accuracy_mps)),
                )
            )
        count = self.resources_per_lap
        sends = [(lo + q) % count for q, (r, x) in enumerate(zip(auth.request, auth.release, strict=True)) if r or x]
        return sends, report

    @staticmethod
    def _rear_confirmed(train: TrainRun, pos, t: float) -> bool:
        """The min safe rear may be reported and resources released behind it: the position confirmed and no
        integrity loss reported."""
        return bool(pos.position_confirmed) and train.spec.fault("integrity_lost", t) is None

    @staticmethod
    def _power_up(train: TrainRun) -> None:
        """An ``atp_reset`` fault: the onboard ATP restarts, its position, authority and supervision back in their
        power-up states (position unknown, no leader known, EB latched); the train and the resource manager keep
        theirs."""
        train.position.state = POSITION_AT_POWER_UP
        train.authority = AUTHORITY_AT_POWER_UP
        train.ats_status = ATS_STATUS_AT_POWER_UP
        train.supervision = SUPERVISION_AT_POWER_UP
        train.sensor_excess_m = 0.0

    def _locate(self, train: TrainRun, t: float):
        """Step 1, position: the tag read this cycle (or a sensor fault in its place) and the tachometer; a valid
        position must contain the true front, its interval widened by the sensors' error beyond their stated
        bounds since the last tag (POS-22: any tachometer or tag fault)."""
        spec = train.spec
        self._move_tag_table(train)
        tag = None if spec.fault("missed_tag", t) else train.last_tag
        tag_id = self.tag_ids[tag] if tag is not None else 0.0
        spurious = spec.fault("spurious_tag", t)
        if spurious is not None:
            tag, tag_id = -1, float(spurious.value)
        since_m, since_tacho_m = train.since_tag_m if tag == train.last_tag else (0.0, 0.0)
        read = PositionInputs(
            tag_read=tag is not None, tag_id=tag_id, since_tag_m=since_tacho_m, tacho_m=train.last_tacho_m
        )
        pos = train.position.step(read)
        table = train.position.params
        train.sensor_excess_m = float(
            sensor_excess_since_tag_m(
                FLOAT,
                table,
                train.sensor_excess_m,
                tag is not None and pos.position_valid,
                (train.last_distance_m, train.last_tacho_m),
                (since_m, since_tacho_m),
                (train.front_m - since_m, table.tag_positions_m[int(train.position.state.lrt_index)]),
            )
        )
        slack_m = train.sensor_excess_m + FLOAT_SLACK_M
        inside = pos.front_min_m - slack_m <= train.front_m <= pos.front_max_m + slack_m
        if pos.position_valid and not inside:
            raise SafetyViolation(
                f"the true front {train.front_m:.3f} m is outside the position interval "
                f"[{pos.front_min_m:.3f}, {pos.front_max_m:.3f}] m widened by the sensors' excess error "
                f"{train.sensor_excess_m:.3f} m (POS-22)",
                spec.name,
                self.step_count,
                t,
            )
        return pos

    def _authority(self, train: TrainRun, pos, leader: TrainRun | None, leader_ahead_m: float, k: int, t: float):
        """Step 2, movement authority on the window of the route the train needs, on exact numbers (the float
        rounding of a stopping point would break the authority properties by an ulp): returns the node's outputs,
        the window's first resource, what became of the leader's report (the trace's ``leader_report``:
        ``none`` delivered, ``accepted``, ``corrupt``, or ``out_of_sequence``: replayed, overtaken or stamped in
        the future) and whether the ATS's status is fresh (the trace's ``ats_status``)."""
        ats = self._ats_status(train, pos, t)
        received = None
        if leader is not None and leader.report is not None:
            received = decode_report(leader.report, expected_sender_id=self.trains.index(leader) + 1)
        report = received.report if received is not None else T2TReport(0, 0, Fraction(0), Fraction(0), Fraction(0))
        lo, hi = self._window(train, pos, k)
        window = dataclasses.replace(
            train.authority_params, **{name: getattr(train.authority_params, name)[lo:hi] for name in ROUTE_FIELDS}
        )
        held, count = self.held[k], self.resources_per_lap
        unlocked = train.spec.fault("switch_unlocked", t) is not None
        train.authority, auth = check_step(
            AUTHORITY,
            window,
            train.authority,
            AuthorityInputs(
                front_max_m=Fraction(pos.front_max_m),
                rear_min_m=Fraction(pos.rear_min_m),
                rear_confirmed=self._rear_confirmed(train, pos, t),
                held=tuple(held[i % count] for i in range(lo, hi)),
                switch_locked=tuple(not unlocked and i % count not in self.switch_thrown_at for i in range(lo, hi)),
                switch_reversed=tuple(self.switch_reversed[i % count] for i in range(lo, hi)),
                now_s=self.onboard_clock_s(train),
                report_delivered=received is not None,
                report_intact=received is not None and received.intact,
                report_seq=Fraction(report.seq),
                report_sent_s=report.sent_s,
                report_rear_m=report.rear_m + Fraction(leader_ahead_m),
                report_speed_mps=report.speed_mps,
                zone_active=ats.zone_active,
                zone_start_m=ats.zone_start_m,
            ),
            AUTHORITY_PROPERTIES,
            self.step_count,
            ops=EXACT,
            traces=self.traces,
        )
        for i, command in enumerate(auth.switch_command, start=lo):
            if command and i % count not in self.switch_thrown_at:
                self._throw_switch(i % count, bool(window.switch_needs_reverse[i - lo]), t)
        status = "none"
        if received is not None:
            status = "accepted" if auth.report_accepted else "out_of_sequence" if received.intact else "corrupt"
        return auth, lo, status, bool(ats.status_fresh)

    def _ats_status(self, train: TrainRun, pos, t: float):
        """The ATS's status as the train receives it this cycle (:data:`~atcs.model.ats_status.ATS_STATUS` on
        exact numbers): the ATS sends it every cycle, numbered by the cycle and stamped by the true time (the
        ATS's clock), with the first active protection zone ahead of the train's rear; an ``ats_status_lost``
        fault loses it."""
        zones = [x for x in self._zone_starts(t) if x > pos.rear_min_m]
        train.ats_status, out = check_step(
            ATS_STATUS,
            train.ats_status_params,
            train.ats_status,
            AtsStatusInputs(
                now_s=self.onboard_clock_s(train),
                front_max_m=Fraction(pos.front_max_m),
                status_delivered=self._ats_status_delivered(train, t),
                status_intact=True,
                status_seq=Fraction(self.step_count + 1),
                status_sent_s=self.clock_s,
                status_zone_active=bool(zones),
                status_zone_start_m=Fraction(min(zones) if zones else 0),
            ),
            ATS_STATUS_PROPERTIES,
            self.step_count,
            ops=EXACT,
            traces=self.traces,
        )
        return out

    @staticmethod
    def _ats_status_delivered(train: TrainRun, t: float) -> bool:
        """The ATS's status reaches the train this cycle (with its temporary restrictions)."""
        return train.spec.fault("ats_status_lost", t) is None

    def _throw_switch(self, r: int, reverse: bool, t: float) -> None:
        """The object controller starts throwing switch ``r`` to ``reverse`` (or normal): it reports it unlocked
        until the line's throw time has passed."""
        if self.switch_reversed[r] != reverse:
            self.switch_reversed[r] = reverse
            self.switch_thrown_at[r] = t + float(self.scenario.switch_throw_s)

    def _lock_switches(self, t: float) -> None:
        """The switches whose throw time has passed are reported locked in their new position."""
        for r in [r for r, until in self.switch_thrown_at.items() if until <= t]:
            del self.switch_thrown_at[r]

    def _supervise(self, train: TrainRun, pos, eoa_m: float, t: float):
        """Step 3, speed and distance supervision against the MRSP and the EoA: returns the commands and the
        curves at the max safe front; counts the interventions once the train has started."""
        spec = train.spec
        prepared = train.curve_tables
        if prepared is None or not _same_horizon(prepared.horizon, train, eoa_m):
            horizon = Horizon(mrsp=train.mrsp, gradient=train.gradient, eoa_m=eoa_m, eoa_speed_mps=0.0)
            prepared = train.curve_tables = prepare_horizon(
                FLOAT, train.train_data, train.national, horizon, reuse=prepared
            )
        a_est = float(train.plant.max_acceleration_mps2)
        over, curves, _ = supervise_prepared(
            FLOAT, train.train_data, train.national, prepared, pos.front_max_m, pos.speed_est_mps, a_est
        )
        departed = t >= float(spec.depart_s)
        released = (departed and not train.started) or (
            spec.eb_release_after_stop_s is not None
            and train.stopped_s is not None
            and t >= train.stopped_s + float(spec.eb_release_after_stop_s)
        )
        before = train.supervision
        train.supervision, commands = supervise(
            FLOAT, SupervisionParams(True), before, over, pos.standstill, released, pos.position_valid
        )
        if train.started and commands.emergency_brake and not before.eb_latched:
            train.stats.emergency_brakes += 1
        if train.started and commands.service_brake and not before.sb_latched:
            train.stats.service_brakes += 1
        train.started = train.started or (departed and not commands.emergency_brake)
        return commands, curves

    def _drive(self, train: TrainRun, pos, eoa_m: float, curves, commands, t: float):
        """Steps 4 and 5: the ATO's commands, the doors at a stop (which may cut traction), then the plant under
        the ATP's brake commands: returns the ATO's target and whether traction was applied."""
        spec = train.spec
        departed = t >= float(spec.depart_s)
        station, at_station, target, traction, ato_brake = ato_commands(
            self, train, pos, eoa_m, curves, departed, bool(commands.traction_cut)
        )
        doors = station_doors(
            self,
            train,
            pos,
            station if at_station else None,
            t,
            immobilised=ato_brake > 0,
            traction_request=traction,
            supervision_cut=bool(commands.traction_cut),
        )
        traction = bool(doors.traction_applied) or spec.fault("traction_stuck", t) is not None
        service_max = float(spec.data.service_decelerations_mps2[0])
        ignores_sb = spec.fault("ignores_service_brake", t) is not None
        service = 0.0 if ignores_sb else (service_max if commands.service_brake else ato_brake)
        move(self, train, commands.emergency_brake, traction, service, t)
        if commands.emergency_brake and train.speed_mps == 0.0 and train.stopped_s is None:
            train.stopped_s = t
        if not commands.emergency_brake:
            train.stopped_s = None
        return target, traction

    def _record(self, train: TrainRun, pos, eoa_m: float, curves, target, commands, traction: bool, t: float):
        """The train's row of the trace for this cycle."""
        train.last = {
            "t_s": t,
            "front_m": train.front_m,
            "speed_kmh": train.speed_mps * KMH,
            "front_min_m": pos.front_min_m,
            "front_max_m": pos.front_max_m,
            "eoa_m": eoa_m,
            "ebi_m": curves.ebi_m,
            "permitted_m": curves.permitted_m,
            "target_kmh": target.speed_mps * KMH,
            "eb": bool(commands.emergency_brake),
            "sb": bool(commands.service_brake),
            "traction": bool(traction),
            "position_valid": bool(pos.position_valid),
            "position_confirmed": bool(pos.position_confirmed),
            "doors_open": bool(train.dcu.door_open_left or train.dcu.door_open_right),
        }
        if self.scenario.loop:  # where the front is on the double track
            train.last["track"], train.last["x_m"] = self.scenario.double_track.place(train.front_m)

    def _window(self, train: TrainRun, pos, k: int) -> tuple[int, int]:
        """The resources (by index on the route) the authority node needs this cycle: those held, those from the
        min safe rear to dRequestResource, and the first one past it (not held, so dLockedResource is the same as
        over the whole route)."""
        starts, ends = self.resource_floats
        last = len(ends) - 1
        d_request = min(float(self.route_end_m), pos.front_max_m + float(self.scenario.max_ma_m))
        mine = sorted(self._route_index(r, pos.front_max_m) for r in self.held_sets[k])
        lo = min([bisect.bisect_right(ends, pos.rear_min_m), *mine[:1], last])
        beyond = bisect.bisect_left(starts, d_request)
        hi = max([min(beyond, last) + 1, *(i + 2 for i in mine[-1:])])
        return lo, min(hi, len(ends))

    def _route_index(self, r: int, front_m: float) -> int:
        """Resource ``r``'s index on the route nearest ``front_m`` (on a loop, the lap a train holds it on)."""
        if not self.scenario.loop:
            return r
        count = self.resources_per_lap
        f = max(bisect.bisect_right(self.resource_floats[0], front_m) - 1, 0)
        ahead = (r - f) % count
        return f + ahead if ahead < count // 2 else f + ahead - count

    def _zone_starts(self, t: float) -> list[float]:
        """The starts of the active protection zones, on every lap."""
        line = float(self.scenario.line_m)
        return [float(z.start_m) + n * line for z in self.scenario.zones if z.active_at(t) for n in range(self.laps)]

    def _check(self) -> None:
        for k, train in enumerate(self.trains):
            leader, ahead_m = self._leader(k)
            if leader is not None:
                rear_m = leader.front_m - float(leader.spec.data.train_length_m)
                if leader.detached is not None:
                    rear_m = min(rear_m, leader.detached[0])
                gap = rear_m + ahead_m - train.front_m
                train.stats.min_gap_m = min(train.stats.min_gap_m, gap)
                if gap <= 0:
                    raise SafetyViolation(
                        f"collision with {leader.spec.name}", train.spec.name, self.step_count, self.time_s
                    )
            for start in self._zone_starts(self.time_s):
                if train.front_m - train.last_distance_m <= start < train.front_m:
                    raise SafetyViolation(
                        f"entered the protection zone at {start:g} m", train.spec.name, self.step_count, self.time_s
                    )
            self._check_switches(train)
            if train.front_m > float(self.route_end_m):
                raise SafetyViolation("ran past the end of the line", train.spec.name, self.step_count, self.time_s)

    def _check_switches(self, train: TrainRun) -> None:
        """A train's front must not be on a switch that is being thrown or lies against its route."""
        line = float(self.scenario.line_m)
        front = train.front_m % line if self.scenario.loop else train.front_m
        starts, ends = self.resource_floats
        for r in self.switches:
            if starts[r] <= front < ends[r]:
                resource = self.scenario.resources[r]
                if r in self.switch_thrown_at or self.switch_reversed[r] != (resource.direction == "reverse"):
                    raise SafetyViolation(
                        f"ran onto switch {resource.id}, which is not locked {resource.direction}",
                        train.spec.name,
                        self.step_count,
                        self.time_s,
                    )

    def run(self) -> Simulation:
        cycles = int(self.scenario.duration_s / self.scenario.cycle_s)
        while self.step_count < cycles:
            self.step()
        return self


def _laps(scenario: Scenario) -> int:
    """How many laps of a loop the route needs: as far as any train can run in the scenario's time, and its MA
    beyond (1 on an open line)."""
    if not scenario.loop:
        return 1
    reach = (
        max(t.front_m for t in scenario.trains)
        + scenario.duration_s * max(t.max_speed_kmh for t in scenario.trains) / KMH_PER_MPS
        + 2 * scenario.max_ma_m
    )
    return int(reach // scenario.line_m) + 1
