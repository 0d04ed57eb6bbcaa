"""Reading a reference frame of the ERA braking-curves tool (the JSON of ``frames/README.md``) into the model's
data: the train as Subset-026 states it, the national and fixed values, the line's gradients, the target and
the expected rows. A frame the reader cannot use is refused naming the file, the field and the value."""

from __future__ import annotations

import itertools
import math
import re
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

from atcs.model.braking_data import (
    GammaBrakes,
    IntegratedFactors,
    LambdaBrakes,
    RailTrain,
    StepFunction,
    curve_national_data,
    curve_train_data,
)
from atcs.model.curves import check_braking_capability
from atcs.model.data_files import read_json
from atcs.model.errors import AtcsInputError
from atcs.model.ops.exact import EXACT
from atcs.model.profile import KMH_PER_MPS, Profile
from atcs.model.psl import extend_by_train_length
from atcs.model.train_data import NationalData, TrainDataError, subset026_national, validate

__all__ = ["CURVES", "Frame", "FrameError", "InputRow", "Row", "load_frame", "shipped_frames"]

FRAMES_DIR = Path(__file__).parent / "frames"

CURVES = ("A_safe", "EBD", "EBI", "SBI2", "Warning", "Permitted", "Indication")
"""The curves a frame may give rows for (others are listed as not compared)."""

BRAKE_POSITIONS = {"PassengerTrainInP": "passenger_P", "FreightTrainInP": "freight_P", "FreightTrainInG": "freight_G"}


MAX_MAGNITUDE = 1e7
"""No quantity of a frame (m, s, km/h, m/s^2, per mille) is larger: a larger one is refused, not computed."""


class FrameError(AtcsInputError):
    """A frame that cannot be read; the message names the file, the field and the value."""


@dataclass(frozen=True)
class Row:
    """One expected value: for a curve, the distance (m, positive in rear of the target) at which it reaches
    ``speed_kmh``; for ``A_safe``, the deceleration (m/s^2) at ``speed_kmh`` and ``location_m``."""

    curve: str
    target_speed_kmh: Fraction
    target_m: Fraction
    speed_kmh: Fraction
    expected: Fraction
    tolerance: Fraction
    location_m: Fraction | None = None


@dataclass(frozen=True)
class InputRow:
    """One of the frame's checks of the data the curves start from (``expected.input_verification``): a
    conversion-model output, T_be, T_bs, or A_brake_*(V) at ``speed_kmh``."""

    quantity: str
    speed_kmh: Fraction | None
    expected: Fraction | bool
    tolerance: Fraction


@dataclass(frozen=True)
class Frame:
    name: str
    path: Path
    train: RailTrain
    national: NationalData
    gradient: Profile
    """The line's gradients as the frame gives them (per mille, uphill positive), not yet compensated."""
    mrsp_kmh: Fraction
    rows: tuple[Row, ...]
    inputs: tuple[InputRow, ...]
    not_compared: tuple[str, ...]
    """Expectation groups of the frame that are not curve rows (e.g. ``input_verification``)."""


class _Reader:
    def __init__(self, path: Path, doc):
        self.path, self.doc = path, doc

    def error(self, field: str, value, why: str) -> FrameError:
        return FrameError(f"{self.path}: {field} = {value!r} {why}")

    def get(self, field: str, node=None, at: str = ""):
        """``field`` (dotted) of ``node`` (the document by default), ``at`` naming ``node`` in messages."""
        node = self.doc if node is None else node
        for part in field.split("."):
            if not isinstance(node, dict) or part not in node:
                raise FrameError(f"{self.path}: {at}{field} is missing")
            node = node[part]
        return node

    def number(self, field: str, node=None, *, at: str = "", infinite_ok: bool = False) -> Fraction | None:
        value = self.get(field, node, at)
        if infinite_ok and value == "Infinity":
            return None
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise self.error(at + field, value, "is not a finite number")
        if abs(value) > MAX_MAGNITUDE:
            raise self.error(at + field, value, f"is larger than {MAX_MAGNITUDE:g} in magnitude")
        return Fraction(str(value))

    def value(self, field: str, node=None) -> Fraction:
        """A number given directly or as ``{"value": ...}``."""
        raw = self.get(field, node)
        return self.number(f"{field}.value", node) if isinstance(raw, dict) else self.number(field, node)

    def flag(self, field: str, node=None) -> bool:
        raw = self.get(field, node)
        raw = raw.get("value") if isinstance(raw, dict) else raw
        if raw in (True, "Yes"):
            return True
        if raw in (False, "No"):
            return False
        raise self.error(field, raw, "is not true/false or Yes/No")


def _steps(r: _Reader, field: str, values_key: str = "Acceleration", step_key: str = "SpeedStep") -> StepFunction:
    """A model's ``[{<step_key>, <values_key>}, ...]`` list, the last step's ``Infinity`` a sentinel."""
    rows = r.get(field)
    if not isinstance(rows, list) or not rows:
        raise r.error(field, rows, "is not a non-empty list of steps")
    speeds, values = [], []
    for k, row in enumerate(rows):
        speed = r.number(step_key, row, at=f"{field}[{k}].", infinite_ok=True)
        if speed is None:
            continue
        speeds.append(speed)
        values.append(r.number(values_key, row, at=f"{field}[{k}]."))
    try:
        return StepFunction(tuple(speeds), tuple(values))
    except TrainDataError as exc:
        raise FrameError(f"{r.path}: {field}: {exc}") from None


def _correction_factor(r: _Reader, field: str, speeds_kmh: tuple[Fraction, ...]) -> StepFunction:
    """``{CF0: ..., CF6: ...}``: CF_i on the EB model's i-th speed step (the frame's ``model_semantics``)."""
    factors = r.get(field)
    values = tuple(r.number(f"CF{k}", factors, at=f"{field}.") for k in range(len(speeds_kmh)))
    return StepFunction(speeds_kmh, values)


def _gamma(r: _Reader) -> GammaBrakes:
    base = "inputs.brake_parameters"
    eb_name, sb_name = r.get(f"{base}.active_combination_EB"), r.get(f"{base}.active_combination_SB")
    eb = f"{base}.emergency_brake_models.{eb_name}"
    sb = f"{base}.service_brake_models.{sb_name}"
    emergency = _steps(r, f"{eb}.model_values")
    return GammaBrakes(
        emergency_mps2=emergency,
        kdry_rst=_correction_factor(r, f"{eb}.Kdry_rst", emergency.speeds_kmh),
        kwet_rst=_correction_factor(r, f"{eb}.Kwet_rst", emergency.speeds_kmh),
        t_brake_emergency_s=r.number(f"{eb}.T_brake_emergency_s"),
        service_mps2=_steps(r, f"{sb}.model_values"),
        t_brake_service_s=r.number(f"{sb}.T_brake_service_s"),
    )


def _lambda(r: _Reader, position: str) -> LambdaBrakes:
    national = "inputs.national_values"
    kv_key = "IntegratedCorrectionFactorKvInt_PassengerTrain" if position == "passenger_P" else None
    factors = IntegratedFactors.neutral()
    if kv_key is not None:
        kv = f"{national}.{kv_key}"
        kr_int = _steps(r, f"{national}.IntegratedCorrectionFactorKrInt.values", "Value", "LengthStep")
        factors = IntegratedFactors(
            kv_int_a=_steps(r, f"{kv}.values", "ValueA"),
            kv_int_b=_steps(r, f"{kv}.values", "ValueB"),
            a_nvp12_mps2=r.value(f"{kv}.A_NVP12"),
            a_nvp23_mps2=r.value(f"{kv}.A_NVP23"),
            kr_int_lengths_m=kr_int.speeds_kmh,
            kr_int_values=kr_int.values,
            kt_int=r.value(f"{national}.Kt_int"),
        )
    else:
        raise r.error("inputs.train_data.brake_position", position, "is not read for a Lambda train yet (Kv_int)")
    return LambdaBrakes(r.number("inputs.brake_parameters.brake_percentage_lambda_percent"), factors)


def _train(r: _Reader) -> RailTrain:
    data = "inputs.train_data"
    position_text = r.get(f"{data}.brake_position")
    position = BRAKE_POSITIONS.get(position_text)
    if position is None:
        raise r.error(f"{data}.brake_position", position_text, f"is not one of {', '.join(BRAKE_POSITIONS)}")
    kind = r.get("inputs.train_type")
    if kind not in ("Gamma", "Lambda"):
        raise r.error("inputs.train_type", kind, "is not Gamma or Lambda")
    rotating = r.get(f"{data}.M_rotating_nom_percent")
    return RailTrain(
        name=r.path.stem,
        length_m=r.number(f"{data}.train_length_m"),
        max_speed_kmh=r.number(f"{data}.maximum_speed_kmh"),
        brake_position=position,
        brakes=_gamma(r) if kind == "Gamma" else _lambda(r, position),
        t_traction_cut_off_s=r.number(f"{data}.T_traction_cut_off_s"),
        service_brake_command=r.flag(f"{data}.service_brake_command_interface_implemented"),
        service_brake_feedback=False,
        traction_cut_off_command=r.flag(f"{data}.traction_cut_off_interface_implemented"),
        rotating_mass_percent=None if isinstance(rotating, str) else r.number(f"{data}.M_rotating_nom_percent"),
    )


def _national(r: _Reader) -> NationalData:
    fixed, national = "inputs.fixed_values", "inputs.national_values"

    def kmh(name: str) -> Fraction:
        return r.value(f"{fixed}.{name}") / KMH_PER_MPS

    base = subset026_national()
    return NationalData(
        m_nvavadh=r.value(f"{national}.M_NVAVADH"),
        inhibit_speed_inaccuracy=r.flag(f"{national}.Q_NVINHSMICPERM"),
        **{f"{name.lower()}_mps": kmh(name) for name in _CEILING_NAMES},
        t_warning_s=r.value(f"{fixed}.T_warning"),
        t_driver_s=r.value(f"{fixed}.T_driver"),
        t_indication_s=base.t_indication_s,  # replaced by the train's rule (braking_data.curve_national_data)
    )


_CEILING_NAMES = tuple(
    f"{prefix}{kind}_{end}" for kind in ("ebi", "sbi", "warning") for prefix in ("dV_", "V_") for end in ("min", "max")
)


def _gradient(r: _Reader, line_end_m: Fraction) -> Profile:
    field = "inputs.track_data.gradients"
    rows = r.get(field)
    if not isinstance(rows, list) or not rows:
        raise r.error(field, rows, "is not a non-empty list")
    starts = tuple(r.number("location_m", row, at=f"{field}[{k}].") for k, row in enumerate(rows))
    values = tuple(r.number("gradient_permille", row, at=f"{field}[{k}].") for k, row in enumerate(rows))
    if starts[0] != 0 or any(a >= b for a, b in itertools.pairwise(starts)) or starts[-1] >= line_end_m:
        raise r.error(f"{field}[*].location_m", [float(s) for s in starts], "must start at 0 and increase")
    return Profile(starts, values, line_end_m)


def _rows(r: _Reader) -> tuple[tuple[Row, ...], tuple[str, ...]]:
    expected = r.get("expected")
    if not isinstance(expected, dict):
        raise r.error("expected", expected, "is not an object of curves")
    rows, others = [], []
    for curve, items in expected.items():
        if curve == "input_verification":
            continue
        if curve not in CURVES:
            others.append(curve)
            continue
        if not isinstance(items, list):
            raise r.error(f"expected.{curve}", items, "is not a list of rows")
        for k, item in enumerate(items):
            at = f"expected.{curve}[{k}]."
            rows.append(
                Row(
                    curve=curve,
                    target_speed_kmh=r.number("target.speed_kmh", item, at=at),
                    target_m=r.number("target.location_m", item, at=at),
                    speed_kmh=r.number("speed_kmh", item, at=at),
                    expected=r.number("expected_value", item, at=at),
                    tolerance=r.number("tolerance", item, at=at),
                    location_m=r.number("location_m", item, at=at) if curve == "A_safe" else None,
                )
            )
    return tuple(rows), tuple(others)


def _check_braking(path: Path, train: RailTrain, national: NationalData, gradient: Profile) -> None:
    """The train's data as the curves take it, for a target at standstill and above it, in range
    (:func:`~atcs.model.train_data.validate`), and able to stop on every gradient of the line."""
    try:
        for target_speed_kmh in (0, 1):
            data = curve_train_data(train, national, target_speed_kmh)
            validate(data, curve_national_data(train, national, target_speed_kmh))
            check_braking_capability(data, national, extend_by_train_length(EXACT, gradient, data.train_length_m))
    except TrainDataError as exc:
        raise FrameError(f"{path}: {exc}") from None


_SPEED_ARGUMENT = re.compile(r"\(V => ([0-9.eE+-]+)\)")


def _inputs(r: _Reader) -> tuple[InputRow, ...]:
    items = r.get("expected").get("input_verification", [])
    if not isinstance(items, list):
        raise r.error("expected.input_verification", items, "is not a list of rows")
    rows = []
    for k, item in enumerate(items):
        at = f"expected.input_verification[{k}]."
        quantity, expression = r.get("quantity", item, at), r.get("expression", item, at)
        if not isinstance(quantity, str) or not isinstance(expression, str):
            raise r.error(at + "quantity", quantity, "is not a string")
        raw = r.get("expected_value", item, at)
        expected = raw if isinstance(raw, bool) else r.number("expected_value", item, at=at)
        speed = _SPEED_ARGUMENT.search(expression) if quantity.endswith("(V)") else None
        if quantity.endswith("(V)") and speed is None:
            raise r.error(at + "expression", expression, "names no speed (V => ...)")
        speed_kmh = Fraction(speed.group(1)) if speed else None
        rows.append(InputRow(quantity, speed_kmh, expected, r.number("tolerance", item, at=at)))
    return tuple(rows)


def load_frame(path: str | Path) -> Frame:
    """The frame at ``path`` (:class:`FrameError` naming the file, the field and the value if unusable)."""
    path = Path(path)
    doc = read_json(path, FrameError, "the frame")
    r = _Reader(path, doc)
    train = _train(r)
    mrsp_kmh = min(r.number("inputs.track_data.signalling_related_speed_restriction.value_kmh"), train.max_speed_kmh)
    line_end_m = r.number("inputs.track_data.signalling_related_speed_restriction.end_m")
    rows, others = _rows(r)
    national, gradient = _national(r), _gradient(r, line_end_m)
    _check_braking(path, train, national, gradient)
    return Frame(
        name=str(doc.get("frame_name", path.stem)),
        path=path,
        train=train,
        national=national,
        gradient=gradient,
        mrsp_kmh=mrsp_kmh,
        rows=rows,
        inputs=_inputs(r),
        not_compared=others,
    )


def shipped_frames() -> list[Path]:
    """The reference frames shipped with atcs (``frames/``)."""
    return sorted(FRAMES_DIR.glob("*.json"))
