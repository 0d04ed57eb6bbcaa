"""Each row of a reference frame computed with the model's curve functions on exact numbers, and compared.

A row's curve is computed for the frame's target (``V_target + dV_ebi(V_target)`` at the target, the curve
continuing below it: a target that is not the end of authority, §3.13.8.3.1) with the estimated acceleration 0,
as the reference tool's rows are. The permitted curve is 0 m at or below the target speed (the tool's curves stop
at the target), and the permitted and indication curves at or above V_MRSP are those of V_MRSP (ceiling speed
monitoring takes over there). A row agrees when the computed value is within its tolerance of the expected one,
sign included (the reference tool itself compares absolute values).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

from atcs.model.braking_data import LambdaBrakes, conversion_model, curve_national_data, curve_train_data
from atcs.model.curves import Target, ceiling_offset_mps, gradient_acceleration_mps2, reference_curve_locations
from atcs.model.deceleration import braking_deceleration_mps2
from atcs.model.ops.exact import EXACT
from atcs.model.profile import KMH_PER_MPS, value_at
from atcs.model.psl import extend_by_train_length
from atcs.proofs.conformance.frames import CURVES, Frame, InputRow, Row

__all__ = ["InputResult", "RowResult", "check_frame", "check_inputs", "worst_by_curve"]

_LOCATION_OF = {
    "EBD": "ebd_m",
    "EBI": "ebi_m",
    "SBI2": "sbi_m",
    "Warning": "warning_m",
    "Permitted": "permitted_m",
    "Indication": "indication_m",
}


@dataclass(frozen=True)
class RowResult:
    row: Row
    computed: Fraction

    @property
    def error(self) -> Fraction:
        return abs(self.computed - self.row.expected)

    @property
    def agrees(self) -> bool:
        return self.error < self.row.tolerance


def _target(frame: Frame, row: Row) -> Target:
    speed = row.target_speed_kmh / KMH_PER_MPS
    n = frame.national
    foot = speed + ceiling_offset_mps(
        EXACT, speed, n.dv_ebi_min_mps, n.dv_ebi_max_mps, n.v_ebi_min_mps, n.v_ebi_max_mps
    )
    return Target(row.target_m, speed, foot)


def _data(frame: Frame, target_speed_kmh) -> tuple:
    """The train and national data and the compensated gradient for a target of ``target_speed_kmh``."""
    t = curve_train_data(frame.train, frame.national, target_speed_kmh)
    n = curve_national_data(frame.train, frame.national, target_speed_kmh)
    return t, n, extend_by_train_length(EXACT, frame.gradient, t.train_length_m)


def _computed(frame: Frame, row: Row, data: tuple) -> Fraction:
    t, n, gradient_c = data
    speed = row.speed_kmh / KMH_PER_MPS
    if row.curve == "A_safe":
        a_brake = braking_deceleration_mps2(EXACT, t.emergency_speeds_mps, t.emergency_decelerations_mps2, speed)
        return a_brake + gradient_acceleration_mps2(EXACT, t, value_at(EXACT, gradient_c, row.location_m))
    if row.curve == "Permitted" and row.speed_kmh <= row.target_speed_kmh:
        return Fraction(0)
    if row.curve in ("Permitted", "Indication"):
        speed = min(speed, frame.mrsp_kmh / KMH_PER_MPS)
    locations = reference_curve_locations(EXACT, t, n, gradient_c, _target(frame, row), speed, Fraction(0))
    return row.target_m - getattr(locations, _LOCATION_OF[row.curve])


@dataclass(frozen=True)
class InputResult:
    row: InputRow
    computed: Fraction | bool | None
    """None: a quantity atcs does not compute (listed, not compared)."""

    @property
    def agrees(self) -> bool | None:
        if self.computed is None:
            return None
        if isinstance(self.row.expected, bool) or isinstance(self.computed, bool):
            return self.computed == self.row.expected
        return abs(self.computed - self.row.expected) <= self.row.tolerance


def _input_value(frame: Frame, row: InputRow):
    """The value atcs computes for one of the frame's input checks (targets at standstill, as the frame's)."""
    brakes = frame.train.brakes
    if row.quantity == "ConversionModel.ConversionModelIsUsed()":
        return isinstance(brakes, LambdaBrakes)
    t = curve_train_data(frame.train, frame.national, 0)
    n = curve_national_data(frame.train, frame.national, 0)
    converted = None
    if isinstance(brakes, LambdaBrakes):
        train = frame.train
        converted = conversion_model(brakes.brake_percentage, train.brake_position, train.length_m, train.max_speed_kmh)
    model = {
        "T_be()": t.t_be_s,
        "T_bs()": None if converted is None else converted.t_brake_service_cm0_s,
        "T_indication": n.t_indication_s,
    }
    if converted is not None:
        model |= {
            "ConversionModel.kto()": converted.kto,
            "ConversionModel.T_brake_emergency_cm0": converted.t_brake_emergency_cm0_s,
            "ConversionModel.T_brake_emergency_cmt": converted.t_brake_emergency_cmt_s,
            "ConversionModel.T_brake_service_cm0": converted.t_brake_service_cm0_s,
            "ConversionModel.T_brake_service_cmt": converted.t_brake_service_cmt_s,
            "A_brake_emergency.Val1.SpeedStep": converted.emergency_mps2.speeds_kmh[1],
            "A_brake_service.Val1.SpeedStep": converted.service_mps2.speeds_kmh[1],
        }
        if row.speed_kmh is not None:
            model["A_brake_emergency(V)"] = converted.emergency_mps2.at(row.speed_kmh)
            model["A_brake_service(V)"] = converted.service_mps2.at(row.speed_kmh)
    return model.get(row.quantity)


def check_inputs(frame: Frame) -> list[InputResult]:
    """Every input check of ``frame``, computed (None where atcs has no such quantity)."""
    return [InputResult(row, _input_value(frame, row)) for row in frame.inputs]


def check_frame(frame: Frame) -> list[RowResult]:
    """Every row of ``frame``, computed."""
    data = {speed: _data(frame, speed) for speed in {row.target_speed_kmh for row in frame.rows}}
    return [RowResult(row, _computed(frame, row, data[row.target_speed_kmh])) for row in frame.rows]


def worst_by_curve(results: list[RowResult]) -> dict[str, tuple[int, int, Fraction]]:
    """Per curve, in :data:`~atcs.proofs.conformance.frames.CURVES` order: rows, rows in tolerance, worst
    error."""
    summary = {}
    for curve in CURVES:
        mine = [r for r in results if r.row.curve == curve]
        if mine:
            summary[curve] = (len(mine), sum(r.agrees for r in mine), max(r.error for r in mine))
    return summary
