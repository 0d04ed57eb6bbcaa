"""Configurations (docs/configuration.md): the loader accepts exactly the documented keys, the shipped ones load,
and every bad value is refused naming the file, the field and the value."""

import dataclasses
import math
import re
from fractions import Fraction
from pathlib import Path

import pytest

from atcs.model.configuration import FIELDS, ConfigurationError, load_configuration
from atcs.model.profile import Profile
from atcs.model.train_data import whole_cycle_train
from atcs.model.train_files import shipped_trains
from atcs.properties.configured import (
    compensated_gradients,
    configuration_gaps,
    configuration_properties,
    gradient_transitions,
)

REFERENCE = Path(__file__).parents[2] / "docs" / "configuration.md"
SHIPPED = Path(__file__).parents[2] / "model" / "configurations"

CONFIG = f"""
name = "test"

[national]
preset = "subset026"

[atp]
cycle_s = 0.1

[[trains]]
file = "{shipped_trains()["gamma_passenger_P"]}"

[[trains]]
preset = "seed000"

[[lines]]
name = "short"
length_m = 3000
speed_limits = [{{ start_m = 0, kmh = 100 }}, {{ start_m = 1500, kmh = 60 }}]
gradients = [{{ start_m = 0, permille = 0 }}, {{ start_m = 800, permille = -10 }}, {{ start_m = 1600, permille = 5 }}]
"""


def _documented() -> dict[str, set[str]]:
    tables, current = {}, None
    for line in REFERENCE.read_text(encoding="utf-8").splitlines():
        if line.startswith("## "):
            current = ("",) if line == "## Top level" else tuple(re.findall(r"`\[\[?([\w.]+)\]?\]`", line))
            tables.update({name: set() for name in current})
        elif current and line.startswith("| `"):
            key = line.split("|")[1].strip()
            found = set(re.findall(r"\[(\w+)\]", key)) if key.startswith("`[") else set(re.findall(r"`(\w+)`", key))
            for name in current:
                tables[name] |= found
    return tables


def test_the_loader_accepts_exactly_the_documented_keys():
    assert _documented() == {table: set(keys) for table, keys in FIELDS.items()}


@pytest.mark.parametrize("path", sorted(SHIPPED.glob("*.toml")), ids=lambda p: p.name)
def test_the_shipped_configurations_load(path):
    config = load_configuration(path)
    assert configuration_properties(config)


def _write(tmp_path, text=CONFIG) -> Path:
    path = tmp_path / "c.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_a_configuration_reads_its_trains_lines_and_cycle(tmp_path):
    config = load_configuration(_write(tmp_path))
    assert [t.name for t in config.trains] == ["gamma_passenger_P", "seed000"]
    assert config.trains[0].rail is not None and config.trains[1].rail is None
    line = config.lines[0]
    assert line.speed_limits.values == (Fraction(100) / Fraction(36, 10), Fraction(60) / Fraction(36, 10))
    assert line.gradients == Profile((0, 800, 1600), (0, -10, 5), 3000)
    assert config.cycle_s == Fraction(1, 10)


def test_a_train_file_is_found_beside_the_configuration(tmp_path):
    (tmp_path / "trains").mkdir()
    (tmp_path / "trains" / "g.toml").write_text(shipped_trains()["gamma_passenger_P"].read_text(), encoding="utf-8")
    config = load_configuration(
        _write(tmp_path, CONFIG.replace(str(shipped_trains()["gamma_passenger_P"]), "trains/g.toml"))
    )
    assert config.trains[0].name == "gamma_passenger_P"


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("cycle_s = 0.1", "cycle_s = 2", "atp.cycle_s = 2 is above 1 s"),
        ("cycle_s = 0.1", "cycle_s = 0", "atp.cycle_s = 0 must be positive"),
        ("cycle_s = 0.1", "cycle = 0.1", "atp.cycle: unknown field"),
        ('preset = "subset026"', 'preset = "uk"', "national.preset = 'uk' must be one of subset026, seed002"),
        ('preset = "subset026"', "t_driver_s = -1", "national.t_driver_s = -1 must be at least 0"),
        ('preset = "subset026"', 'inhibit_speed_inaccuracy = "yes"', "national.inhibit_speed_inaccuracy = 'yes' must"),
        ('preset = "seed000"', 'preset = "seed001"', "trains[1].preset = 'seed001' must be one of seed000, seed002"),
        ('preset = "seed000"', 'preset = "seed000"\nfile = "x.toml"', "trains[1]: give exactly one of file"),
        ('preset = "seed000"', 'file = "missing.toml"', "trains[1].file: "),
        ('preset = "seed000"', 'preset = "seed000"\n[[trains]]\npreset = "seed000"', "trains[2] is named 'seed000'"),
        ("length_m = 3000", "length_m = 2e6", "lines[0].length_m = 2000000.0 is above 1000000 m"),
        ("kmh = 60", "kmh = 700", "lines[0].speed_limits[1].kmh = 700 is outside (0, 600]"),
        ("kmh = 60", "kmh = 0", "lines[0].speed_limits[1].kmh = 0 is outside (0, 600]"),
        ("permille = 5", "permille = 45", "lines[0].gradients[2].permille = 45 is outside [-40, 40]"),
        ("start_m = 1600", "start_m = 3000", "lines[0].gradients[2].start_m = 3000 must be before the line's end"),
        ("start_m = 1600", "start_m = 700", "lines[0].gradients[2].start_m = 700 must be after the previous"),
        ("{ start_m = 0, kmh = 100 }, ", "{ start_m = 10, kmh = 100 }, ", "speed_limits[0].start_m = 10 must be 0"),
        ("speed_limits = [", "speed_limits = [] #", "lines[0].speed_limits = [] must be a list of at least one"),
        ('name = "short"', 'name = "short"\nswitches = []', "lines[0].switches: unknown field"),
        ('name = "short"', 'name = "short"\ntag_spacing_m = 0', "lines[0].tag_spacing_m = 0 must be positive"),
        ('name = "short"', 'name = "short"\nresource_length_m = 4000', "resource_length_m = 4000 must not exceed"),
        ('name = "short"', 'name = "short"\nplatforms = 3', "lines[0].platforms must be a table, got 3"),
        (
            'name = "short"',
            'name = "short"\nplatforms = { table = [{ start_m = 2900, length_m = 200, side = "left" }] }',
            "lines[0].platforms: platform 1 ends at 3100 m, past the line's end (3000 m)",
        ),
        (
            'name = "short"',
            'name = "short"\nstations = [{ stop_m = 500, dwell_s = 30 }]',
            "lines[0].stations[0].stop_m = 500: no platform of lines[0].platforms spans it",
        ),
        (
            'name = "short"',
            'name = "short"\nstations = [{ stop_m = 5000, dwell_s = 30 }]',
            "lines[0].stations[0].stop_m = 5000 must be on the line (3000 m)",
        ),
    ],
)
def test_bad_configurations_are_named(tmp_path, old, new, message):
    text = CONFIG.replace(old, new, 1)
    assert text != CONFIG
    with pytest.raises(ConfigurationError, match=re.escape(message)) as caught:
        load_configuration(_write(tmp_path, text))
    assert str(tmp_path / "c.toml") in str(caught.value)


def test_a_configuration_without_trains_or_lines_is_refused(tmp_path):
    with pytest.raises(ConfigurationError, match=r"trains = None must list at least one train"):
        load_configuration(_write(tmp_path, 'name = "x"\n[[lines]]\nname = "l"\nlength_m = 1\n'))


def test_a_train_data_file_error_names_both_files(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(shipped_trains()["gamma_passenger_P"].read_text().replace("length_m = 600", "length_m = 0"))
    with pytest.raises(ConfigurationError) as caught:
        load_configuration(_write(tmp_path, CONFIG.replace(str(shipped_trains()["gamma_passenger_P"]), str(bad))))
    assert str(tmp_path / "c.toml") in str(caught.value) and "bad.toml: length_m = 0 is outside" in str(caught.value)


# --- what is proved for a configuration ---------------------------------------------------------------------------


def test_the_compensated_profile_is_well_formed_and_keeps_the_value_behind_the_start(tmp_path):
    line = load_configuration(_write(tmp_path)).lines[0]
    assert compensated_gradients(line, Fraction(600)) == Profile((0, 800, 2200), (0, -10, 5), 3000)
    downhill_first = type(line)("d", Fraction(3000), line.speed_limits, Profile((0, 1000), (Fraction(20), 0), 3000))
    # behind the start a braking walk takes the first value (20), on the line the lowest under the train
    assert compensated_gradients(downhill_first, Fraction(600)).values[0] == 20


def test_each_transition_is_proved_once(tmp_path):
    profile = Profile((0, 1, 2, 3), (0, 5, 0, 5), 4)
    assert gradient_transitions(profile) == ((0, 5), (5, 0))
    assert gradient_transitions(Profile((0,), (7,), 4)) == ((7, 7),)


def test_the_closed_loop_runs_on_whole_cycles(tmp_path):
    config = load_configuration(_write(tmp_path))
    gamma = whole_cycle_train(config.trains[0].train, Fraction(1, 10))
    assert gamma.t_traction_s == Fraction(1, 10)  # T_traction 0: one cycle
    odd = whole_cycle_train(dataclasses.replace(gamma, t_be_s=Fraction("2.53")), Fraction(1, 10))
    assert odd.t_be_s == Fraction(26, 10)


def test_properties_for_each_train_line_and_transition(tmp_path):
    config = load_configuration(_write(tmp_path))
    names = [p.name for p in configuration_properties(config)]
    curves = [n for n in names if n.startswith("curves.")]
    assert len(curves) == 2 * (2 * (6 + 4) + 1)  # each train: two transitions (curves, tables), the whole line
    windows = {n.rsplit("_w", 1)[1] for n in names if n.startswith("closed_loop.no_overrun_gamma")}
    profile = compensated_gradients(config.lines[0], config.trains[0].train.train_length_m)
    ends = (*profile.starts_m[1:], profile.end_m)
    stretches = sum(math.ceil((end - start) / 800) for start, end in zip(profile.starts_m, ends, strict=True))
    assert windows == {str(k) for k in range(stretches)}  # per segment, one per stretch of at most 800 m
    assert len(names) == len(set(names))
    assert "closed_loop.no_overrun_gamma_passenger_p_short_w1" in names
    assert "curves.ebd_is_braking_curve_seed000_short_whole" in names
    assert configuration_gaps(config) == ()


def test_a_multi_step_emergency_brake_is_not_covered_by_the_closed_loop(tmp_path):
    text = CONFIG.replace(str(shipped_trains()["gamma_passenger_P"]), str(shipped_trains()["lambda_passenger_P_100"]))
    config = load_configuration(_write(tmp_path, text))
    (gap,) = configuration_gaps(config)
    assert gap.startswith("lambda_passenger_P_100: the closed-loop theorems (CL-00 to CL-06) are not made")
    assert not any(p.name.startswith("closed_loop.") and "lambda" in p.name for p in configuration_properties(config))


def test_a_lines_platforms_and_stations_are_read(tmp_path):
    text = CONFIG.replace(
        'name = "short"',
        'name = "short"\ntag_spacing_m = 100\nresource_length_m = 500\n'
        'platforms = { table = [{ start_m = 1000, length_m = 250, side = "both", height_mm = 760 }] }\n'
        'stations = [{ name = "A", stop_m = 1200, dwell_s = 30 }]',
    )
    line = load_configuration(_write(tmp_path, text)).lines[0]
    assert (line.tag_spacing_m, line.resource_length_m) == (100, 500)
    assert [(p.start_m, p.end_m, p.side, p.height_mm) for p in line.platforms] == [(1000, 1250, "both", 760)]
    assert [(s.name, s.stop_m, s.dwell_s) for s in line.stations] == [("A", 1200, 30)]
