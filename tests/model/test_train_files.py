"""Train data files (docs/train-data.md): the loader accepts exactly the documented keys, the shipped trains are
the ERA frames' trains (so every row of the frames holds with them), and every bad value is refused naming the
file, the field and the value."""

import dataclasses
import re
from fractions import Fraction
from pathlib import Path

import pytest

from atcs.model.braking_data import curve_train_data, guidance_data, with_special_brakes
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
        if line.startswith("## "):  # `[gamma]`, `[[gamma.combination]]`, `[normal_service.p]` and `[...g]`
            current = ("",) if line == "## Top level" else tuple(re.findall(r"`\[\[?([\w.]+)\]?\]`", line))
            tables.update({name: set() for name in current})
        elif current and line.startswith("| `"):
            key = line.split("|")[1].strip().strip("`")
            if key.startswith("["):  # a table row: `[interfaces]`, `[gamma]` or `[lambda]`, `[[combination]]`
                found = set(re.findall(r"\[(\w+)\]", key))
            else:  # one key, or several: `emergency`, `kdry_rst`, `kwet_rst`
                found = {k.strip().strip("`") for k in key.split(",")}
            for name in current:
                tables[name] |= found
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


# --- the normal service brake of the guidance curve ------------------------------------------------------------

NORMAL_SERVICE = """
[normal_service]
a_sb01_mps2 = 0.5
a_sb12_mps2 = 0.9
kn_plus = [{ from_kmh = 0, mps2 = 3 }]
kn_minus = [{ from_kmh = 0, mps2 = 5 }, { from_kmh = 100, mps2 = 4 }]

[normal_service.p]
model_0 = [{ from_kmh = 0, mps2 = 0.4 }]
model_1 = [{ from_kmh = 0, mps2 = 0.6 }, { from_kmh = 60, mps2 = 0.5 }]
model_2 = [{ from_kmh = 0, mps2 = 0.7 }]
"""


def _guided(tmp_path, service_mps2="1.0", extra=NORMAL_SERVICE, position="passenger_P") -> Path:
    path = tmp_path / "guided.toml"
    text = GAMMA.replace(
        "service = [{ from_kmh = 0, mps2 = 1.0 }]", f"service = [{{ from_kmh = 0, mps2 = {service_mps2} }}]"
    )
    path.write_text(text.replace('"passenger_P"', f'"{position}"') + extra, encoding="utf-8")
    return path


@pytest.mark.parametrize(("service_mps2", "model"), [("0.5", 0), ("0.51", 1), ("0.9", 1), ("1.0", 2)])
def test_a_brake_service_at_standstill_selects_the_model(tmp_path, service_mps2, model):
    """§3.13.2.2.3.1.10: model 0 up to A_SB01 (included), 1 up to A_SB12 (included), 2 above."""
    guidance = guidance_data(load_train(_guided(tmp_path, service_mps2)))
    first = {0: Fraction(2, 5), 1: Fraction(3, 5), 2: Fraction(7, 10)}[model]
    assert guidance.normal_service_decelerations_mps2[0] == first


def test_the_guidance_steps_are_the_union_of_the_models_and_the_kn_steps(tmp_path):
    guidance = guidance_data(load_train(_guided(tmp_path, "0.8")))
    assert guidance.normal_service_speeds_mps == (0, Fraction(60) / Fraction(36, 10), Fraction(100) / Fraction(36, 10))
    assert guidance.normal_service_decelerations_mps2 == (Fraction(3, 5), Fraction(1, 2), Fraction(1, 2))
    assert guidance.kn_plus_mps2 == (3, 3, 3) and guidance.kn_minus_mps2 == (5, 5, 4)


def test_a_train_without_a_normal_service_brake_has_no_guidance_curve():
    assert guidance_data(load_train(shipped_trains()["gamma_passenger_P"])) is None


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("a_sb12_mps2 = 0.9", "a_sb12_mps2 = 0.5", "normal_service.a_sb12_mps2 = 0.5 must be above a_sb01_mps2 = 0.5"),
        ("kn_plus = [{ from_kmh = 0, mps2 = 3 }]", "kn_plus = [{ from_kmh = 0, mps2 = 11 }]", "kn_plus[0].mps2 = 11"),
        ("model_2 = [{ from_kmh = 0, mps2 = 0.7 }]", "", "normal_service.p.model_2 = None must be a list of 1 to 7"),
        ("[normal_service.p]", "[normal_service.g]", "normal_service.p = None is missing: brake_position"),
        ("a_sb01_mps2 = 0.5", "a_sb01 = 0.5", "normal_service.a_sb01: unknown field"),
        (
            "kn_plus = [{ from_kmh = 0, mps2 = 3 }]",
            "kn_plus = [" + ", ".join(f"{{ from_kmh = {v}, mps2 = 1 }}" for v in range(0, 60, 10)) + "]",
            "must be a list of 1 to 5 steps",
        ),
    ],
)
def test_a_bad_normal_service_brake_is_named(tmp_path, old, new, message):
    with pytest.raises(TrainDataError, match=re.escape(message)):
        load_train(_guided(tmp_path, extra=NORMAL_SERVICE.replace(old, new)))


def test_kn_may_be_zero(tmp_path):
    extra = NORMAL_SERVICE.replace("mps2 = 3 }]", "mps2 = 0 }]")
    assert guidance_data(load_train(_guided(tmp_path, extra=extra))).kn_plus_mps2[0] == 0


def test_a_freight_train_in_g_takes_the_g_set(tmp_path):
    extra = (
        NORMAL_SERVICE
        + "\n[normal_service.g]\n"
        + "\n".join(f"model_{m} = [{{ from_kmh = 0, mps2 = 0.{m + 2} }}]" for m in range(3))
    )
    guidance = guidance_data(load_train(_guided(tmp_path, "0.8", extra=extra, position="freight_G")))
    assert guidance.normal_service_decelerations_mps2 == (Fraction(3, 10),) * 2  # steps 0 and 100 km/h (Kn-)


def test_curves_prints_the_guidance_curve(tmp_path, capsys):
    argv = ["curves", "--train", str(_guided(tmp_path, "0.8")), "--eoa", "1500", "--mrsp", "0:160"]
    assert main([*argv, "--gradient", "0:0,500:-10,1100:5", "--speed", "80", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "permitted with GUI" in out and "1069.76" in out  # worked by hand: 0.6 then 0.5 m/s^2, Kn on +5 and -10


def test_a_normal_service_brake_that_cannot_stop_is_refused(tmp_path, capsys):
    extra = NORMAL_SERVICE.replace("model_1 = [{ from_kmh = 0, mps2 = 0.6 }", "model_1 = [{ from_kmh = 0, mps2 = 0.1 }")
    argv = [
        "curves",
        "--train",
        str(_guided(tmp_path, "0.8", extra=extra)),
        "--gradient",
        "0:-40",
        "--out",
        str(tmp_path),
    ]
    assert main(argv) == 2
    assert (
        "normal_service[0] = 0.1 gives A_normal_service = -0.085 m/s^2 on gradient_permille[0] = -40"
        in capsys.readouterr().err
    )
