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
   (:func:`~atcs.model.dynamic_profile.supervise_position`,
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
of a protection zone or the line's end (:class:`SafetyViolation`).
"""

from __future__ import annotations

import csv
import dataclasses
import io
import json
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from fractions import Fraction

from atcs.model.ato import ato_target_speed as ato_target
from atcs.model.ato import limits_ahead
from atcs.model.authority import AUTHORITY, AuthorityInputs, AuthorityParams, AuthorityState
from atcs.model.dynamic_profile import Horizon, supervise_position
from atcs.model.node import Stateless
from atcs.model.ops.exact import EXACT
from atcs.model.ops.floating import FLOAT
from atcs.model.plant import PlantParams, PlantState, gradient_braking_mps2, plant_admits
from atcs.model.position import POSITION, PositionInputs, PositionState, position_params, tag_table
from atcs.model.profile import KMH_PER_MPS, Profile, value_at
from atcs.model.psl import extend_by_train_length, permanent_speed_limit
from atcs.model.resources import RESOURCES, ResourceInputs, ResourceState
from atcs.model.restrictions import as_float
from atcs.model.supervision import SupervisionParams, SupervisionState, supervise
from atcs.model.train_data import NationalData, TrainData, subset026_national
from atcs.properties import select
from atcs.properties.closed_loop import preset_data
from atcs.sim.monitor import Monitor, check_step
from atcs.sim.scenario import Scenario, TrainSpec

KMH = float(KMH_PER_MPS)
ATO_LOOKAHEAD_S = 2.0
"""The ATO does not accelerate within this many seconds (at its speed) of the indication point."""
FLOAT_MARGIN = 1e-9
"""Traction runs this fraction under the plant's bound, so that IEEE rounding never takes a motion past it."""
ROUTE_FIELDS = ("resource_start_m", "resource_end_m", "resource_is_switch", "switch_needs_reverse")
AUTHORITY_PROPERTIES = tuple(p for p in (*select("authority.*"), *select("resources.*")) if p.node is AUTHORITY)
RESOURCE_PROPERTIES = tuple(p for p in select("resources.*") if p.node is RESOURCES)


class SafetyViolation(AssertionError):
    """A collision, or a train past a protection zone's start or the line's end."""

    def __init__(self, what: str, train: str, step: int, time_s: float):
        self.what, self.train, self.step, self.time_s = what, train, step, time_s
        super().__init__(f"{train}: {what} at step {step} (t = {time_s:.1f} s)")


@dataclass
class TrainStats:
    distance_m: float = 0.0
    running_s: float = 0.0
    max_speed_kmh: float = 0.0
    emergency_brakes: int = 0
    """ATP EB commands (rising edges)."""
    service_brakes: int = 0
    """ATP service-brake interventions (rising edges)."""
    min_gap_m: float = math.inf
    """The least distance from the front to the preceding train's rear."""


@dataclass
class TrainRun:
    spec: TrainSpec
    plant: PlantParams
    """Float plant data: the bounds the proofs assume, checked every cycle."""
    position: Monitor
    authority: AuthorityState
    authority_params: AuthorityParams
    """The whole route's; each cycle the node runs on the window the train needs (:meth:`Simulation._window`)."""
    supervision: SupervisionState
    front_m: float
    speed_mps: float
    brake_cycles: float
    mrsp: Profile
    gradient: Profile
    train_data: TrainData
    """Float, for the curves."""
    national: NationalData
    tags_m: tuple[float, ...]
    tag_ids: tuple[float, ...]
    last_distance_m: float = 0.0
    last_tag: int | None = None
    """The tag the front passed in the last cycle (read in this one)."""
    report: tuple[float, float] | None = None
    """(min safe rear, min speed) the train sent last cycle."""
    started: bool = False
    """The driver has released the power-up emergency brake (at departure)."""
    stopped_s: float | None = None
    """When the train last came to a standstill with EB applied."""
    stats: TrainStats = field(default_factory=TrainStats)
    last: dict = field(default_factory=dict)
    """This cycle's values for the trace."""


def _floats(value):
    if isinstance(value, tuple):
        return tuple(_floats(v) for v in value)
    return float(value) if isinstance(value, Fraction) else value


def _as_float(record):
    return type(record)(**{f.name: _floats(getattr(record, f.name)) for f in dataclasses.fields(record)})


class Simulation:
    """One scenario, stepped cycle by cycle (:meth:`step`) or to its end (:meth:`run`)."""

    def __init__(self, scenario: Scenario, *, on_cycle: Callable[[Simulation], None] | None = None):
        self.scenario, self.on_cycle = scenario, on_cycle
        self.dt = float(scenario.cycle_s)
        self.step_count = 0
        line = scenario.line_m
        self.resource_starts = _grid(Fraction(0), line, scenario.resource_length_m)
        self.resource_floats = tuple(tuple(float(x) for x in column) for column in self.resource_starts)
        tag_positions = _grid(Fraction(0), line, scenario.tag_spacing_m)[0]
        self.tags = tag_table(scenario.source, range(1, len(tag_positions) + 1), tag_positions)
        self.trains = [self._train(spec) for spec in scenario.trains]
        resources = len(self.resource_starts[0])
        zero = (0.0,)
        self.resources = ResourceState(
            owner=zero * resources, holding=zero * (resources * len(self.trains)),
            up=zero * (resources * len(self.trains)), down=zero * (resources * len(self.trains)))
        self.held = [[False] * resources for _ in self.trains]

    @property
    def time_s(self) -> float:
        return self.step_count * self.dt

    def _train(self, spec: TrainSpec) -> TrainRun:
        s, d = self.scenario, spec.data
        starts, ends = self.resource_starts
        data = preset_data(d, subset026_national(), cycle_s=s.cycle_s)
        length = d.train_length_m
        pisl = Profile(tuple(g.start_m for g in s.speed_limits_kmh),
                       tuple(g.value / KMH_PER_MPS for g in s.speed_limits_kmh),
                       s.line_m)
        ptsl = Profile((Fraction(0),), (spec.max_speed_kmh / KMH_PER_MPS,), s.line_m)
        gradient = Profile(tuple(g.start_m for g in s.gradients_permille),
                           tuple(g.value for g in s.gradients_permille), s.line_m)
        compensated = extend_by_train_length(EXACT, gradient, length)
        plant = PlantParams(
            gradient_starts_m=compensated.starts_m, gradient_permille=compensated.values, line_end_m=s.line_m,
            **{k: data[k] for k in ("rotating_mass_uphill_percent", "rotating_mass_downhill_percent",
                                    "max_acceleration_mps2", "guaranteed_deceleration_mps2",
                                    "max_deceleration_mps2", "cycle_s", "traction_cut_cycles",
                                    "brake_build_up_cycles")},
        )
        pos = position_params(self.tags, tag_window_m=s.tag_window_m, tacho_error=s.tacho_error,
                              train_length_m=length, cycle_s=s.cycle_s,
                              max_acceleration_mps2=plant.max_acceleration_mps2 + Fraction(1, 2),
                              max_deceleration_mps2=plant.max_deceleration_mps2)
        authority = AuthorityParams(
            resource_start_m=starts, resource_end_m=ends, resource_is_switch=(False,) * len(starts),
            switch_needs_reverse=(False,) * len(starts), line_end_m=s.line_m, max_ma_m=s.max_ma_m,
            leader_max_deceleration_mps2=max(t.data.emergency_decelerations_mps2[0] for t in s.trains) + 1,
            safety_margin_m=s.safety_margin_m, report_timeout_s=s.report_timeout_s, brick_wall=s.brick_wall,
            cycle_s=s.cycle_s,
        )
        first_tag = self.tags.positions_m.index(spec.front_m)  # powered up on a tag: read in the first cycle
        return TrainRun(
            spec=spec, plant=_as_float(plant),
            position=Monitor(POSITION, _as_float(pos), PositionState(False, 0.0, 0.0, 0.0)),
            authority=AuthorityState(False, *(Fraction(0),) * 3), authority_params=authority,
            supervision=SupervisionState(eb_latched=True, sb_latched=False),
            front_m=float(spec.front_m), speed_mps=0.0, brake_cycles=float(plant.brake_build_up_cycles),
            mrsp=as_float(permanent_speed_limit(EXACT, pisl, ptsl, length)), gradient=as_float(compensated),
            train_data=_as_float(d), national=_as_float(subset026_national()),
            tags_m=_floats(self.tags.positions_m), tag_ids=_floats(self.tags.ids), last_tag=first_tag,
        )

    # --- one cycle ---------------------------------------------------------------------------------------

    def step(self) -> None:
        t = self.time_s
        sends, reports = [], []
        for k, train in enumerate(self.trains):
            leader = self.trains[k - 1] if k else None
            train_sends, report = self._onboard(train, leader, self.held[k], t)
            sends.extend(train_sends)
            reports.append(report)
        for train, report in zip(self.trains, reports, strict=True):  # delivered in the next cycle
            train.report = report
        self._manage(sends)
        self.step_count += 1
        self._check()
        if self.on_cycle is not None:
            self.on_cycle(self)

    def _manage(self, sends: list[bool]) -> None:
        """The resource manager on the resources with anything to do (a send, or a message in flight): the slots
        of different resources never interact in :func:`~atcs.model.resources.resource_step`, and an idle
        resource's slots and owner stay as they are, so this is the whole manager's step."""
        s, trains = self.resources, len(self.trains)
        count = len(s.owner)
        active = [r for r in range(count) if any(
            sends[k * count + r] or s.up[k * count + r] or s.down[k * count + r] for k in range(trains))]
        if not active:
            return
        slots = [k * count + r for k in range(trains) for r in active]
        part = ResourceState(owner=tuple(s.owner[r] for r in active), holding=tuple(s.holding[j] for j in slots),
                             up=tuple(s.up[j] for j in slots), down=tuple(s.down[j] for j in slots))
        every = (True,) * len(slots)
        inputs = ResourceInputs(send=tuple(sends[j] for j in slots), deliver_up=every, deliver_down=every)
        nxt, out = check_step(RESOURCES, Stateless(), part, inputs, RESOURCE_PROPERTIES, self.step_count)
        owner, holding, up, down = list(s.owner), list(s.holding), list(s.up), list(s.down)
        for q, r in enumerate(active):
            owner[r] = nxt.owner[q]
        for q, j in enumerate(slots):
            holding[j], up[j], down[j] = nxt.holding[q], nxt.up[q], nxt.down[q]
            self.held[j // count][j % count] = bool(out.held[q])
        self.resources = ResourceState(tuple(owner), tuple(holding), tuple(up), tuple(down))

    def _onboard(self, train: TrainRun, leader: TrainRun | None, held, t: float):
        """One cycle of one train's onboard functions and its plant: returns (its sends to the resource manager,
        the T2T report it sends)."""
        o, s, spec, data = FLOAT, self.scenario, train.spec, train.spec.data
        tag = train.last_tag
        pos = train.position.step(PositionInputs(
            tag_read=tag is not None, tag_id=train.tag_ids[tag] if tag is not None else 0.0,
            tacho_m=train.last_distance_m))
        zones = [float(z.start_m) for z in s.zones if z.active_at(t)]
        report = leader.report if leader is not None else None
        # exact, from the floats' exact values: the authority properties are checked on exact numbers (the
        # float rounding of a stopping point would break them by an ulp)
        lo, hi = self._window(train, pos, held)
        window = dataclasses.replace(train.authority_params, **{
            name: getattr(train.authority_params, name)[lo:hi] for name in ROUTE_FIELDS})
        n = hi - lo
        train.authority, auth = check_step(AUTHORITY, window, train.authority, AuthorityInputs(
            front_max_m=Fraction(pos.front_max_m), rear_min_m=Fraction(pos.rear_min_m), held=tuple(held[lo:hi]),
            switch_locked=(True,) * n, switch_reversed=(False,) * n, report_delivered=report is not None,
            report_rear_m=Fraction(report[0] if report else 0), report_speed_mps=Fraction(report[1] if report else 0),
            zone_active=bool(zones), zone_start_m=Fraction(min(zones) if zones else 0)),
            AUTHORITY_PROPERTIES, self.step_count, ops=EXACT)
        eoa_m = float(auth.eoa_m)

        horizon = Horizon(mrsp=train.mrsp, gradient=train.gradient, eoa_m=eoa_m, eoa_speed_mps=0.0)
        speed = pos.speed_est_mps
        a_est = float(train.plant.max_acceleration_mps2)
        over, curves, _ = supervise_position(o, train.train_data, train.national, horizon, pos.front_max_m, speed,
                                             a_est)
        departed = t >= float(spec.depart_s)
        released = (departed and not train.started) or (
            spec.eb_release_after_stop_s is not None and train.stopped_s is not None
            and t >= train.stopped_s + float(spec.eb_release_after_stop_s))
        before = train.supervision
        train.supervision, commands = supervise(o, SupervisionParams(True), before, over, pos.standstill,
                                                released, pos.position_valid)
        if train.started and commands.emergency_brake and not before.eb_latched:
            train.stats.emergency_brakes += 1
        if train.started and commands.service_brake and not before.sb_latched:
            train.stats.service_brakes += 1

        # the ATO (seed 003 target speed; seed 000: it follows the permitted curve): traction below the target
        # speed while short of the indication point for its speed, service braking above the target speed or
        # past the indication point
        ahead = limits_ahead(train.mrsp, pos.front_max_m)
        target = ato_target(
            o, front_m=pos.front_max_m, speed_mps=speed, line_limit_mps=ahead.line_limit_mps,
            train_max_mps=float(spec.max_speed_kmh) / KMH, next_limit_m=ahead.next_limit_m,
            next_limit_mps=ahead.next_limit_mps, ma_end_m=eoa_m, ma_speed_mps=0.0,
            planning_decel_mps2=float(s.planning_decel_kmhps) / KMH, margin_m=float(s.ato_margin_m))
        service_max = float(data.service_decelerations_mps2[0])
        train.started = train.started or (departed and not commands.emergency_brake)
        lookahead_m = speed * ATO_LOOKAHEAD_S
        past_indication = pos.front_max_m + lookahead_m >= curves.indication_m
        traction = (departed and speed < target.speed_mps - 0.3 and not past_indication
                    and not commands.traction_cut)
        ato_brake = 0.0
        if speed > 0 and (pos.front_max_m >= curves.indication_m or not departed):
            ato_brake = service_max
        elif speed > target.speed_mps:
            distance = max(target.location_m - pos.front_max_m - float(s.ato_margin_m) / 2, 0.5)
            wanted = (speed * speed - target.speed_mps ** 2) / (2 * distance)
            ato_brake = min(service_max, max(wanted, 0.05))
        ignores_sb = any(f.kind == "ignores_service_brake" and f.active_at(t) for f in spec.faults)
        service = 0.0 if ignores_sb else (service_max if commands.service_brake else ato_brake)
        self._move(train, commands.emergency_brake, traction, service)

        if commands.emergency_brake and train.speed_mps == 0.0 and train.stopped_s is None:
            train.stopped_s = t
        if not commands.emergency_brake:
            train.stopped_s = None
        train.last = {
            "t_s": t, "front_m": train.front_m, "speed_kmh": train.speed_mps * KMH,
            "front_min_m": pos.front_min_m, "front_max_m": pos.front_max_m, "eoa_m": eoa_m,
            "ebi_m": curves.ebi_m, "permitted_m": curves.permitted_m, "target_kmh": target.speed_mps * KMH,
            "eb": bool(commands.emergency_brake), "sb": bool(commands.service_brake),
            "traction": bool(traction), "position_valid": bool(pos.position_valid),
        }
        report = (pos.rear_min_m, max(0.0, pos.speed_est_mps - pos.speed_accuracy_mps)) if pos.position_valid \
            else None
        sends = [False] * len(held)
        sends[lo:hi] = [bool(r) or bool(x) for r, x in zip(auth.request, auth.release, strict=True)]
        return sends, report

    def _window(self, train: TrainRun, pos, held) -> tuple[int, int]:
        """The resources the authority node needs this cycle: those held, those from the min safe rear to
        dRequestResource, and the first one past it (not held, so dLockedResource is the same as over the whole
        route)."""
        starts, ends = self.resource_floats
        d_request = min(float(self.scenario.line_m), pos.front_max_m + float(self.scenario.max_ma_m))
        mine = [r for r, h in enumerate(held) if h]
        lo = min([r for r, end in enumerate(ends) if end > pos.rear_min_m][:1] + mine[:1] + [len(ends) - 1])
        beyond = [r for r, start in enumerate(starts) if start >= d_request][:1]
        hi = max([(beyond[0] if beyond else len(ends) - 1) + 1] + [r + 2 for r in mine[-1:]])
        return lo, min(hi, len(ends))

    def _move(self, train: TrainRun, emergency_brake: bool, traction: bool, service_mps2: float) -> None:
        """The plant: nominal traction and brakes, checked against the proofs' plant bounds."""
        p, dt = train.plant, self.dt
        data = train.spec.data
        brake_on = emergency_brake and train.brake_cycles >= p.brake_build_up_cycles
        grade = value_at(FLOAT, train.gradient, train.front_m)
        a = -float(gradient_braking_mps2(FLOAT, p, grade))
        if brake_on:
            a -= float(data.emergency_decelerations_mps2[0])
        elif traction and not emergency_brake:
            a += float(p.max_acceleration_mps2) * (1 - FLOAT_MARGIN)
        else:
            a -= service_mps2
        v = train.speed_mps
        v_next = max(0.0, v + a * dt)
        distance = v * v / (-2 * a) if v_next == 0.0 and a < 0 else (v + v_next) / 2 * dt
        state = PlantState(front_m=train.front_m, speed_mps=v, brake_cycles=train.brake_cycles)
        if not plant_admits(FLOAT, p, state, emergency_brake, v_next, distance):
            raise SafetyViolation(f"the motion ({v:.3f} -> {v_next:.3f} m/s over {distance:.3f} m) leaves the "
                                  "proofs' plant bounds", train.spec.name, self.step_count, self.time_s)
        passed = [j for j, x in enumerate(train.tags_m) if train.front_m < x <= train.front_m + distance]
        train.last_tag = passed[-1] if passed else None
        train.front_m += distance
        train.speed_mps = v_next
        train.last_distance_m = distance
        train.brake_cycles = min(train.brake_cycles + 1, p.brake_build_up_cycles) if emergency_brake else 0.0
        stats = train.stats
        stats.distance_m += distance
        stats.running_s += dt if distance > 0 else 0.0
        stats.max_speed_kmh = max(stats.max_speed_kmh, v_next * KMH)

    def _check(self) -> None:
        for k, train in enumerate(self.trains):
            if k:
                leader = self.trains[k - 1]
                gap = leader.front_m - float(leader.spec.data.train_length_m) - train.front_m
                train.stats.min_gap_m = min(train.stats.min_gap_m, gap)
                if gap <= 0:
                    raise SafetyViolation(f"collision with {leader.spec.name}", train.spec.name, self.step_count,
                                          self.time_s)
            for zone in self.scenario.zones:
                if zone.active_at(self.time_s) and train.front_m > float(zone.start_m):
                    raise SafetyViolation(f"entered the protection zone at {zone.start_m} m", train.spec.name,
                                          self.step_count, self.time_s)
            if train.front_m > float(self.scenario.line_m):
                raise SafetyViolation("ran past the end of the line", train.spec.name, self.step_count,
                                      self.time_s)

    def run(self) -> Simulation:
        cycles = int(self.scenario.duration_s / self.scenario.cycle_s)
        while self.step_count < cycles:
            self.step()
        return self


def trace_text(rows: list[dict], suffix: str) -> str:
    """A trace as CSV (one row per train and cycle) or JSON lines."""
    if suffix == ".jsonl":
        return "".join(json.dumps(row) + "\n" for row in rows)
    buffer = io.StringIO()
    if rows:
        writer = csv.DictWriter(buffer, fieldnames=list(rows[0]), lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
    return buffer.getvalue()


def _grid(start: Fraction, end: Fraction, spacing: Fraction) -> tuple[tuple[Fraction, ...], tuple[Fraction, ...]]:
    """Consecutive ``[start, end)`` pieces of ``spacing`` (the last one shorter): their starts and ends."""
    starts = []
    x = start
    while x < end:
        starts.append(x)
        x += spacing
    ends = [*starts[1:], end]
    return tuple(starts), tuple(ends)
