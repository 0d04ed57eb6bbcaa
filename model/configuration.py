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
from atcs.model.profile import KMH_PER_MPS, MAX_SPEED_KMH, Profile
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
    "Configuration",
    "ConfigurationError",
    "ConfiguredTrain",
    "Line",
    "load_configuration",
]

MAX_LINE_M = 1_000_000
"""The longest line (m), as the curve proofs cover."""
MAX_LINE_GRADIENT_PERMILLE = 40
"""The steepest gradient of a line (per mille): the curve proofs' range, and about the steepest downhill whose
acceleration stays within Subset-026's A_est2 cap of 0.4 m/s^2, which the closed loop's plant assumes."""
MAX_CYCLE_S = 1
"""The longest ATP cycle accepted (s)."""

NATIONAL_PRESETS = {"subset026": subset026_national, "seed002": seed002_national}
"""The national values a configuration may start from: Subset-026's defaults (Appendix A.3.2), seed 002's."""

_NATIONAL_FIELDS = tuple(f.name for f in dataclasses.fields(NationalData))

FIELDS = {
    "": ("name", "national", "atp", "trains", "lines"),
    "national": ("preset", *_NATIONAL_FIELDS),
    "atp": ("cycle_s",),
    "trains": ("file", "preset"),
    "lines": ("name", "length_m", "speed_limits", "gradients"),
}
"""The fields of each table of a configuration (docs/configuration.md documents each)."""


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


@dataclass(frozen=True)
class Line:
    """A line: its speed limits (m/s) and gradients (per mille, uphill positive) from 0 to ``length_m``."""

    name: str
    length_m: Fraction
    speed_limits: Profile
    gradients: Profile


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
    return Line(
        name=r.text("name"),
        length_m=length_m,
        speed_limits=_segments(source, r, "speed_limits", "kmh", length_m, 0, MAX_SPEED_KMH),
        gradients=_segments(
            source, r, "gradients", "permille", length_m, -MAX_LINE_GRADIENT_PERMILLE, MAX_LINE_GRADIENT_PERMILLE
        ),
    )


def _train(source: str, table, index: int, national: NationalData) -> ConfiguredTrain:
    r = _Reader(source, table, f"trains[{index}]", FIELDS["trains"])
    if ("file" in r.table) == ("preset" in r.table):
        raise ConfigurationError(f"{source}: trains[{index}]: give exactly one of file (a train data file) or preset")
    if "preset" in r.table:
        name = r.text("preset", choices=tuple(PRESETS))
        return ConfiguredTrain(name, PRESETS[name][0](), national, None)
    path = Path(r.text("file"))
    if not path.is_absolute():
        path = Path(source).parent / path
    try:
        rail = load_train(path)
    except TrainDataError as exc:
        raise ConfigurationError(f"{source}: trains[{index}].file: {exc}") from None
    return ConfiguredTrain(rail.name, curve_train_data(rail, national, 0), curve_national_data(rail, national, 0), rail)


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
