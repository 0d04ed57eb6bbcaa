"""The braking curves against the ERA braking-curves tool's reference frames (docs/conformance.md): every row of
both shipped frames within its tolerance, the conversion model's outputs as the Lambda frame checks them, frames
that cannot be read refused naming the field, and a harness that fails when the model is wrong."""

import dataclasses
import json
import re
from fractions import Fraction

import pytest

from atcs.model import braking_data
from atcs.model.braking_data import conversion_model
from atcs.model.curves import Target, ebd_location_m, ebd_reference_location_m
from atcs.model.ops.exact import EXACT
from atcs.model.profile import Profile
from atcs.model.train_data import TrainDataError, seed000_train, subset026_national
from atcs.proofs.cli import main
from atcs.proofs.conformance.check import check_frame, check_inputs, worst_by_curve
from atcs.proofs.conformance.frames import FrameError, load_frame, shipped_frames
from atcs.proofs.mutation.mutants import patched

FRAMES = {path.stem: path for path in shipped_frames()}


@pytest.mark.parametrize("name", sorted(FRAMES))
def test_every_row_of_the_shipped_frames_is_within_its_tolerance(name):
    results = check_frame(load_frame(FRAMES[name]))
    outside = [(r.row.curve, float(r.row.speed_kmh), float(r.row.expected), float(r.computed)) for r in results]
    outside = [o for o, r in zip(outside, results, strict=True) if not r.agrees]
    assert not outside, outside
    below_foot = [r for r in results if r.row.curve == "EBD" and r.row.speed_kmh < Fraction("7.5")]
    assert len(below_foot) == 2  # 0 and 5 km/h: the EBD beyond the target, compared too
    assert set(worst_by_curve(results)) >= {"EBD", "EBI", "SBI2", "Warning", "Permitted", "Indication"}


def test_the_conversion_model_gives_what_the_lambda_frame_checks():
    inputs = check_inputs(load_frame(FRAMES["lambda_passenger_P_100"]))
    assert len(inputs) == 22 and all(i.agrees for i in inputs), [i for i in inputs if not i.agrees]
    converted = conversion_model(100, "passenger_P", 700, 180)
    assert (converted.t_brake_emergency_cm0_s, converted.t_brake_service_cm0_s) == (Fraction("10.63"), Fraction("18.4"))
    assert converted.kto == Fraction("1.2")
    assert converted.emergency_mps2.values == tuple(map(Fraction, ("0.826", "0.6171", "0.5915", "0.58173")))


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        ((29, "passenger_P", 700, 180), "brake_percentage = 29 is outside [30, 250]"),
        ((251, "passenger_P", 700, 180), "brake_percentage = 251 is outside [30, 250]"),
        ((100, "passenger_P", 901, 180), "length_m = 901 is above 900 for passenger_P"),
        ((100, "freight_G", 1501, 100), "length_m = 1501 is above 1500 for freight_G"),
        ((100, "passenger_P", 700, 201), "max_speed_kmh = 201 is above 200"),
        ((100, "freight", 700, 100), "brake_position = 'freight' is not one of"),
    ],
)
def test_the_conversion_model_is_refused_outside_its_validity_limits(arguments, message):
    with pytest.raises(TrainDataError, match=re.escape(message)):
        conversion_model(*arguments)


def test_below_its_foot_the_reference_ebd_continues_beyond_the_target():
    t, n = seed000_train(), subset026_national()
    level = Profile((Fraction(0),), (Fraction(0),), Fraction(5000))
    foot = Fraction(5)
    target = Target(Fraction(1000), Fraction(3), foot)
    assert ebd_reference_location_m(EXACT, t, n, level, target, foot) == 1000
    beyond = ebd_reference_location_m(EXACT, t, n, level, target, Fraction(0))
    a = t.kdry_rst * t.kwet_rst * t.emergency_decelerations_mps2[0]  # M_NVAVADH = 0
    assert beyond == 1000 + foot * foot / (2 * a)
    assert ebd_location_m(EXACT, t, n, level, target, Fraction(0)) > 1_000_000  # supervision: never constrains
    assert ebd_reference_location_m(EXACT, t, n, level, target, Fraction(20)) == ebd_location_m(
        EXACT, t, n, level, target, Fraction(20)
    )


def test_the_harness_fails_when_the_model_is_wrong():
    """T_indication as a fixed 2 s national value (atcs before the rule of §3.13.9.3.6.2): the indication rows
    of both frames are out."""
    with patched(braking_data.t_indication_s, "max(Fraction(4, 5) * t_bs_s, T_INDICATION_MIN_S)", "Fraction(2)"):
        for path in FRAMES.values():
            results = check_frame(load_frame(path))
            out = {r.row.curve for r in results if not r.agrees}
            assert out == {"Indication"}, out


def test_the_command_prints_a_table_per_frame_and_exits_0(capsys):
    assert main(["conformance"]) == 0
    out = capsys.readouterr().out
    assert "gamma_passenger_P.json" in out and "lambda_passenger_P_100.json" in out and "22 of 22" in out


def test_a_row_outside_its_tolerance_exits_1_and_is_listed(tmp_path, capsys):
    doc = json.loads(FRAMES["gamma_passenger_P"].read_text(encoding="utf-8"))
    doc["expected"]["EBD"][5]["expected_value"] += 1
    path = tmp_path / "edited.json"
    path.write_text(json.dumps(doc), encoding="utf-8")
    assert main(["conformance", str(path)]) == 1
    assert "OUT EBD at 25 km/h: expected 23.37" in capsys.readouterr().out


def _edited(tmp_path, edit) -> str:
    doc = json.loads(FRAMES["gamma_passenger_P"].read_text(encoding="utf-8"))
    edit(doc)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(doc), encoding="utf-8")
    return str(path)


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda d: d["inputs"]["train_data"].pop("train_length_m"), "inputs.train_data.train_length_m is missing"),
        (
            lambda d: d["inputs"]["train_data"].update(train_length_m="long"),
            "inputs.train_data.train_length_m = 'long' is not a finite number",
        ),
        (
            lambda d: d["inputs"]["train_data"].update(train_length_m=1e300),
            "inputs.train_data.train_length_m = 1e+300 is larger than 1e+07",
        ),
        (
            lambda d: d["expected"]["EBD"][3].update(speed_kmh=None),
            "expected.EBD[3].speed_kmh = None is not a finite number",
        ),
        (
            lambda d: d["inputs"]["train_data"].update(brake_position="G"),
            "inputs.train_data.brake_position = 'G' is not one of",
        ),
        (
            lambda d: d["inputs"]["track_data"]["gradients"][1].update(location_m=0),
            "inputs.track_data.gradients[*].location_m = [0.0, 0.0, 6000.0, 6500.0] must start at 0 and increase",
        ),
    ],
)
def test_a_frame_that_cannot_be_read_is_one_line_naming_the_field(tmp_path, capsys, edit, message):
    path = _edited(tmp_path, edit)
    assert main(["conformance", path]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"atcs: error: conformance: {path}: ") and message in err and "\n" not in err, err


@pytest.mark.parametrize(
    ("name", "edit", "message"),
    [
        (
            "lambda_passenger_P_100",
            lambda d: d["inputs"]["brake_parameters"].update(brake_percentage_lambda_percent=300),
            "brake_percentage = 300 is outside [30, 250]",
        ),
        (
            "gamma_passenger_P",
            lambda d: d["inputs"]["brake_parameters"]["emergency_brake_models"]["EddyCurrent_Magnetic_Regenerative"][
                "model_values"
            ][0].update(Acceleration=-1),
            "emergency_decelerations_mps2[0] = Fraction(-1, 1) is outside (0, 5] m/s^2",
        ),
    ],
)
def test_train_data_the_curves_cannot_use_is_refused_naming_the_frame(tmp_path, capsys, name, edit, message):
    doc = json.loads(FRAMES[name].read_text(encoding="utf-8"))
    edit(doc)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(doc), encoding="utf-8")
    assert main(["conformance", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"atcs: error: conformance: {path}: ") and message in err, err


@pytest.mark.parametrize(
    ("content", "reason"),
    [
        (b"\xff\xfe not utf-8", "the frame is not UTF-8 text"),
        (b"{not json", "the frame is not JSON"),
        (b"", "the frame is not JSON"),
    ],
)
def test_a_file_that_is_not_a_json_frame_is_refused(tmp_path, content, reason):
    path = tmp_path / "frame.json"
    path.write_bytes(content)
    with pytest.raises(FrameError, match=reason):
        load_frame(path)
    with pytest.raises(FrameError, match="cannot read the frame: No such file"):
        load_frame(tmp_path / "missing.json")


def _train(**changes):
    frame = load_frame(FRAMES["gamma_passenger_P"])
    return dataclasses.replace(frame.train, **changes), frame.national


def test_the_interfaces_set_t_bs2_t_traction_and_t_indication():
    """§3.13.9.3: T_bs2 is T_bs with a service-brake command, else 0; with a traction cut-off command T_traction
    is what remains of T_traction_cut_off after T_warning + T_bs2; T_indication is max(0.8 T_bs, 5 s) without
    service-brake feedback, 5 s with it."""
    train, national = _train(t_traction_cut_off_s=Fraction(8))
    t = braking_data.curve_train_data(train, national, 0)
    assert (t.t_bs_s, t.t_traction_s) == (0, 8)
    train, national = _train(
        t_traction_cut_off_s=Fraction(8), service_brake_command=True, traction_cut_off_command=True
    )
    t = braking_data.curve_train_data(train, national, 0)
    assert (t.t_bs_s, t.t_traction_s) == (Fraction(5, 2), Fraction(8) - 2 - Fraction(5, 2))
    assert braking_data.t_indication_s(train, Fraction(10)) == 8
    assert braking_data.t_indication_s(train, Fraction(5)) == 5
    train, _ = _train(service_brake_feedback=True)
    assert braking_data.t_indication_s(train, Fraction(10)) == 5


@pytest.mark.parametrize(
    ("speeds", "values", "message"),
    [((), (), "one value per speed step"), ((0, 10), (1,), "one value per speed step"), ((5,), (1,), "start at 0")],
)
def test_a_step_function_is_checked(speeds, values, message):
    with pytest.raises(TrainDataError, match=message):
        braking_data.StepFunction(tuple(map(Fraction, speeds)), tuple(map(Fraction, values)))


def _disagreements() -> int:
    """Rows and input checks of both shipped frames outside their tolerance (a frame refused counts as one)."""
    count = 0
    for path in FRAMES.values():
        try:
            frame = load_frame(path)
        except FrameError:
            count += 1
            continue
        count += sum(not r.agrees for r in check_frame(frame))
        count += sum(i.agrees is False for i in check_inputs(frame))
    return count


FRAME_MUTANTS = {
    "AD_0 without its constant": (braking_data._deceleration_steps, '* lam + Fraction("0.076")', "* lam"),
    "the polynomial one degree up": (braking_data._polynomial, "lam**k", "lam ** (k + 1)"),
    "V_lim's exponent": (braking_data._deceleration_steps, "math.pow(float(lam), 0.428)", "math.pow(float(lam), 0.43)"),
    "T_brake_basic without its square": (braking_data._build_up_s, "(el / 100) ** 2", "(el / 100)"),
    "kto without the 1": (braking_data.conversion_model, "kto = 1 + _CT[brake_position]", "kto = _CT[brake_position]"),
    "cmt for a target at standstill": (braking_data._brakes, "target_speed_kmh == 0", "target_speed_kmh != 0"),
    "T_bs2 without the interface rule": (
        braking_data.curve_train_data,
        "t_bs if train.service_brake_command else Fraction(0)",
        "t_bs",
    ),
}


@pytest.mark.parametrize("name", sorted(FRAME_MUTANTS))
def test_the_frames_catch_a_wrong_formula_of_the_train_data(name):
    function, old, new = FRAME_MUTANTS[name]
    with patched(function, old, new):
        assert _disagreements() > 0
    assert _disagreements() == 0


def test_the_formulas_no_frame_exercises():
    """What the two frames cannot tell apart (their factors are 1, their lengths over 400 m, their brake
    percentage under 135 %), stated from Subset-026 §3.13.3 and §3.13.6."""
    low = conversion_model(200, "passenger_P", 300, 160)
    assert low.service_mps2 == conversion_model(135, "passenger_P", 300, 160).emergency_mps2  # min(lambda, 135)
    assert low.t_brake_emergency_cm0_s == Fraction("2.30") + Fraction("0.17") * 16  # L taken as at least 400 m
    assert low.t_brake_service_cm0_s == 3 + Fraction("1.5") * 3 + Fraction("0.1") * 9  # the real length for SB
    g = conversion_model(100, "freight_G", 1200, 100)
    assert g.kto == Fraction("1.16") and g.t_brake_emergency_cmt_s == Fraction("1.16") * (
        Fraction("-0.4") + Fraction("1.6") * 12 + Fraction("0.03") * 144
    )
    train, national = _train(
        brakes=braking_data.GammaBrakes(
            emergency_mps2=braking_data.StepFunction((Fraction(0), Fraction(100)), (Fraction(1), Fraction(1, 2))),
            kdry_rst=braking_data.StepFunction.constant(Fraction(9, 10)),
            kwet_rst=braking_data.StepFunction((Fraction(0), Fraction(50)), (Fraction(8, 10), Fraction(6, 10))),
            t_brake_emergency_s=Fraction(3),
            service_mps2=braking_data.StepFunction.constant(1),
            t_brake_service_s=Fraction(4),
        )
    )
    national = dataclasses.replace(national, m_nvavadh=Fraction(1, 2))
    t = braking_data.curve_train_data(train, national, 0)
    kmh = [s * 36 / 10 for s in t.emergency_speeds_mps]
    k_low, k_high = (
        Fraction(9, 10) * (Fraction(8, 10) + Fraction(1, 2) * Fraction(2, 10)),
        Fraction(9, 10) * (Fraction(6, 10) + Fraction(1, 2) * Fraction(4, 10)),
    )
    assert (kmh, list(t.emergency_decelerations_mps2)) == ([0, 50, 100], [k_low, k_high, k_high / 2])
    factors = braking_data.IntegratedFactors(
        kv_int_a=braking_data.StepFunction.constant(Fraction(9, 10)),
        kv_int_b=braking_data.StepFunction.constant(Fraction(7, 10)),
        a_nvp12_mps2=Fraction(1, 2),
        a_nvp23_mps2=Fraction(1),
        kr_int_lengths_m=(Fraction(0), Fraction(500)),
        kr_int_values=(Fraction(1), Fraction(9, 10)),
        kt_int=Fraction(11, 10),
    )
    lam, _ = _train(brakes=braking_data.LambdaBrakes(Fraction(100), factors), length_m=Fraction(700))
    t = braking_data.curve_train_data(lam, national, 0)
    converted = conversion_model(100, "passenger_P", 700, 180)
    a_ebmax = max(converted.emergency_mps2.values)  # 0.826: between A_NVP12 and A_NVP23
    kv = Fraction(9, 10) + (a_ebmax - Fraction(1, 2)) / Fraction(1, 2) * (Fraction(7, 10) - Fraction(9, 10))
    assert t.emergency_decelerations_mps2[0] == converted.emergency_mps2.values[0] * kv * Fraction(9, 10)
    assert t.t_be_s == Fraction(11, 10) * converted.t_brake_emergency_cm0_s
    assert (
        braking_data.curve_train_data(lam, national, 30).t_be_s == Fraction(11, 10) * converted.t_brake_emergency_cmt_s
    )
