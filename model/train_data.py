"""Train and national data for the braking curves (Subset-026 §3.13 style, docs/design.md reference formulas).

Everything is SI inside: m, s, m/s, m/s^2; gradients per mille. The presets take the
seeds' figures in km/h and km/h/s and convert them once, exactly:

- seed 000 §2.5 Table 1: 200 m train, 80 km/h, acceleration 3.0, service brake 3.0,
  emergency brake 4.0 km/h/s;
- seed 002 §4.2 Table 1: 200 m train, 80 km/h, acceleration 3.0, full service 3.5,
  emergency 4.5 km/h/s, EB / FSB / warning 5 km/h apart.

The seeds give no build-up times, adhesion factors or speed accuracy; the presets
use the values documented on each field (Subset-026's national defaults where it
has them). :func:`validate` rejects data out of range with a message naming the
field and the value.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Generic

from atcs.model.errors import AtcsInputError
from atcs.model.ops import B, N
from atcs.model.profile import KMH_PER_MPS


class TrainDataError(AtcsInputError):
    """Invalid train or national data; the message names the field and the value."""


@dataclass(frozen=True)
class TrainData(Generic[N, B]):
    train_length_m: N
    max_acceleration_mps2: N
    """A_max: the highest acceleration traction can give (the plant's bound, and A_est's)."""
    emergency_speeds_mps: tuple[N, ...]
    """Speed steps of A_brake_emergency: ``emergency_decelerations_mps2[k]`` from ``emergency_speeds_mps[k]``
    up (the first step starts at 0)."""
    emergency_decelerations_mps2: tuple[N, ...]
    service_speeds_mps: tuple[N, ...]
    """Speed steps of A_brake_service, as for the emergency brake."""
    service_decelerations_mps2: tuple[N, ...]
    kdry_rst: N
    """Kdry_rst: the share of the emergency deceleration guaranteed on dry rails (confidence level), in (0, 1]."""
    kwet_rst: N
    """Kwet_rst: the share that remains on wet rails, in (0, 1]."""
    rotating_mass_uphill_percent: N
    """M_rotating used for uphill gradients: M_rotating_nom if known, else M_rotating_max (15 %)."""
    rotating_mass_downhill_percent: N
    """M_rotating used for downhill gradients: M_rotating_nom if known, else M_rotating_min (2 %)."""
    t_be_s: N
    """T_be: emergency brake build-up time (command to full effect)."""
    t_bs_s: N
    """T_bs: service brake build-up time."""
    t_traction_s: N
    """T_traction: traction cut-off time."""
    v_ura_mps: N
    """V_ura: speed-measurement accuracy (the measured speed is within +- V_ura of the true speed)."""


@dataclass(frozen=True)
class NationalData(Generic[N, B]):
    m_nvavadh: N
    """M_NVAVADH: weighting of the wet-rail factor, in [0, 1] (0: assume wet rails)."""
    inhibit_speed_inaccuracy: B
    """Q_NVINHSMICPERM: do not add V_ura to the estimated speed in the EBI."""
    dv_ebi_min_mps: N
    dv_ebi_max_mps: N
    v_ebi_min_mps: N
    v_ebi_max_mps: N
    dv_sbi_min_mps: N
    dv_sbi_max_mps: N
    v_sbi_min_mps: N
    v_sbi_max_mps: N
    dv_warning_min_mps: N
    dv_warning_max_mps: N
    v_warning_min_mps: N
    v_warning_max_mps: N
    t_warning_s: N
    """Warning time before the SBI."""
    t_driver_s: N
    """Driver reaction time: the permitted curve lies this far (in time) before the SBI."""
    t_indication_s: N
    """Indication time before the permitted curve."""


def _kmh(value) -> Fraction:
    return Fraction(value) / KMH_PER_MPS


def _kmh_s(value) -> Fraction:
    return Fraction(value) / KMH_PER_MPS


def seed000_train() -> TrainData:
    """Seed 000 §2.5: SB 3.0, EB 4.0 km/h/s, acceleration 3.0 km/h/s, 200 m. T_be 1.5 s, T_bs 2 s,
    T_traction 0.8 s, Kdry 0.9, Kwet 0.8, M_rotating 2 % / 15 % (unknown), V_ura 2 km/h (assumed)."""
    return TrainData(
        train_length_m=Fraction(200),
        max_acceleration_mps2=_kmh_s(3),
        emergency_speeds_mps=(Fraction(0),),
        emergency_decelerations_mps2=(_kmh_s(4),),
        service_speeds_mps=(Fraction(0),),
        service_decelerations_mps2=(_kmh_s(3),),
        kdry_rst=Fraction(9, 10),
        kwet_rst=Fraction(8, 10),
        rotating_mass_uphill_percent=Fraction(15),
        rotating_mass_downhill_percent=Fraction(2),
        t_be_s=Fraction(3, 2),
        t_bs_s=Fraction(2),
        t_traction_s=Fraction(4, 5),
        v_ura_mps=_kmh(2),
    )


def seed002_train() -> TrainData:
    """Seed 002 §4.2: full service 3.5, EB 4.5 km/h/s; otherwise as :func:`seed000_train`."""
    return dataclasses.replace(
        seed000_train(), emergency_decelerations_mps2=(_kmh_s("4.5"),), service_decelerations_mps2=(_kmh_s("3.5"),)
    )


def subset026_national() -> NationalData:
    """Subset-026 defaults: ceilings 4 / 5.5 / 7.5 km/h up to 110 km/h (5 / 10 / 15 from 210 km/h),
    M_NVAVADH 0, no inhibition, warning 2 s, driver 4 s, indication from the permitted curve 2 s (assumed)."""
    return NationalData(
        m_nvavadh=Fraction(0),
        inhibit_speed_inaccuracy=False,
        dv_ebi_min_mps=_kmh("7.5"),
        dv_ebi_max_mps=_kmh(15),
        v_ebi_min_mps=_kmh(110),
        v_ebi_max_mps=_kmh(210),
        dv_sbi_min_mps=_kmh("5.5"),
        dv_sbi_max_mps=_kmh(10),
        v_sbi_min_mps=_kmh(110),
        v_sbi_max_mps=_kmh(210),
        dv_warning_min_mps=_kmh(4),
        dv_warning_max_mps=_kmh(5),
        v_warning_min_mps=_kmh(110),
        v_warning_max_mps=_kmh(140),
        t_warning_s=Fraction(2),
        t_driver_s=Fraction(4),
        t_indication_s=Fraction(2),
    )


def seed002_national() -> NationalData:
    """Seed 002 §3.2: warning, FSB and EB 5 km/h apart (5 / 10 / 15 km/h over the MRSP at every speed)."""
    return dataclasses.replace(
        subset026_national(),
        dv_warning_min_mps=_kmh(5),
        dv_warning_max_mps=_kmh(5),
        dv_sbi_min_mps=_kmh(10),
        dv_sbi_max_mps=_kmh(10),
        dv_ebi_min_mps=_kmh(15),
        dv_ebi_max_mps=_kmh(15),
    )


PRESETS = {"seed000": (seed000_train, subset026_national), "seed002": (seed002_train, seed002_national)}
"""The seeds' train and national data by name (each a function returning a fresh record)."""

CYCLE_S = Fraction(1, 10)
"""One ATP cycle (seed 001)."""

DESIGN_GRADIENTS_PERMILLE = (-40, 40)
"""The design case of the compensated gradient: the steepest falling and rising gradients the presets'
plant data fix (per mille, uphill positive)."""


def preset_data(train: TrainData, national: NationalData, cycle_s=CYCLE_S) -> dict:
    """Train, national and plant data of a closed loop: the plant's delays are the train data's times less one
    cycle (the cycle in which the last passing check was made), its guaranteed deceleration is
    K * A_brake_emergency."""
    from atcs.model.curves import adhesion_factor  # curves imports this module
    from atcs.model.node import as_dict
    from atcs.model.ops.exact import EXACT

    k = adhesion_factor(EXACT, train, national)
    return {
        **as_dict(train),
        **as_dict(national),
        "gradient_permille": tuple(Fraction(g) for g in DESIGN_GRADIENTS_PERMILLE),
        "service_brake_fitted": True,
        "cycle_s": cycle_s,
        "traction_cut_cycles": train.t_traction_s / cycle_s - 1,
        "brake_build_up_cycles": train.t_be_s / cycle_s - 1,
        "guaranteed_deceleration_mps2": k * min(train.emergency_decelerations_mps2),
        "max_deceleration_mps2": Fraction(3),
    }


def whole_cycle_train(train: TrainData, cycle_s) -> TrainData:
    """``train`` with T_be and T_traction rounded up to whole cycles of ``cycle_s``, T_traction to at least one: the
    closed loop's plant acts on cycles, and the ATP then assumes the same (not shorter) times."""
    t_be = math.ceil(train.t_be_s / cycle_s) * cycle_s
    t_traction = max(math.ceil(train.t_traction_s / cycle_s), 1) * cycle_s
    return dataclasses.replace(train, t_be_s=Fraction(t_be), t_traction_s=Fraction(t_traction))


MAX_BUILD_UP_S = 120
"""Longest brake build-up or traction cut-off time accepted (s): well above the longest the conversion model of
Subset-026 §3.13.3 gives within its validity limits (a 1,500 m freight train in G: T_brake_service_cmt 64.7 s)."""


def validate(train: TrainData, national: NationalData) -> None:
    """Raise :class:`TrainDataError` for data out of range (concrete data only)."""
    _check(train.train_length_m > 0, "train_length_m", train.train_length_m, "not positive")
    _check(train.max_acceleration_mps2 >= 0, "max_acceleration_mps2", train.max_acceleration_mps2, "negative")
    for brake in ("emergency", "service"):
        speeds = getattr(train, f"{brake}_speeds_mps")
        decels = getattr(train, f"{brake}_decelerations_mps2")
        _check(
            len(speeds) == len(decels) and len(speeds) > 0,
            f"{brake}_speeds_mps",
            speeds,
            f"not one speed per deceleration ({len(decels)} decelerations)",
        )
        _check(speeds[0] == 0, f"{brake}_speeds_mps[0]", speeds[0], "not 0 (the first step starts at standstill)")
        for k in range(1, len(speeds)):
            _check(
                speeds[k] > speeds[k - 1],
                f"{brake}_speeds_mps[{k}]",
                speeds[k],
                f"not above {brake}_speeds_mps[{k - 1}] = {speeds[k - 1]!r}",
            )
        for k, a in enumerate(decels):
            _check(0 < a <= 5, f"{brake}_decelerations_mps2[{k}]", a, "outside (0, 5] m/s^2")
    for name in ("kdry_rst", "kwet_rst"):
        _check(0 < getattr(train, name) <= 1, name, getattr(train, name), "outside (0, 1]")
    for name in ("rotating_mass_uphill_percent", "rotating_mass_downhill_percent"):
        _check(0 <= getattr(train, name) <= 50, name, getattr(train, name), "outside [0, 50] %")
    for name in ("t_be_s", "t_bs_s", "t_traction_s"):
        _check(
            0 <= getattr(train, name) <= MAX_BUILD_UP_S, name, getattr(train, name), f"outside [0, {MAX_BUILD_UP_S}] s"
        )
    _check(train.v_ura_mps >= 0, "v_ura_mps", train.v_ura_mps, "negative")
    _check(0 <= national.m_nvavadh <= 1, "m_nvavadh", national.m_nvavadh, "outside [0, 1]")
    for curve in ("ebi", "sbi", "warning"):
        lo, hi = getattr(national, f"dv_{curve}_min_mps"), getattr(national, f"dv_{curve}_max_mps")
        vlo, vhi = getattr(national, f"v_{curve}_min_mps"), getattr(national, f"v_{curve}_max_mps")
        _check(0 <= lo <= hi, f"dv_{curve}_max_mps", hi, f"below dv_{curve}_min_mps = {lo!r} or negative")
        _check(0 <= vlo < vhi, f"v_{curve}_max_mps", vhi, f"not above v_{curve}_min_mps = {vlo!r}")
    for name in ("t_warning_s", "t_driver_s", "t_indication_s"):
        _check(0 <= getattr(national, name) <= 60, name, getattr(national, name), "outside [0, 60] s")
    _check(
        national.t_driver_s >= national.t_warning_s,
        "t_driver_s",
        national.t_driver_s,
        f"below t_warning_s = {national.t_warning_s!r} (the permitted curve must lie behind the warning curve)",
    )


def _check(ok: bool, field: str, value, expected: str) -> None:
    """Raise :class:`TrainDataError` naming the field, its value and what is wrong with it unless ``ok``."""
    if not ok:
        raise TrainDataError(f"train data: {field} = {value!r} is {expected}")
