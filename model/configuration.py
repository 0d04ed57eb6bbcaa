"""A user's configuration (TOML): the trains, the national values, the lines and the ATP's settings that
``atcs prove --config`` proves the train- and line-dependent properties for (docs/configuration.md is the
reference: every key, its unit, default and range).

Trains are train data files (:mod:`atcs.model.train_files`), named by a path relative to the configuration, or
the seeds' presets. Every error names the file, the field and the value (:class:`ConfigurationError`).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

from atcs.model.braking_data import RailTrain, curve_national_data, curve_train_data
from atcs.model.data_files import TableReader, read_toml
from atcs.model.errors import AtcsInputError
from atcs.model.platforms import Platform, PlatformDataError, Station, platform_data, station_stops
from atcs.model.position import TagTable
from atcs.model.profile import KMH_PER_MPS, MAX_SPEED_KMH, Profile
from atcs.model.route import Resource
from atcs.model.track_layout import track_layout
from atcs.model.train_data import (
    PRESETS,
    NationalData,
    TrainData,
    TrainDataError,
    seed002_national,
    subset026_national,
    validate,
)
from atcs.model.train_files import load_train

__all__ = [
    "FIELDS",
    "NATIONAL_PRESETS",
    "RANGE_FIELDS",
    "Configuration",
    "ConfigurationError",
    "ConfiguredTrain",
    "DataRange",
    "Line",
    "load_configuration",
    "train_with",
]

MAX_LINE_M = 1_000_000
"""The longest line (m), as the curve proofs cover."""
MAX_LINE_GRADIENT_PERMILLE = 40
"""The steepest gradient of a line (per mille): the curve proofs' range, and about the steepest downhill whose
acceleration stays within Subset-026's A_est2 cap of 0.4 m/s^2, which the closed loop's plant assumes."""
MAX_CYCLE_S = 1
"""The longest ATP cycle accepted (s)."""
MAX_RANGE_CELLS = 64
"""The finest split of one range: at most this many cells of its resolution."""

NATIONAL_PRESETS = {"subset026": subset026_national, "seed002": seed002_national}
"""The national values a configuration may start from: Subset-026's defaults (Appendix A.3.2), seed 002's."""

_NATIONAL_FIELDS = tuple(f.name for f in dataclasses.fields(NationalData))

FIELDS = {
    "": ("name", "national", "atp", "trains", "lines"),
    "national": ("preset", *_NATIONAL_FIELDS),
    "atp": ("cycle_s",),
    "trains": ("file", "preset", "ranges"),
    "trains.ranges": ("min", "max", "resolution"),
    "lines": (
        "name",
        "length_m",
        "speed_limits",
        "gradients",
        "tag_spacing_m",
        "resource_length_m",
        "tags",
        "resources",
        "switch_throw_s",
        "platforms",
        "stations",
    ),
}
"""The fields of each table of a configuration (docs/configuration.md documents each)."""


RANGE_FIELDS = {
    "t_be_s": "T_be, the emergency brake's build-up time (s)",
    "t_traction_s": "T_traction, the traction cut-off time (s)",
    "emergency_deceleration_scale": "a factor on every step of A_brake_emergency (1 is the train's own)",
    "service_deceleration_scale": "a factor on every step of A_brake_service (1 is the train's own)",
    "max_acceleration_mps2": "A_max, the train's maximum acceleration (m/s^2)",
    "v_ura_mps": "V_ura, the speed measurement's uncertainty (m/s)",
    "rotating_mass_uphill_percent": "M_rotating's bound for an uphill gradient (%)",
    "rotating_mass_downhill_percent": "M_rotating's bound for a downhill gradient (%)",
}
"""The train data a configuration may give as a range (``[trains.ranges]``), each with what it is."""


@dataclass(frozen=True)
class DataRange:
    """A range of one of :data:`RANGE_FIELDS`: every value in ``[min, max]``, split down to cells no wider than
    ``resolution``."""

    field: str
    min: Fraction
    max: Fraction
    resolution: Fraction


def train_with(train: TrainData, field: str, value) -> TrainData:
    """``train`` with the range field ``field`` at ``value`` (a scale multiplies every step of the brake)."""
    if field.endswith("_deceleration_scale"):
        brake = field.removesuffix("_deceleration_scale")
        key = f"{brake}_decelerations_mps2"
        return dataclasses.replace(train, **{key: tuple(a * value for a in getattr(train, key))})
    return dataclasses.replace(train, **{field: value})


class ConfigurationError(AtcsInputError):
    """A configuration that cannot be used: the message names the file, the field and the value."""


class _Reader(TableReader):
    error = ConfigurationError


@dataclass(frozen=True)
class ConfiguredTrain:
    """A train of the configuration: its name, and its train data for a target at standstill (the curves' and the
    closed loop's: a Lambda train's cm0 build-up times, §3.13.3.4.3) with the configuration's national values."""

    name: str
    train: TrainData
    national: NationalData
    rail: RailTrain | None
    """The train data file's train, None for a preset."""
    ranges: tuple[DataRange, ...] = ()
    """The train data given as ranges: the properties are proved for every value in them."""


@dataclass(frozen=True)
class Line:
    """A line: its speed limits (m/s) and gradients (per mille, uphill positive) from 0 to ``length_m``; for the
    simulator, where its tags and resources repeat, its platforms and its station stops (each on a platform)."""

    name: str
    length_m: Fraction
    speed_limits: Profile
    gradients: Profile
    tag_spacing_m: Fraction | None = None
    resource_length_m: Fraction | None = None
    tags: TagTable | None = None
    """The line's tags one by one (in place of ``tag_spacing_m``)."""
    resources: tuple[Resource, ...] | None = None
    """The line's track and switch resources one by one, from 0 to its end (in place of ``resource_length_m``)."""
    switch_throw_s: Fraction | None = None
    """How long the object controller takes to throw a switch and report it locked (a line with switches)."""
    platforms: tuple[Platform, ...] = ()
    stations: tuple[Station, ...] = ()


@dataclass(frozen=True)
class Configuration:
    source: str
    name: str
    national: NationalData
    cycle_s: Fraction
    trains: tuple[ConfiguredTrain, ...]
    lines: tuple[Line, ...]


def _national(source: str, table) -> NationalData:
    r = _Reader(source, table, "national", FIELDS["national"])
    national = NATIONAL_PRESETS[r.text("preset", "subset026", tuple(NATIONAL_PRESETS))]()
    changes = {}
    for name in _NATIONAL_FIELDS:
        if name not in r.table:
            continue
        if isinstance(getattr(national, name), bool):
            if not isinstance(r.table[name], bool):
                r.fail(name, "must be true or false")
            changes[name] = r.table[name]
        else:
            changes[name] = r.number(name, minimum=0)
    return dataclasses.replace(national, **changes)


def _segments(source: str, r: _Reader, key: str, value_key: str, length_m: Fraction, low, high) -> Profile:
    """``[{start_m = 0, <value_key> = ...}, ...]``: a profile over the line, values within [low, high]."""
    if key not in r.table:
        raise ConfigurationError(f"{source}: {r.name(key)} is missing")
    rows = r.rows(key)
    if not rows:
        r.fail(key, "must be a list of at least one segment")
    starts, values = [], []
    for j, row in enumerate(rows):
        c = _Reader(source, row, f"{r.name(key)}[{j}]", ("start_m", value_key))
        start = c.number("start_m", minimum=0)
        value = c.number(value_key)
        if j == 0 and start != 0:
            c.fail("start_m", "must be 0 for the first segment")
        if j > 0 and start <= starts[-1]:
            c.fail("start_m", "must be after the previous segment's start")
        if start >= length_m:
            c.fail("start_m", f"must be before the line's end ({float(length_m):g} m)")
        if not low <= value <= high or (value_key == "kmh" and value == 0):
            c.fail(value_key, f"is outside {'(' if value_key == 'kmh' else '['}{low}, {high}]")
        starts.append(start)
        values.append(value / KMH_PER_MPS if value_key == "kmh" else value)
    return Profile(tuple(starts), tuple(values), length_m)


def _line(source: str, table, index: int) -> Line:
    r = _Reader(source, table, f"lines[{index}]", FIELDS["lines"])
    length_m = r.number("length_m", positive=True)
    if length_m > MAX_LINE_M:
        r.fail("length_m", f"is above {MAX_LINE_M} m")
    spacings = {}
    for key in ("tag_spacing_m", "resource_length_m"):
        spacings[key] = r.optional_number(key, positive=True)
        if spacings[key] is not None and spacings[key] > length_m:
            r.fail(key, f"must not exceed the line's length ({float(length_m):g} m)")
    return Line(
        name=r.text("name"),
        length_m=length_m,
        speed_limits=_segments(source, r, "speed_limits", "kmh", length_m, 0, MAX_SPEED_KMH),
        gradients=_segments(
            source, r, "gradients", "permille", length_m, -MAX_LINE_GRADIENT_PERMILLE, MAX_LINE_GRADIENT_PERMILLE
        ),
        **spacings,
        **track_layout(r, length_m),
        **_stops(source, r, length_m),
    )


def _stops(source: str, r: _Reader, length_m: Fraction) -> dict:
    """A line's platforms (the table or packet form of a scenario's ``[platforms]``, on the line) and its stations
    (each stop on one of them)."""
    try:
        platforms = platform_data(r.table["platforms"], source, r.name("platforms")) if "platforms" in r.table else ()
    except PlatformDataError as exc:
        raise ConfigurationError(str(exc)) from None
    for j, platform in enumerate(platforms):
        if platform.end_m > length_m:
            raise ConfigurationError(
                f"{source}: {r.name('platforms')}: platform {j + 1} ends at {platform.end_m} m, past the line's end "
                f"({float(length_m):g} m)"
            )
    stations = station_stops(r, "stations", length_m)
    for j, station in enumerate(stations):
        if not any(p.start_m <= station.stop_m <= p.end_m for p in platforms):
            raise ConfigurationError(
                f"{source}: {r.name('stations')}[{j}].stop_m = {station.stop_m}: no platform of "
                f"{r.name('platforms')} spans it"
            )
    return {"platforms": platforms, "stations": stations}


def _ranges(source: str, r: _Reader, t: ConfiguredTrain) -> tuple[DataRange, ...]:
    """``[trains.ranges]``: ``field = { min, max, resolution }`` for fields of :data:`RANGE_FIELDS`; the train data
    must be valid at both ends of each range."""
    table = r.table.get("ranges", {})
    ranges = _Reader(source, table, r.name("ranges"), tuple(RANGE_FIELDS))
    found = []
    for field in table:
        c = _Reader(source, table[field], ranges.name(field), FIELDS["trains.ranges"])
        low, high = c.number("min", minimum=0), c.number("max", minimum=0)
        if high <= low:
            c.fail("max", f"must be above min ({low})")
        resolution = c.number("resolution", positive=True)
        if resolution > high - low:
            c.fail("resolution", f"must be at most max - min ({high - low})")
        if resolution < (high - low) / MAX_RANGE_CELLS:
            c.fail("resolution", f"splits the range into more than {MAX_RANGE_CELLS} cells")
        for key, value in (("min", low), ("max", high)):
            try:
                validate(train_with(t.train, field, value), t.national)
            except TrainDataError as exc:
                c.fail(key, f"makes the train data invalid: {exc}")
        found.append(DataRange(field, low, high, resolution))
    return tuple(found)


def _train(source: str, table, index: int, national: NationalData) -> ConfiguredTrain:
    r = _Reader(source, table, f"trains[{index}]", FIELDS["trains"])
    if ("file" in r.table) == ("preset" in r.table):
        raise ConfigurationError(f"{source}: trains[{index}]: give exactly one of file (a train data file) or preset")
    if "preset" in r.table:
        name = r.text("preset", choices=tuple(PRESETS))
        t = ConfiguredTrain(name, PRESETS[name][0](), national, None)
        return dataclasses.replace(t, ranges=_ranges(source, r, t))
    path = Path(r.text("file"))
    if not path.is_absolute():
        path = Path(source).parent / path
    try:
        rail = load_train(path)
    except TrainDataError as exc:
        raise ConfigurationError(f"{source}: trains[{index}].file: {exc}") from None
    t = ConfiguredTrain(rail.name, curve_train_data(rail, national, 0), curve_national_data(rail, national, 0), rail)
    return dataclasses.replace(t, ranges=_ranges(source, r, t))


def load_configuration(path: str | Path) -> Configuration:
    """The configuration of the TOML file at ``path``; its trains' data are validated with its national values."""
    source = str(path)
    doc = read_toml(path, ConfigurationError, "the configuration")
    top = _Reader(source, doc, "", FIELDS[""])
    national = _national(source, doc.get("national", {}))
    atp = _Reader(source, doc.get("atp", {}), "atp", FIELDS["atp"])
    cycle_s = atp.number("cycle_s", Fraction(1, 10), positive=True)
    if cycle_s > MAX_CYCLE_S:
        atp.fail("cycle_s", f"is above {MAX_CYCLE_S} s")
    for key in ("trains", "lines"):
        if not top.rows(key):
            top.fail(key, f"must list at least one {key[:-1]}")
    trains = tuple(_train(source, row, j, national) for j, row in enumerate(top.rows("trains")))
    lines = tuple(_line(source, row, j) for j, row in enumerate(top.rows("lines")))
    for kind, items in (("trains", trains), ("lines", lines)):
        names = [item.name for item in items]
        for j, name in enumerate(names):
            if name in names[:j]:
                raise ConfigurationError(f"{source}: {kind}[{j}] is named {name!r} as an earlier one")
    for j, t in enumerate(trains):
        try:
            validate(t.train, t.national)
        except TrainDataError as exc:
            raise ConfigurationError(f"{source}: trains[{j}] ({t.name}) with the national values: {exc}") from None
    return Configuration(source, top.text("name"), national, cycle_s, trains, lines)
