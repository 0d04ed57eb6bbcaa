"""Simulation scenarios: TOML files with explicit units, validated with errors naming the file, field and value.

A scenario is a line (length, tags, resources, speed limits, gradients, protection
zones, platforms), the ATP and ATO settings, and the trains in order from the front
(the first train leads). Units are in the field names: ``_m``, ``_s``, ``_kmh``,
``_kmhps`` (km/h per second), ``_permille``. The shipped scenarios are in
``sim/scenarios/``, named after their seed; :func:`shipped` lists them.
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Mapping
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

from atcs.model.braking_data import curve_train_data
from atcs.model.configuration import MAX_LINE_M, ConfigurationError, load_configuration
from atcs.model.data_files import TableReader, read_toml
from atcs.model.errors import AtcsInputError
from atcs.model.platforms import Platform, PlatformDataError, Station, platform_data, station_stops
from atcs.model.position import TagTable, grid_tags
from atcs.model.profile import KMH_PER_MPS, MAX_GRADIENT_PERMILLE, MAX_SPEED_KMH, parse_number
from atcs.model.route import Resource, grid_resources
from atcs.model.track_layout import track_layout
from atcs.model.train_data import PRESETS as TRAIN_PRESETS
from atcs.model.train_data import (
    NationalData,
    TrainData,
    TrainDataError,
    seed002_national,
    subset026_national,
    whole_cycle_train,
)
from atcs.model.train_files import load_train
from atcs.sim.double_track import TRACKS, DoubleTrack

SCENARIO_DIR = Path(__file__).parent / "scenarios"
MAX_DURATION_S = 86_400
"""The longest run a scenario may ask for (s): a day of operation."""
MAX_PLANNING_DECEL_KMHPS = 18
"""The highest deceleration the ATO may plan with (km/h/s): 5 m/s^2, above any train's service brake."""
MAX_CYCLE_S = 1
"""The longest ATP cycle a scenario may give (s): the position node reads at most one tag a cycle."""
PRESETS = {name: train for name, (train, _) in TRAIN_PRESETS.items()}
"""The seeds' trains a scenario's ``preset`` names."""
NATIONAL = {"subset026": subset026_national, "seed002": seed002_national}
FAULTS = {
    "ignores_service_brake": "the train does not apply the ATP's service brake command",
    "traction_stuck": "full traction stays applied whatever the ATO, the doors and the ATP's traction cut and "
    "service brake command; only EB (its own loop) cuts it",
    "missed_tag": "the tag reader reads nothing",
    "spurious_tag": "the tag reader reports tag id `tag_id` (default 999999, not in the table) every cycle",
    "tacho_drift": "the tachometer reads `factor` times the distance run (e.g. 1.03)",
    "tacho_slide": "the tachometer reads `factor` times the distance run while braking (e.g. 0.5: a slide)",
    "t2t_loss": "the train's T2T reports are lost",
    "t2t_delay": "the train's T2T reports arrive `delay_s` late",
    "t2t_reorder": "every other T2T report of the train is held back two cycles, so it arrives after the next one",
    "t2t_replay": "the train's T2T reports are replaced by a replay of the last one delivered before the fault",
    "t2t_corrupt": "one bit of each T2T report of the train is flipped on the way (its rear's 2^24 cm bit)",
    "stuck_door": "an obstacle holds the doors open",
    "atp_reset": "the onboard ATP restarts in each cycle of the window: position unknown, no leader known, EB "
    "latched, as at power-up",
    "switch_unlocked": "the object controller reports every switch on the train's route unlocked (detection lost, "
    "a switch moving)",
    "integrity_lost": "the rear half of the train parts at `from_s` and brakes to a stop where it stays; the "
    "train's integrity monitor reports the loss during the window",
    "lying_door_sensor": "one of the DCU's two door detection loops reports every door closed and locked whatever "
    "the doors",
    "brake_fade": "the brakes (emergency and service) deliver `factor` times the train data's deceleration (e.g. "
    "0.8: fade, low adhesion)",
    "ats_status_lost": "the ATS's status messages (protection zones, temporary restrictions) do not reach the train",
    "clock_drift": "the train's clock runs `factor` times as fast as true time (e.g. 1.05, or 0.95: slow)",
}
"""Fault kinds a train may carry for a time window, and what each does."""
FAULT_FIELDS = {
    "spurious_tag": {"tag_id": 999999},
    "tacho_drift": {"factor": None},
    "tacho_slide": {"factor": None},
    "t2t_delay": {"delay_s": None},
    "clock_drift": {"factor": None},
    "brake_fade": {"factor": None},
}
"""Each fault's own fields, with their defaults (None: required)."""
FAULT_FIELD_MAXIMUM = {"factor": 10, "delay_s": MAX_DURATION_S, ("brake_fade", "factor"): 1}
"""The largest value of a fault's own field (by field, or by kind and field): a tachometer or clock off by more
than 10 times, or a report late by more than a day, is no fault a run can show more of (and a clock 10 times fast
keeps a day's time stamps within the report's 32-bit milliseconds); a brake delivering more than its train data is
no fade."""


class ScenarioError(AtcsInputError):
    """A malformed scenario; the message names the file, the field and the value."""


@dataclass(frozen=True)
class Segment:
    start_m: Fraction
    value: Fraction


@dataclass(frozen=True)
class Zone:
    """A protection zone set by the ATS: trains must stop short of ``start_m`` while it is active."""

    start_m: Fraction
    from_s: Fraction
    until_s: Fraction | None

    def active_at(self, t_s) -> bool:
        return self.from_s <= t_s and (self.until_s is None or t_s < self.until_s)


@dataclass(frozen=True)
class Fault:
    kind: str
    from_s: Fraction
    until_s: Fraction | None
    value: Fraction | None = None
    """The fault's own field (``tag_id``, ``factor`` or ``delay_s``, :data:`FAULT_FIELDS`), if it has one."""

    active_at = Zone.active_at


@dataclass(frozen=True)
class Window:
    """A time window: a resource-manager outage."""

    from_s: Fraction
    until_s: Fraction | None
    zone: int | None = None
    """The wayside zone whose manager is out (1, 2, ...; None: every zone's)."""

    active_at = Zone.active_at


@dataclass(frozen=True)
class TimedRestriction:
    """A temporary speed restriction (TISL) the ATS sets on ``[start_m, end_m)`` for a time window."""

    start_m: Fraction
    end_m: Fraction
    kmh: Fraction
    from_s: Fraction
    until_s: Fraction | None

    active_at = Zone.active_at


@dataclass(frozen=True)
class TrainSpec:
    name: str
    data: TrainData
    front_m: Fraction
    max_speed_kmh: Fraction
    depart_s: Fraction
    faults: tuple[Fault, ...] = ()
    eb_release_after_stop_s: Fraction | None = None
    """The driver's release input this long after an emergency stop (never, if None)."""
    first_door_m: Fraction = Fraction(10)
    """The foremost door's distance behind the front."""
    last_door_m: Fraction | None = None
    """The rearmost door's distance behind the front (default: 10 m short of the train's length)."""

    def fault(self, kind: str, t_s) -> Fault | None:
        """The fault of this kind active at ``t_s``, if any."""
        return next((f for f in self.faults if f.kind == kind and f.active_at(t_s)), None)


@dataclass(frozen=True)
class Scenario:
    name: str
    seed: str
    description: str
    source: str
    duration_s: Fraction
    cycle_s: Fraction
    line_m: Fraction
    tags: TagTable
    """The line's tags (on a double track, round the loop)."""
    resources: tuple[Resource, ...]
    """The line's track and switch resources from 0 to :attr:`line_m`."""
    speed_limits_kmh: tuple[Segment, ...]
    gradients_permille: tuple[Segment, ...]
    max_ma_m: Fraction
    brick_wall: bool
    safety_margin_m: Fraction
    report_timeout_s: Fraction
    tag_window_m: Fraction
    tacho_error: Fraction
    planning_decel_kmhps: Fraction
    ato_margin_m: Fraction
    trains: tuple[TrainSpec, ...]
    zones: tuple[Zone, ...] = ()
    platforms: tuple[Platform, ...] = field(default=())
    national: NationalData = field(default_factory=subset026_national)
    ato_speed_margin_kmh: Fraction = Fraction(0)
    clock_skew_s: Fraction = Fraction(0)
    """The largest difference between two trains' clocks the ATP allows for when it ages a T2T report."""
    status_timeout_s: Fraction = Fraction(2)
    """The oldest the ATS's status may be for a train to run on it (:mod:`atcs.model.ats_status`)."""
    """The ATO aims this far under the line's limits (seed 002 §4.2: 25 km/h under a 30 km/h limit)."""
    restrictions: tuple[TimedRestriction, ...] = ()
    stations: tuple[Station, ...] = ()
    stop_tolerance_m: Fraction = Fraction(1)
    """How far the safe front interval may lie from a station's stopping point for the doors (seed 004 §2.1)."""
    manager_outages: tuple[Window, ...] = ()
    ato_reference_profile: bool = False
    """The ATO tracks the minimum-time profile to the next station stop (:mod:`atcs.sim.reference_profile`)."""
    switch_throw_s: Fraction | None = None
    """How long the object controller takes to throw a switch (a line with switches)."""
    double_track: DoubleTrack | None = None
    """The double track with its turn-backs, one closed track of :attr:`line_m` (:mod:`atcs.sim.double_track`);
    None: an open line from 0 to :attr:`line_m`. Every position of the scenario is in loop coordinates."""

    @property
    def loop(self) -> bool:
        return self.double_track is not None


class _Reader(TableReader):
    error = ScenarioError


def _segments(
    reader: _Reader, key: str, value_key: str, default: Fraction, line_m: Fraction, *, positive: bool, high
) -> tuple[Segment, ...]:
    """The rows of ``key``: from 0, increasing starts on the line, values in (0, high] (``positive``) or
    [-high, high]."""
    rows = reader.rows(key)
    if not rows:
        return (Segment(Fraction(0), default),)
    segments = []
    for j, row in enumerate(rows):
        r = _Reader(reader.source, row, f"{reader.name(key)}[{j}]", ("start_m", value_key))
        start = r.number("start_m", minimum=0)
        value = r.number(value_key, positive=positive, minimum=None if positive else -high, maximum=high)
        if j == 0 and start != 0:
            r.fail("start_m", "must be 0 for the first segment")
        if j > 0 and start <= segments[-1].start_m:
            r.fail("start_m", "must be after the previous segment's start")
        if start >= line_m:
            r.fail("start_m", f"must be before the line's end ({line_m} m)")
        segments.append(Segment(start, value))
    return tuple(segments)


def _window(r: _Reader) -> tuple[Fraction, Fraction | None]:
    start = r.number("from_s", 0, minimum=0)
    until = r.optional_number("until_s")
    if until is not None and until <= start:
        r.fail("until_s", f"must be after from_s ({start} s)")
    return start, until


def _track(r: _Reader, layout: DoubleTrack | None) -> str:
    """The row's ``track`` (``up`` unless it says ``down``); only a double track has one."""
    return r.text("track", "up", TRACKS) if layout is not None else "up"


def _row_fields(layout: DoubleTrack | None, *fields: str) -> tuple[str, ...]:
    return (*fields, "track") if layout is not None else fields


def _train_data(source: str, r: _Reader, national: NationalData, cycle_s: Fraction) -> TrainData:
    """The train of the row's ``preset``, or of its train data ``file`` (relative to the scenario; its data for a
    target at standstill, T_be and T_traction rounded up to whole cycles as in the closed-loop proofs)."""
    if "file" not in r.table:
        return PRESETS[r.text("preset", "seed000", tuple(PRESETS))]()
    if "preset" in r.table:
        r.fail("file", "and preset both given: give one")
    path = Path(r.text("file"))
    path = path if path.is_absolute() else Path(source).parent / path
    try:
        data = whole_cycle_train(curve_train_data(load_train(path), national, 0), cycle_s)
    except TrainDataError as exc:
        raise ScenarioError(f"{source}: {r.name('file')}: {exc}") from None
    if len(data.emergency_decelerations_mps2) != 1:
        r.fail(
            "file",
            f"gives an emergency brake of {len(data.emergency_decelerations_mps2)} speed steps: the simulated "
            "plant guarantees one deceleration at every speed",
        )
    return data


def _train(
    source: str,
    row,
    j: int,
    length_m: Fraction,
    layout: DoubleTrack | None,
    tags: TagTable,
    national: NationalData,
    cycle_s: Fraction,
) -> TrainSpec:
    r = _Reader(
        source,
        row,
        f"trains[{j}]",
        _row_fields(
            layout,
            "name",
            "preset",
            "file",
            "front_m",
            "max_speed_kmh",
            "depart_s",
            "faults",
            "eb_release_after_stop_s",
            "first_door_m",
            "last_door_m",
        ),
    )
    name = r.text("name", f"T{j + 1}")
    data = _train_data(source, r, national, cycle_s)
    track = _track(r, layout)
    front = r.number("front_m", minimum=0)
    front_loop = layout.point(track, front) if layout is not None else front
    if front >= length_m or (layout is None and front - data.train_length_m < 0):
        r.fail(
            "front_m",
            f"must put the whole train on the line (its length is {data.train_length_m} m, the line {length_m} m)",
        )
    if layout is not None and front_loop - data.train_length_m < 0:
        r.fail(
            "front_m",
            f"must put the whole train on the loop: its rear ({data.train_length_m} m behind) would "
            "be round the near turn-back, behind the loop's origin (x = 0 on the up track)",
        )
    if front_loop not in tags.positions_m:
        r.fail("front_m", "must be on a tag of the line: a train powers up on a tag and reads it in its first cycle")
    faults = []
    for k, fault in enumerate(r.rows("faults")):
        where = f"{r.name('faults')}[{k}]"
        kind = _Reader(source, fault, where, tuple(fault) if isinstance(fault, Mapping) else ()).text(
            "kind", choices=tuple(FAULTS)
        )
        own = FAULT_FIELDS.get(kind, {})
        f = _Reader(source, fault, where, ("kind", "from_s", "until_s", *own))
        value = None
        for key, default in own.items():
            maximum = FAULT_FIELD_MAXIMUM.get((kind, key), FAULT_FIELD_MAXIMUM.get(key))
            value = f.number(key, default, positive=True, maximum=maximum)
            if key == "tag_id" and value.denominator != 1:
                f.fail(key, "must be a whole number (a tag's id)")
        faults.append(Fault(kind, *_window(f), value))
    first_door = r.number("first_door_m", 10, minimum=0)
    last_door = r.number("last_door_m", data.train_length_m - 10, minimum=0)
    if not first_door <= last_door <= data.train_length_m:
        r.fail(
            "last_door_m",
            f"must lie from first_door_m ({first_door} m) to the train's length ({data.train_length_m} m)",
        )
    return TrainSpec(
        name=name,
        data=data,
        front_m=front_loop,
        max_speed_kmh=r.number("max_speed_kmh", positive=True, maximum=MAX_SPEED_KMH),
        depart_s=r.number("depart_s", 0, minimum=0, maximum=MAX_DURATION_S),
        faults=tuple(faults),
        eb_release_after_stop_s=r.optional_number("eb_release_after_stop_s", minimum=0),
        first_door_m=first_door,
        last_door_m=last_door,
    )


def _trains_in_order(source: str, trains: list[TrainSpec], layout: DoubleTrack | None) -> tuple[TrainSpec, ...]:
    """The trains from the front. On an open line they must be listed so; on the loop of a double track the front
    train is the one farthest along the loop, and its leader is the last (round the near turn-back, which no train
    is on at the start: every train's rear is at or after the loop's origin)."""
    if layout is not None:
        trains = sorted(trains, key=lambda t: -t.front_m)
    for j, (ahead, train) in enumerate(itertools.pairwise(trains), start=1):
        rear = ahead.front_m - ahead.data.train_length_m
        if train.front_m >= rear and layout is None:
            raise ScenarioError(
                f"{source}: trains[{j}].front_m = {train.front_m} must be behind the rear of "
                f"{ahead.name} ({rear} m; trains are listed from the front)"
            )
        if train.front_m >= rear:
            raise ScenarioError(
                f"{source}: trains: {train.name} (front at {train.front_m} m round the loop) "
                f"overlaps {ahead.name} (rear at {rear} m)"
            )
    return tuple(trains)


def _double_track(line: _Reader, length_m: Fraction, spacings: dict, one_by_one: dict) -> DoubleTrack | None:
    flag = line.table.get("double_track", False)
    if not isinstance(flag, bool):
        line.fail("double_track", "must be true or false")
    own = ("turn_back_m", "turn_back_kmh", "wayside_zone_boundaries_m")
    if not flag:
        for key in own:
            if key in line.table:
                line.fail(key, "needs line.double_track = true")
        return None
    for key, given in one_by_one.items():
        if given is not None:
            line.fail(
                key,
                "is given one by one: a double track lays its tags and resources round the loop by "
                "line.tag_spacing_m and line.resource_length_m",
            )
    turn_back = line.number("turn_back_m", positive=True)
    for key, value in (("length_m", length_m), ("turn_back_m", turn_back)):
        for spacing_key, spacing in spacings.items():
            if value % spacing:
                line.fail(
                    key,
                    f"must be a multiple of line.{spacing_key} = {spacing} on a double track, so that "
                    "the tags and resources of both tracks repeat round the loop",
                )
    return DoubleTrack(length_m, turn_back, _wayside_zone_boundaries(line, length_m))


def _wayside_zone_boundaries(line: _Reader, length_m: Fraction) -> tuple[Fraction, ...]:
    """The boundaries between the wayside zones of a double track: increasing positions inside the line."""
    raw = line.table.get("wayside_zone_boundaries_m", [])
    if not isinstance(raw, list):
        line.fail("wayside_zone_boundaries_m", "must be a list of positions along the line")
    boundaries = []
    for j, value in enumerate(raw):
        b = parse_number(line.source, f"line.wayside_zone_boundaries_m[{j}]", value, ScenarioError)
        if not (boundaries[-1] if boundaries else 0) < b < length_m:
            raise ScenarioError(
                f"{line.source}: line.wayside_zone_boundaries_m[{j}] = {value!r} must lie inside the "
                f"line (0 to {length_m} m) and after the previous boundary"
            )
        boundaries.append(b)
    return tuple(boundaries)


def _mirrored_stations(
    source: str, stations: list[Station], platforms: tuple[Platform, ...], layout: DoubleTrack
) -> tuple[tuple[Station, ...], tuple[Platform, ...]]:
    """The stations and platforms of both tracks, in loop order: those given (the up track), then their mirror on
    the down track. A down train stops with its doors where an up train's are, mirrored about the platform."""
    down = []
    for j, station in enumerate(stations):
        spanning = [p for p in platforms if p.start_m <= station.stop_m <= p.end_m]
        if not spanning:
            raise ScenarioError(
                f"{source}: stations[{j}].stop_m = {station.stop_m}: no platform of [platforms] "
                "contains it, so it has no mirror on the down track"
            )
        p = spanning[0]
        down.append(
            Station(
                f"{station.name} (down)", layout.point("down", p.start_m + p.end_m - station.stop_m), station.dwell_s
            )
        )
    mirrored = []
    for p in platforms:
        start, end = layout.interval("down", p.start_m, p.end_m)
        mirrored.append(dataclasses.replace(p, start_m=start, end_m=end))
    return (*stations, *reversed(down)), (*platforms, *reversed(mirrored))


def _message_timing(atp) -> tuple[Fraction, Fraction, Fraction]:
    """The T2T reports' and the ATS status's time-outs, and the clock skew allowed for, each below its time-out."""
    report_timeout_s = atp.number("report_timeout_s", positive=True, maximum=MAX_DURATION_S)
    status_timeout_s = atp.number("status_timeout_s", report_timeout_s, positive=True, maximum=MAX_DURATION_S)
    clock_skew_s = atp.number("clock_skew_s", 0, minimum=0)
    for key, timeout in (("report_timeout_s", report_timeout_s), ("status_timeout_s", status_timeout_s)):
        if clock_skew_s >= timeout:
            atp.fail("clock_skew_s", f"must be below {key} ({timeout}): every message would be stale")
    return report_timeout_s, status_timeout_s, clock_skew_s


def load_scenario(path: str | Path) -> Scenario:
    """Read and check a scenario file (:class:`ScenarioError` on anything malformed)."""
    source = str(path)
    document = read_toml(path, ScenarioError, "the scenario")
    top = _Reader(
        source,
        document,
        "",
        (
            "name",
            "seed",
            "description",
            "duration_s",
            "cycle_s",
            "line",
            "atp",
            "ato",
            "trains",
            "zones",
            "platforms",
            "restrictions",
            "stations",
            "manager_outages",
        ),
    )
    for key in ("line", "atp", "ato"):
        if key not in document:
            raise ScenarioError(f"{source}: [{key}] is missing")
    line = _Reader(
        source,
        document["line"],
        "line",
        (
            "length_m",
            "configuration",
            "line",
            "tag_spacing_m",
            "resource_length_m",
            "tags",
            "resources",
            "switch_throw_s",
            "speed_limits",
            "gradients",
            "max_ma_m",
            "double_track",
            "turn_back_m",
            "turn_back_kmh",
            "wayside_zone_boundaries_m",
        ),
    )
    configured = _configured_line(line)
    length_m = line.number("length_m", positive=True, maximum=MAX_LINE_M) if configured is None else configured.length_m
    spacings, one_by_one = _track_layout(line, configured, length_m)
    layout = _double_track(line, length_m, spacings, one_by_one)
    line_m = layout.loop_m if layout is not None else length_m
    for key, spacing in spacings.items():
        if spacing is not None and line_m / spacing > MAX_GRID:
            line.fail(key, f"lays more than {MAX_GRID:,} of them on the line ({float(line_m):g} m)")
    tags = one_by_one["tags"] or grid_tags(line_m, spacings["tag_spacing_m"])
    resources = one_by_one["resources"] or grid_resources(line_m, spacings["resource_length_m"])
    speed_limits, gradients = _line_profiles(line, length_m, layout, configured)
    atp = _Reader(
        source,
        document["atp"],
        "atp",
        (
            "mode",
            "safety_margin_m",
            "report_timeout_s",
            "status_timeout_s",
            "clock_skew_s",
            "tag_window_m",
            "tacho_error",
            "national",
            "stop_tolerance_m",
        ),
    )
    ato = _Reader(
        source, document["ato"], "ato", ("planning_decel_kmhps", "margin_m", "speed_margin_kmh", "reference_profile")
    )
    reference = document["ato"].get("reference_profile", False)
    if not isinstance(reference, bool):
        ato.fail("reference_profile", "must be true or false")
    tacho_error = atp.number("tacho_error", minimum=0)
    report_timeout_s, status_timeout_s, clock_skew_s = _message_timing(atp)
    if tacho_error >= 1:
        atp.fail("tacho_error", "must be below 1")
    rows = top.rows("trains")
    if not rows:
        raise ScenarioError(f"{source}: trains: at least one [[trains]] entry is needed")
    national = NATIONAL[atp.text("national", "subset026", tuple(NATIONAL))]()
    cycle_s = top.number("cycle_s", "0.1", positive=True, maximum=MAX_CYCLE_S)
    _tags_apart(line, tags, speed_limits, cycle_s)
    trains = _trains_in_order(
        source,
        [_train(source, row, j, length_m, layout, tags, national, cycle_s) for j, row in enumerate(rows)],
        layout,
    )
    platforms, stations = _platforms_and_stations(top, document, length_m, configured)
    given = len(stations)
    if layout is not None:
        stations, platforms = _mirrored_stations(source, stations, platforms, layout)
    scenario = Scenario(
        name=top.text("name"),
        seed=top.text("seed"),
        description=top.text("description", ""),
        source=source,
        duration_s=top.number("duration_s", positive=True, maximum=MAX_DURATION_S),
        cycle_s=cycle_s,
        line_m=line_m,
        tags=tags,
        resources=resources,
        switch_throw_s=one_by_one["switch_throw_s"],
        speed_limits_kmh=speed_limits,
        gradients_permille=gradients,
        max_ma_m=line.number("max_ma_m", positive=True, maximum=MAX_LINE_M),
        brick_wall=atp.text("mode", "relative_braking", ("relative_braking", "brick_wall")) == "brick_wall",
        safety_margin_m=atp.number("safety_margin_m", minimum=0, maximum=MAX_LINE_M),
        report_timeout_s=report_timeout_s,
        status_timeout_s=status_timeout_s,
        clock_skew_s=clock_skew_s,
        tag_window_m=atp.number("tag_window_m", minimum=0),
        tacho_error=tacho_error,
        planning_decel_kmhps=ato.number("planning_decel_kmhps", positive=True, maximum=MAX_PLANNING_DECEL_KMHPS),
        ato_margin_m=ato.number("margin_m", minimum=0, maximum=MAX_LINE_M),
        trains=trains,
        zones=_zones(source, top, length_m, layout),
        platforms=tuple(platforms),
        national=national,
        ato_speed_margin_kmh=ato.number("speed_margin_kmh", 0, minimum=0),
        restrictions=_restrictions(source, top, length_m, layout),
        stations=tuple(stations),
        stop_tolerance_m=atp.number("stop_tolerance_m", 1, positive=True),
        manager_outages=_outages(source, top, layout),
        ato_reference_profile=reference,
        double_track=layout,
    )
    _check_stops(scenario, given=given)
    return scenario


def _configured_line(line: _Reader):
    """The line that ``line.configuration`` (a configuration file, relative to the scenario) names ``line.line``,
    or None without one; the scenario then gives neither its length, nor its speed limits, nor its gradients."""
    if "configuration" not in line.table:
        if "line" in line.table:
            line.fail("line", "needs line.configuration, the file that has the line")
        return None
    for key in ("length_m", "speed_limits", "gradients"):
        if key in line.table:
            line.fail(key, "and line.configuration both given: the configuration's line has its own")
    path = Path(line.text("configuration"))
    path = path if path.is_absolute() else Path(line.source).parent / path
    try:
        config = load_configuration(path)
    except ConfigurationError as exc:
        raise ScenarioError(f"{line.source}: line.configuration: {exc}") from None
    name = line.text("line", config.lines[0].name if len(config.lines) == 1 else None)
    found = [ln for ln in config.lines if ln.name == name]
    if not found:
        line.fail("line", f"names no line of {path} (its lines: {', '.join(ln.name for ln in config.lines)})")
    return found[0]


MAX_GRID = 100_000
"""The most tags, or resources, a spacing may lay on a line (a 1,000 km line at 10 m)."""


def _tags_apart(line: _Reader, tags: TagTable, speed_limits: tuple[Segment, ...], cycle_s: Fraction) -> None:
    """Consecutive tags more than a cycle's run at the line's top speed limit apart: the position node reads at
    most one tag a cycle (``reader_complete``; the simulator stops a train that passes two)."""
    top_kmh = max(g.value for g in speed_limits)
    run_m = top_kmh / KMH_PER_MPS * cycle_s
    for j, (a, b) in enumerate(itertools.pairwise(tags.positions_m), start=1):
        if b - a <= run_m:
            raise ScenarioError(
                f"{line.source}: line: tag {j} at {float(b):g} m is {float(b - a):g} m after the tag before it, "
                f"within a cycle's run at the line's top speed limit ({float(top_kmh):g} km/h for cycle_s = "
                f"{float(cycle_s):g} s: {float(run_m):.3g} m): the position node reads at most one tag a cycle"
            )


def _track_layout(line: _Reader, configured, length_m: Fraction) -> tuple[dict, dict]:
    """The line's tags and resources, by spacing (``tag_spacing_m``, ``resource_length_m``) or one by one
    (``tags``, ``resources`` with ``switch_throw_s``): the scenario's, or the configured line's where it gives
    them (not both). Returns the spacings and the one-by-one forms (None where not given)."""
    own = track_layout(line, length_m)
    spacings = {key: line.optional_number(key, positive=True) for key in ("tag_spacing_m", "resource_length_m")}
    for form, spacing_key in (("tags", "tag_spacing_m"), ("resources", "resource_length_m")):
        theirs = configured is not None and (
            getattr(configured, form) is not None or getattr(configured, spacing_key) is not None
        )
        if theirs:
            for key in (form, spacing_key, *(("switch_throw_s",) if form == "resources" else ())):
                if key in line.table:
                    line.fail(key, "and line.configuration's line both give it: the configuration's line has its own")
            own[form], spacings[spacing_key] = getattr(configured, form), getattr(configured, spacing_key)
            if form == "resources":
                own["switch_throw_s"] = configured.switch_throw_s
        elif own[form] is None and spacings[spacing_key] is None:
            raise ScenarioError(f"{line.source}: line.{spacing_key} is missing (or line.{form}, one by one)")
        if spacings[spacing_key] is not None and spacings[spacing_key] > length_m:
            line.fail(spacing_key, f"must not exceed the line's length ({length_m} m)")
    return spacings, own


def _platforms_and_stations(top: _Reader, document: Mapping, length_m: Fraction, configured) -> tuple[list, list]:
    """The scenario's ``[platforms]`` and ``[[stations]]``, or the configured line's when it has them (not both)."""
    if configured is not None and configured.platforms:
        for key in ("platforms", "stations"):
            if key in document:
                top.fail(key, "and line.configuration's line both give them: the configuration's line has its own")
        return list(configured.platforms), list(configured.stations)
    try:
        platforms = platform_data(document["platforms"], top.source) if "platforms" in document else ()
    except PlatformDataError as exc:
        raise ScenarioError(str(exc)) from None
    return list(platforms), list(station_stops(top, "stations", length_m))


def _line_profiles(
    line: _Reader, length_m: Fraction, layout, configured=None
) -> tuple[tuple[Segment, ...], tuple[Segment, ...]]:
    """The line's speed limits and gradients (the scenario's, or the ``configured`` line's), laid out over both
    tracks of a double track."""
    if configured is None:
        speed_limits = _segments(line, "speed_limits", "kmh", Fraction(80), length_m, positive=True, high=MAX_SPEED_KMH)
        gradients = _segments(
            line, "gradients", "permille", Fraction(0), length_m, positive=False, high=MAX_GRADIENT_PERMILLE
        )
    else:
        limits, grads = configured.speed_limits, configured.gradients
        speed_limits = tuple(Segment(x, v * KMH_PER_MPS) for x, v in zip(limits.starts_m, limits.values, strict=True))
        gradients = tuple(Segment(x, g) for x, g in zip(grads.starts_m, grads.values, strict=True))
    if layout is None:
        return speed_limits, gradients
    turn_back_kmh = line.number("turn_back_kmh", positive=True)
    speed_limits = tuple(
        Segment(*x)
        for x in zip(
            *layout.segments([g.start_m for g in speed_limits], [g.value for g in speed_limits], turn_back_kmh),
            strict=True,
        )
    )
    gradients = tuple(
        Segment(*x)
        for x in zip(
            *layout.segments([g.start_m for g in gradients], [g.value for g in gradients], Fraction(0), negate=True),
            strict=True,
        )
    )
    return speed_limits, gradients


def _zones(source: str, top: _Reader, length_m: Fraction, layout) -> tuple[Zone, ...]:
    zones = []
    for j, row in enumerate(top.rows("zones")):
        z = _Reader(source, row, f"zones[{j}]", _row_fields(layout, "start_m", "from_s", "until_s"))
        start = z.number("start_m", minimum=0)
        if start > length_m:
            z.fail("start_m", f"must be on the line ({length_m} m)")
        zones.append(Zone(layout.point(_track(z, layout), start) if layout else start, *_window(z)))
    return tuple(zones)


def _restrictions(source: str, top: _Reader, length_m: Fraction, layout) -> tuple[TimedRestriction, ...]:
    restrictions = []
    for j, row in enumerate(top.rows("restrictions")):
        x = _Reader(
            source, row, f"restrictions[{j}]", _row_fields(layout, "start_m", "end_m", "kmh", "from_s", "until_s")
        )
        start, end = x.number("start_m", minimum=0), x.number("end_m")
        if not start < end <= length_m:
            x.fail("end_m", f"must lie after start_m ({start} m) and on the line ({length_m} m)")
        if layout is not None:
            start, end = layout.interval(_track(x, layout), start, end)
        restrictions.append(TimedRestriction(start, end, x.number("kmh", positive=True), *_window(x)))
    return tuple(restrictions)


def _outages(source: str, top: _Reader, layout) -> tuple[Window, ...]:
    zone_count = layout.zones if layout is not None else 1
    outages = []
    for j, row in enumerate(top.rows("manager_outages")):
        w = _Reader(source, row, f"manager_outages[{j}]", ("from_s", "until_s", "zone"))
        zone = w.optional_number("zone", minimum=1)
        if zone is not None and (zone.denominator != 1 or zone > zone_count):
            w.fail("zone", f"must be a wayside zone, a whole number from 1 to {zone_count}")
        outages.append(Window(*_window(w), None if zone is None else int(zone)))
    return tuple(outages)


def _check_stops(scenario: Scenario, given: int) -> None:
    """The stations need a reference profile's stops, a stop tolerance past the tag window, and a platform under
    every train's doors (``given`` stations in the file; a double track mirrors them on the down track)."""
    source = scenario.source
    if scenario.ato_reference_profile and not scenario.stations:
        raise ScenarioError(
            f"{source}: ato.reference_profile = true needs [[stations]]: the profile runs from stop to stop"
        )
    if scenario.stations and scenario.stop_tolerance_m <= scenario.tag_window_m:
        raise ScenarioError(
            f"{source}: atp.stop_tolerance_m = {scenario.stop_tolerance_m} must exceed "
            f"atp.tag_window_m = {scenario.tag_window_m}: the position interval is at least "
            "the tag window either side, so the doors could never be enabled at a station"
        )
    for j, station in enumerate(scenario.stations):
        where = (
            f"stations[{j}].stop_m ="
            if j < given
            else f"stations[{2 * given - 1 - j}].stop_m, mirrored on the down track to"
        )
        for train in scenario.trains:
            tolerance = scenario.stop_tolerance_m  # the doors wherever the front is within it
            doors = (station.stop_m - tolerance - train.last_door_m, station.stop_m + tolerance - train.first_door_m)
            if not any(p.start_m <= doors[0] and doors[1] <= p.end_m for p in scenario.platforms):
                raise ScenarioError(
                    f"{source}: {where} {station.stop_m}: no platform of [platforms] spans "
                    f"{train.name}'s doors there ({doors[0]} m to {doors[1]} m)"
                )


def shipped() -> dict[str, Path]:
    """The scenarios shipped in ``sim/scenarios/``, by name (the file's stem)."""
    return {path.stem: path for path in sorted(SCENARIO_DIR.glob("*.toml"))}


def resolve(name_or_path: str) -> Path:
    """A scenario file: a path, or the name of a shipped scenario."""
    path = Path(name_or_path)
    if path.suffix == ".toml" or path.exists():
        return path
    known = shipped()
    if name_or_path not in known:
        raise ScenarioError(f"{name_or_path}: no such file, nor a shipped scenario ({', '.join(known)})")
    return known[name_or_path]
