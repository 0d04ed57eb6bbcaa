"""Train data files (docs/train-data.md): the loader accepts exactly the documented keys, the shipped trains are
the ERA frames' trains (so every row of the frames holds with them), and every bad value is refused naming the
file, the field and the value."""

import dataclasses
import re
from fractions import Fraction
from pathlib import Path

import pytest

from atcs.model.braking_data import curve_train_data, with_special_brakes
from atcs.model.train_data import TrainDataError, subset026_national
from atcs.model.train_files import FIELDS, load_train, shipped_trains
from atcs.proofs.cli import main
from atcs.proofs.conformance.check import check_frame
from atcs.proofs.conformance.frames import load_frame, shipped_frames

REFERENCE = Path(__file__).parents[2] / "docs" / "train-data.md"


def _documented() -> dict[str, set[str]]:
    """The keys of each table the reference documents (its tables' first column)."""
    tables, current = {}, None
    for line in REFERENCE.read_text(encoding="utf-8").splitlines():
        heading = re.match(r"## (?:`\[\[?([\w.]+)\]?\]`|Top level)", line)
        if heading:
            current = heading.group(1) or ""
            tables[current] = set()
        elif current is not None and line.startswith("| `"):
            key = line.split("|")[1].strip().strip("`")
            if key.startswith("["):  # a table row: `[interfaces]`, `[gamma]` or `[lambda]`, `[[combination]]`
                tables[current] |= set(re.findall(r"\[(\w+)\]", key))
            else:  # one key, or several: `emergency`, `kdry_rst`, `kwet_rst`
                tables[current] |= {k.strip().strip("`") for k in key.split(",")}
    return tables


def test_the_loader_accepts_exactly_the_documented_keys():
    assert _documented() == {table: set(keys) for table, keys in FIELDS.items()}


@pytest.mark.parametrize("name", ["gamma_passenger_P", "lambda_passenger_P_100"])
def test_the_shipped_trains_are_the_frames_trains(name):
    frame = load_frame(dict((p.stem, p) for p in shipped_frames())[name])
    train = load_train(shipped_trains()[name])
    national = subset026_national()
    assert curve_train_data(train, national, 0) == curve_train_data(frame.train, national, 0)
    results = check_frame(dataclasses.replace(frame, train=train))
    assert all(r.agrees for r in results)


LAMBDA = shipped_trains()["lambda_passenger_P_100"].read_text(encoding="utf-8")
GAMMA = shipped_trains()["gamma_passenger_P"].read_text(encoding="utf-8")


@pytest.mark.parametrize(
    ("text", "old", "new", "message"),
    [
        (LAMBDA, "brake_percentage = 100", "brake_percentage = 260", "brake_percentage = 260 is outside [30, 250]"),
        (LAMBDA, "length_m = 700", "length_m = 950", "length_m = 950 is above 900 for passenger_P"),
        (LAMBDA, "length_m = 700", "length_m = 0", "length_m = 0 is outside (0, 4095]"),
        (LAMBDA, "length_m = 700", 'length_m = "1e5000"', "length_m"),
        (LAMBDA, 'brake_position = "passenger_P"', 'brake_position = "P"', "brake_position = 'P' must be one of"),
        (LAMBDA, "[lambda]", "[lamda]", "lamda: unknown field"),
        (LAMBDA, "service_brake_command = false", "service_brake_command = 1", "must be true or false"),
        (GAMMA, "t_brake_service_s = 2.5", "t_brake_service_s = 130", "gamma.t_brake_service_s = 130 is outside"),
        (GAMMA, "emergency = [{ from_kmh = 0, mps2 = 1.0 }]", "emergency = [{ from_kmh = 5, mps2 = 1.0 }]", "start"),
        (GAMMA, "emergency = [{ from_kmh = 0, mps2 = 1.0 }]", "emergency = [{ from_kmh = 0, mps2 = 0 }]", "mps2 = 0"),
        (GAMMA, "kwet_rst = [{ from_kmh = 0, value = 1.0 }]", "kwet_rst = [{ from_kmh = 0, value = 1.5 }]", "1.5"),
        (GAMMA, "[gamma]", "[lambda]\nbrake_percentage = 100\n[gamma]", "exactly one of [gamma]"),
    ],
)
def test_bad_train_data_is_named(tmp_path, text, old, new, message):
    assert old in text
    path = tmp_path / "train.toml"
    path.write_text(text.replace(old, new, 1), encoding="utf-8")
    with pytest.raises(TrainDataError) as caught:
        load_train(path)
    assert str(caught.value).startswith(str(path)) and message in str(caught.value), caught.value


def test_freight_build_up_times_are_accepted(tmp_path):
    """A freight train in G has a T_bs of 22.4 s and more (the conversion model gives up to 64.7 s)."""
    path = tmp_path / "freight.toml"
    path.write_text(GAMMA.replace("t_brake_service_s = 2.5", "t_brake_service_s = 22.4"), encoding="utf-8")
    assert load_train(path).brakes.t_brake_service_s == pytest.approx(22.4)


def test_curves_draws_a_lambda_train_from_its_file(tmp_path, capsys):
    train = shipped_trains()["lambda_passenger_P_100"]
    argv = ["curves", "--train", str(train), "--eoa", "3000", "--mrsp", "0:160", "--gradient", "0:0"]
    assert main([*argv, "--eoa-speed", "30", "--speed", "120", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert (tmp_path / "curves.png").exists() and "3000 @ 30" in out


def test_curves_refuses_a_train_that_is_neither_preset_nor_file(capsys):
    assert main(["curves", "--train", "seed001"]) == 2
    assert "--train = 'seed001' is neither a preset (seed000, seed002) nor a .toml file" in capsys.readouterr().err


# --- special brakes: the brake models of each combination of active special brakes (§3.13.2.2.6) ---

REGENERATIVE = """
[[gamma.combination]]
active = ["regenerative"]
service = [{ from_kmh = 0, mps2 = 1.2 }]
t_brake_service_s = 1.5

[[gamma.combination]]
active = ["regenerative", "magnetic_shoe"]
emergency = [{ from_kmh = 0, mps2 = 1.3 }]
t_brake_emergency_s = 2.0
"""


def _with_combinations(tmp_path, extra=REGENERATIVE) -> Path:
    path = tmp_path / "special.toml"
    path.write_text(GAMMA + extra, encoding="utf-8")
    return path


def test_a_combination_selects_its_models_and_keeps_the_others(tmp_path):
    train = load_train(_with_combinations(tmp_path))
    assert with_special_brakes(train, []) is train
    regenerative = with_special_brakes(train, ["regenerative"]).brakes
    assert regenerative.service_mps2.values == (Fraction(6, 5),) and regenerative.t_brake_service_s == Fraction(3, 2)
    assert regenerative.emergency_mps2 == train.brakes.emergency_mps2
    assert regenerative.t_brake_emergency_s == train.brakes.t_brake_emergency_s
    both = with_special_brakes(train, ["magnetic_shoe", "regenerative"]).brakes
    assert both.emergency_mps2.values == (Fraction(13, 10),) and both.service_mps2 == train.brakes.service_mps2


def test_the_selected_models_move_the_curves(tmp_path):
    train, national = load_train(_with_combinations(tmp_path)), subset026_national()
    base = curve_train_data(train, national, 0)
    stronger = curve_train_data(with_special_brakes(train, ["regenerative", "magnetic_shoe"]), national, 0)
    assert stronger.emergency_decelerations_mps2 == (Fraction(13, 10),) and stronger.t_be_s == 2
    assert base.emergency_decelerations_mps2 == (Fraction(1),) and base.t_be_s == Fraction(5, 2)


@pytest.mark.parametrize(
    ("active", "message"),
    [
        (["eddy_current"], "no brake models for the special brakes eddy_current active (combinations declared: "),
        (["rheostatic"], "special brake 'rheostatic' is not one of regenerative, eddy_current, magnetic_shoe, ep"),
    ],
)
def test_an_undeclared_combination_is_refused(tmp_path, active, message):
    with pytest.raises(TrainDataError, match=re.escape(message)):
        with_special_brakes(load_train(_with_combinations(tmp_path)), active)


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (
            '[[gamma.combination]]\nactive = ["ep"]\nservice = [{ from_kmh = 0, mps2 = 1.2 }]\n',
            "gamma.combination[0].service = [{'from_kmh': 0, 'mps2': 1.2}] does not depend on ep (Subset-026 "
            "§3.13.2.2.6.2 Table 4)",
        ),
        ('[[gamma.combination]]\nactive = ["turbo"]\n', "gamma.combination[0].active = ['turbo'] must list distinct"),
        ("[[gamma.combination]]\nactive = []\n", "gamma.combination[0].active = [] must list distinct"),
        (
            '[[gamma.combination]]\nactive = ["ep"]\n[[gamma.combination]]\nactive = ["ep"]\n',
            "gamma.combination[1].active = ['ep'] repeats an earlier combination",
        ),
        ('[[gamma.combination]]\nactive = ["ep"]\nt_brake_service_s = 0\n', "t_brake_service_s = 0 is outside"),
        ('[[gamma.combination]]\nactive = ["ep"]\nspeed = 1\n', "gamma.combination[0].speed: unknown field"),
    ],
)
def test_a_bad_combination_is_named(tmp_path, extra, message):
    with pytest.raises(TrainDataError, match=re.escape(message)):
        load_train(_with_combinations(tmp_path, extra))


def test_curves_takes_the_special_brakes_active(tmp_path, capsys):
    train = _with_combinations(tmp_path)
    argv = ["curves", "--train", str(train), "--eoa", "3000", "--mrsp", "0:160", "--gradient", "0:0"]
    assert main([*argv, "--special-brakes", "regenerative", "--speed", "100", "--out", str(tmp_path)]) == 0
    assert main([*argv, "--special-brakes", "eddy_current", "--out", str(tmp_path)]) == 2
    assert "--special-brakes: gamma_passenger_P: no brake models for" in capsys.readouterr().err
    assert main(["curves", "--special-brakes", "ep"]) == 2
    assert "--special-brakes needs a train data file, not the preset 'seed000'" in capsys.readouterr().err


def test_a_gamma_train_may_be_longer_than_the_conversion_model_allows(tmp_path):
    """L_TRAIN ranges to 4,095 m (Appendix A.3.11); only a Lambda train is held to the conversion model's 1,500 m."""
    path = tmp_path / "long.toml"
    path.write_text(GAMMA.replace("length_m = 600", "length_m = 2000"), encoding="utf-8")
    assert load_train(path).length_m == 2000
    path.write_text(
        LAMBDA.replace('brake_position = "passenger_P"', 'brake_position = "freight_P"').replace(
            "length_m = 700", "length_m = 2000"
        ),
        encoding="utf-8",
    )
    with pytest.raises(TrainDataError, match="length_m = 2000 is above 1500 for freight_P"):
        load_train(path)


def test_a_lambda_train_takes_the_national_kv_int(tmp_path):
    """Kv_int per speed step, a and b for a passenger train interpolated by A_ebmax between the pivots."""
    path = tmp_path / "kv.toml"
    kv = "kv_int = [{ from_kmh = 0, a = 0.9, b = 0.8 }, { from_kmh = 100, a = 0.8, b = 0.7 }]\n"
    path.write_text(LAMBDA.replace("[lambda]\n", "[lambda]\n" + kv), encoding="utf-8")
    factors = load_train(path).brakes.factors
    assert factors.kv_int_a.values == (Fraction(9, 10), Fraction(4, 5)) and factors.kv_int_b.speeds_kmh == (0, 100)
    national = subset026_national()
    neutral = curve_train_data(load_train(shipped_trains()["lambda_passenger_P_100"]), national, 0)
    corrected = curve_train_data(load_train(path), national, 0)

    def at(data, speed_mps):
        steps = zip(data.emergency_speeds_mps, data.emergency_decelerations_mps2, strict=True)
        return [a for s, a in steps if s <= speed_mps][-1]

    assert all(at(corrected, v) < at(neutral, v) for v in corrected.emergency_speeds_mps)


@pytest.mark.parametrize(
    ("kv", "message"),
    [
        ("kv_int = [{ from_kmh = 0, a = 0.9 }]\n", "lambda.kv_int[0].b is missing"),
        ("kv_int = [{ from_kmh = 0, a = 1.2, b = 0.8 }]\n", "lambda.kv_int[0].a = 1.2 is outside (0, 1]"),
        ("kv_int = [{ from_kmh = 10, a = 0.9, b = 0.8 }]\n", "must start at from_kmh = 0"),
        ("a_nvp12_mps2 = 1.4\n", "lambda.a_nvp12_mps2 = 1.4 must be below a_nvp23_mps2 = 1.3"),
        ("a_nvp23_mps2 = 0.5\n", "lambda.a_nvp23_mps2 = 0.5 must be above a_nvp12_mps2 = 1"),
    ],
)
def test_bad_kv_int_is_named(tmp_path, kv, message):
    path = tmp_path / "kv.toml"
    path.write_text(LAMBDA.replace("[lambda]\n", "[lambda]\n" + kv), encoding="utf-8")
    with pytest.raises(TrainDataError, match=re.escape(message)):
        load_train(path)
