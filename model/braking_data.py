"""A train's braking data as Subset-026 §3.13.2 and §3.13.3 state it, Gamma or Lambda, and the
:class:`~atcs.model.train_data.TrainData` the curves take for a target.

A Gamma train brings its brake models (A_brake_emergency(V), A_brake_service(V), T_brake_emergency,
T_brake_service of the active brake combination) and its correction factors Kdry_rst(V), Kwet_rst(V); a Lambda
train brings its brake percentage, which the conversion model (§3.13.3) turns into brake models, to be corrected
by the national integrated factors Kv_int(V), Kr_int(L), Kt_int. Speeds are km/h here, as the spec's tables give
them; everything :func:`curve_train_data` returns is SI.

The correction factors are folded into the deceleration steps: ``A_brake_safe(V) = K(V) * A_brake_emergency(V)``
with ``K(V) = Kdry_rst(V) * (Kwet_rst(V) + M_NVAVADH * (1 - Kwet_rst(V)))`` (Gamma) or ``Kv_int(V) * Kr_int(L)``
(Lambda) is what the EBD uses (§3.13.6.2.1), so the returned data carries ``A_brake_safe`` as its emergency steps
with ``kdry_rst = kwet_rst = 1``. At a step's own speed the spec takes the deceleration of the step below
(``V1 < speed <= V2``, §3.13.2.2.3.1.3) and the data here the step above; the two differ on speeds of measure
zero, which no curve location depends on.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from dataclasses import dataclass
from fractions import Fraction

from atcs.model.curves import GuidanceData
from atcs.model.profile import KMH_PER_MPS
from atcs.model.train_data import NationalData, TrainData, TrainDataError

__all__ = [
    "BRAKE_POSITIONS",
    "DEPENDS_ON",
    "SPECIAL_BRAKES",
    "BrakeCombination",
    "ConvertedBrakes",
    "GammaBrakes",
    "IntegratedFactors",
    "LambdaBrakes",
    "NormalServiceBrake",
    "RailTrain",
    "StepFunction",
    "conversion_model",
    "curve_national_data",
    "curve_train_data",
    "guidance_data",
    "t_indication_s",
    "t_traction_s",
    "with_special_brakes",
]

BRAKE_POSITIONS = ("passenger_P", "freight_P", "freight_G")
"""§3.13.2.2.4.1: passenger train in P, freight train in P, freight train in G."""

SPECIAL_BRAKES = ("regenerative", "eddy_current", "magnetic_shoe", "ep")
"""§3.13.2.2.6.1: the special brakes whose status (active or not) selects the brake models."""

DEPENDS_ON = {
    "emergency": frozenset({"regenerative", "eddy_current", "magnetic_shoe"}),
    "kdry_rst": frozenset({"regenerative", "eddy_current", "magnetic_shoe"}),
    "kwet_rst": frozenset({"regenerative", "eddy_current", "magnetic_shoe"}),
    "t_brake_emergency_s": frozenset(SPECIAL_BRAKES),
    "service": frozenset({"regenerative", "eddy_current"}),
    "t_brake_service_s": frozenset({"regenerative", "eddy_current", "ep"}),
}
"""§3.13.2.2.6.2 Table 4: the special brakes whose status each Gamma brake model depends on (the correction factors
go with A_brake_emergency, one set per model, §3.13.2.2.9.1.2)."""

T_INDICATION_MIN_S = Fraction(5)
"""§3.13.9.3.6.2: the least T_indication (s)."""


@dataclass(frozen=True)
class StepFunction:
    """A step function of speed: ``values[k]`` from ``speeds_kmh[k]`` up to the next step (the first step
    starts at 0 km/h, the last is open ended, §3.13.2.2.3.1.4)."""

    speeds_kmh: tuple[Fraction, ...]
    values: tuple[Fraction, ...]

    def __post_init__(self):
        if not self.speeds_kmh or len(self.speeds_kmh) != len(self.values):
            raise TrainDataError(f"a step function needs one value per speed step, got {self!r}")
        if self.speeds_kmh[0] != 0 or any(a >= b for a, b in itertools.pairwise(self.speeds_kmh)):
            raise TrainDataError(f"speed steps must start at 0 and increase, got {list(map(str, self.speeds_kmh))}")

    @classmethod
    def constant(cls, value) -> StepFunction:
        return cls((Fraction(0),), (Fraction(value),))

    def at(self, speed_kmh) -> Fraction:
        """The value at ``speed_kmh`` (the step starting at or below it)."""
        return next(v for s, v in zip(reversed(self.speeds_kmh), reversed(self.values), strict=True) if s <= speed_kmh)

    def times(self, other: StepFunction) -> StepFunction:
        """The product, on the union of both functions' steps."""
        steps = tuple(sorted(set(self.speeds_kmh) | set(other.speeds_kmh)))
        return StepFunction(steps, tuple(self.at(s) * other.at(s) for s in steps))


@dataclass(frozen=True)
class GammaBrakes:
    """Brake models given as train data for the active brake combination (§3.13.2.2.3, Table 4)."""

    emergency_mps2: StepFunction
    """A_brake_emergency(V)."""
    kdry_rst: StepFunction
    """Kdry_rst(V) at the national EB confidence level M_NVEBCL (§3.13.6.2.1)."""
    kwet_rst: StepFunction
    """Kwet_rst(V)."""
    t_brake_emergency_s: Fraction
    service_mps2: StepFunction
    """A_brake_service(V)."""
    t_brake_service_s: Fraction


@dataclass(frozen=True)
class BrakeCombination:
    """The Gamma brake models of one combination of active special brakes (§3.13.2.2.3.1.7, §3.13.2.2.3.2.8)."""

    active: frozenset[str]
    brakes: GammaBrakes


@dataclass(frozen=True)
class IntegratedFactors:
    """The national integrated correction factors of Lambda trains (§3.13.6.2.2, §3.13.6.3): Kv_int for
    passenger trains as the pair (a, b) per speed step with the pivots A_NVP12, A_NVP23 (for freight trains
    ``kv_int_b`` equals ``kv_int_a``, and the pivots are unused), Kr_int per train-length step (m), Kt_int."""

    kv_int_a: StepFunction
    kv_int_b: StepFunction
    a_nvp12_mps2: Fraction
    a_nvp23_mps2: Fraction
    kr_int_lengths_m: tuple[Fraction, ...]
    kr_int_values: tuple[Fraction, ...]
    kt_int: Fraction

    @classmethod
    def neutral(cls) -> IntegratedFactors:
        one = StepFunction.constant(1)
        return cls(one, one, Fraction(1), Fraction("1.3"), (Fraction(0),), (Fraction(1),), Fraction(1))


@dataclass(frozen=True)
class LambdaBrakes:
    """A brake percentage as train data (§3.13.2.2.5), with the national integrated correction factors."""

    brake_percentage: Fraction
    factors: IntegratedFactors


@dataclass(frozen=True)
class NormalServiceBrake:
    """The normal service brake of the guidance curve, as train data (§3.13.2.2.3.1.9-11, §3.13.2.2.9.2): up to two
    sets of three A_brake_normal_service(V) models, one for the brake position freight in G (``"G"``), one for
    passenger or freight in P (``"P"``); in a set, model 0, 1 or 2 by A_brake_service(V=0) against the pivots
    A_SB01 < A_SB12; the gradient corrections Kn+(V) (uphill) and Kn-(V) (downhill), m/s^2."""

    sets: dict[str, tuple[StepFunction, StepFunction, StepFunction]]
    a_sb01_mps2: Fraction
    a_sb12_mps2: Fraction
    kn_plus_mps2: StepFunction
    kn_minus_mps2: StepFunction


@dataclass(frozen=True)
class RailTrain:
    """A train as Subset-026 §3.13.2.2 describes it, for the braking curves."""

    name: str
    length_m: Fraction
    max_speed_kmh: Fraction
    brake_position: str
    brakes: GammaBrakes | LambdaBrakes
    t_traction_cut_off_s: Fraction
    service_brake_command: bool
    """§3.13.2.2.7: the on-board can command the service brake (else T_bs1 = T_bs2 = 0, §3.13.9.3.3)."""
    service_brake_feedback: bool
    """§3.13.2.2.7: the brake pressure is fed back (T_indication is then T_INDICATION_MIN_S, §3.13.9.3.6.2)."""
    traction_cut_off_command: bool
    """§3.13.2.2.8: the on-board can cut traction itself (before the EB command): T_traction is then what remains
    of T_traction_cut_off after the warning and the service brake's build-up (:func:`t_traction_s`)."""
    rotating_mass_percent: Fraction | None
    """M_rotating_nom, or None when not known (M_rotating_max uphill, M_rotating_min downhill, §3.13.4.2)."""
    max_acceleration_mps2: Fraction = Fraction(0)
    v_ura_mps: Fraction = Fraction(0)
    brake_combinations: tuple[BrakeCombination, ...] = ()
    """A Gamma train's models for other combinations of active special brakes; ``brakes`` is the one with none
    active (:func:`with_special_brakes` selects one)."""
    normal_service: NormalServiceBrake | None = None
    """The normal service brake of the guidance curve, or None when the train data gives none (no GUI)."""

    def __post_init__(self):
        if self.brake_position not in BRAKE_POSITIONS:
            raise TrainDataError(
                f"{self.name}: brake_position = {self.brake_position!r} is not one of {', '.join(BRAKE_POSITIONS)}"
            )


@dataclass(frozen=True)
class ConvertedBrakes:
    """The conversion model's outputs (§3.13.3)."""

    emergency_mps2: StepFunction
    service_mps2: StepFunction
    t_brake_emergency_cm0_s: Fraction
    t_brake_emergency_cmt_s: Fraction
    t_brake_service_cm0_s: Fraction
    t_brake_service_cmt_s: Fraction
    kto: Fraction


_COEFFICIENTS = (
    # (from km/h, (c0, c1, c2, c3)): AD_n = c0 + c1 * lambda + c2 * lambda^2 + c3 * lambda^3 (§3.13.3.3.3)
    (Fraction(0), None),
    (Fraction(100), ("0.13", "5.14e-3", "-4.54e-6", "2.73e-7")),
    (Fraction(120), ("0.0479", "5.81e-3", "-6.76e-6", "5.58e-8")),
    (Fraction(150), ("0.048", "5.52e-3", "-3.85e-6", "3e-8")),
    (Fraction(180), ("0.0559", "5.06e-3", "1.66e-6", "3.23e-9")),
)
_BELOW_100 = ("0.0663", "4.72e-3", "6.1e-5", "-6.3e-7")
"""The coefficients of the step from V_lim to 100 km/h (when V_lim < 100 km/h)."""


def _polynomial(coefficients, lam: Fraction) -> Fraction:
    return sum((Fraction(c) * lam**k for k, c in enumerate(coefficients)), Fraction(0))


def _deceleration_steps(lam: Fraction) -> StepFunction:
    """A_brake(V) from the brake percentage ``lam`` (§3.13.3.3.3): AD_0 below V_lim, then the polynomial steps.

    ``V_lim = 16.85 * lam^0.428`` km/h is irrational; it is taken as the exact value of its double."""
    v_lim = Fraction(16.85 * math.pow(float(lam), 0.428))
    steps = {Fraction(0): Fraction("0.0075") * lam + Fraction("0.076")}
    if v_lim < 100:
        steps[v_lim] = _polynomial(_BELOW_100, lam)
    for k, (start, coefficients) in enumerate(_COEFFICIENTS[1:], start=1):
        end = _COEFFICIENTS[k + 1][0] if k + 1 < len(_COEFFICIENTS) else None
        if start >= v_lim:
            steps[start] = _polynomial(coefficients, lam)
        elif end is None or v_lim < end:  # V_lim inside this range: the range's deceleration from V_lim
            steps[v_lim] = _polynomial(coefficients, lam)
    ordered = sorted(steps)
    return StepFunction(tuple(ordered), tuple(steps[s] for s in ordered))


_BUILD_UP = {
    # brake position: ((a, b, c) up to 900 m, (a, b, c) above, the least length used up to 900 m)
    # T_brake_basic = a + b * (L / 100) + c * (L / 100)^2 (§3.13.3.4, A.3.8, A.3.9)
    "emergency": {
        "passenger_P": (("2.30", "0", "0.17"), None, 400),
        "freight_P": (("2.30", "0", "0.17"), ("-0.4", "1.6", "0.03"), 400),
        "freight_G": (("12.0", "0", "0.05"), ("-0.4", "1.6", "0.03"), 0),
    },
    "service": {
        "passenger_P": (("3.00", "1.5", "0.1"), None, 0),
        "freight_P": (("3.00", "2.77", "0"), ("10.5", "0.32", "0.18"), 0),
        "freight_G": (("3.00", "2.77", "0"), ("10.5", "0.32", "0.18"), 400),
    },
}
_CT = {"passenger_P": Fraction("0.20"), "freight_P": Fraction("0.20"), "freight_G": Fraction("0.16")}
"""C_t per brake position: kto = 1 + C_t (§3.13.3.4)."""

CONVERSION_LIMITS = {
    "brake_percentage": (Fraction(30), Fraction(250)),
    "max_speed_kmh": Fraction(200),
    "length_m": {"passenger_P": Fraction(900), "freight_P": Fraction(1500), "freight_G": Fraction(1500)},
}
"""§3.13.3.2: where the conversion model may be used."""


def _build_up_s(kind: str, position: str, length_m: Fraction) -> Fraction:
    up_to_900, above_900, least_m = _BUILD_UP[kind][position]
    short = length_m <= 900  # the conversion model refuses a passenger train above 900 m
    a, b, c = map(Fraction, up_to_900 if short else above_900)
    el = max(length_m, Fraction(least_m)) if short else length_m
    return a + b * (el / 100) + c * (el / 100) ** 2


def conversion_model(brake_percentage, brake_position: str, length_m, max_speed_kmh) -> ConvertedBrakes:
    """§3.13.3: the brake models of a train given by its brake percentage; outside the validity limits of
    §3.13.3.2 the model must not be used, and :class:`~atcs.model.train_data.TrainDataError` names the limit."""
    lam, length_m, max_speed_kmh = Fraction(brake_percentage), Fraction(length_m), Fraction(max_speed_kmh)
    low, high = CONVERSION_LIMITS["brake_percentage"]
    if not low <= lam <= high:
        raise TrainDataError(
            f"brake_percentage = {float(lam):g} is outside [{low}, {high}]: the conversion model does not apply "
            "(§3.13.3.2); give the brake models (a Gamma train)"
        )
    if max_speed_kmh > CONVERSION_LIMITS["max_speed_kmh"]:
        raise TrainDataError(
            f"max_speed_kmh = {float(max_speed_kmh):g} is above {CONVERSION_LIMITS['max_speed_kmh']}: the conversion "
            "model does not apply (§3.13.3.2)"
        )
    longest = CONVERSION_LIMITS["length_m"].get(brake_position)
    if longest is None:
        raise TrainDataError(f"brake_position = {brake_position!r} is not one of {', '.join(BRAKE_POSITIONS)}")
    if length_m > longest:
        raise TrainDataError(
            f"length_m = {float(length_m):g} is above {longest} for {brake_position}: the conversion model does not "
            "apply (§3.13.3.2)"
        )
    kto = 1 + _CT[brake_position]
    t_eb, t_sb = _build_up_s("emergency", brake_position, length_m), _build_up_s("service", brake_position, length_m)
    return ConvertedBrakes(
        emergency_mps2=_deceleration_steps(lam),
        service_mps2=_deceleration_steps(min(lam, Fraction(135))),
        t_brake_emergency_cm0_s=t_eb,
        t_brake_emergency_cmt_s=kto * t_eb,
        t_brake_service_cm0_s=t_sb,
        t_brake_service_cmt_s=kto * t_sb,
        kto=kto,
    )


def _kv_int(train: RailTrain, factors: IntegratedFactors, a_ebmax: Fraction) -> StepFunction:
    """Kv_int(V): for passenger trains each step interpolated between a and b by A_ebmax (§3.13.6.2.2)."""
    if train.brake_position != "passenger_P":
        return factors.kv_int_a
    p12, p23 = factors.a_nvp12_mps2, factors.a_nvp23_mps2
    steps = tuple(sorted(set(factors.kv_int_a.speeds_kmh) | set(factors.kv_int_b.speeds_kmh)))
    values = []
    for s in steps:
        a, b = factors.kv_int_a.at(s), factors.kv_int_b.at(s)
        if a_ebmax <= p12:
            values.append(a)
        elif a_ebmax >= p23:
            values.append(b)
        else:
            values.append(a + (a_ebmax - p12) / (p23 - p12) * (b - a))
    return StepFunction(steps, tuple(values))


def _kr_int(factors: IntegratedFactors, length_m: Fraction) -> Fraction:
    return next(
        v
        for s, v in zip(reversed(factors.kr_int_lengths_m), reversed(factors.kr_int_values), strict=True)
        if s <= length_m
    )


def with_special_brakes(train: RailTrain, active) -> RailTrain:
    """``train`` with the brake models of the special brakes ``active`` (the others not active, §3.13.2.2.6.2):
    ``brakes`` for none; otherwise the combination its data declares for exactly these, refused if it declares
    none (Subset-026 does not say which models apply to a combination without data)."""
    active = frozenset(active)
    unknown = sorted(active - set(SPECIAL_BRAKES))
    if unknown:
        raise TrainDataError(f"{train.name}: special brake {unknown[0]!r} is not one of {', '.join(SPECIAL_BRAKES)}")
    if not active:
        return train
    found = [c for c in train.brake_combinations if c.active == active]
    if not found:
        declared = "; ".join(", ".join(sorted(c.active)) for c in train.brake_combinations) or "none"
        raise TrainDataError(
            f"{train.name}: no brake models for the special brakes {', '.join(sorted(active))} active "
            f"(combinations declared: {declared})"
        )
    return dataclasses.replace(train, brakes=found[0].brakes, brake_combinations=())


def _brakes(train: RailTrain, m_nvavadh: Fraction, target_speed_kmh) -> tuple[StepFunction, Fraction, Fraction]:
    """``(A_brake_safe(V) without the gradient, T_be, T_bs)`` for a target of ``target_speed_kmh``."""
    brakes = train.brakes
    if isinstance(brakes, GammaBrakes):
        k = brakes.kdry_rst.times(
            StepFunction(brakes.kwet_rst.speeds_kmh, tuple(w + m_nvavadh * (1 - w) for w in brakes.kwet_rst.values))
        )
        return brakes.emergency_mps2.times(k), brakes.t_brake_emergency_s, brakes.t_brake_service_s
    converted = conversion_model(brakes.brake_percentage, train.brake_position, train.length_m, train.max_speed_kmh)
    factors = brakes.factors
    a_ebmax = max(converted.emergency_mps2.values)
    kv = _kv_int(train, factors, a_ebmax)
    safe = converted.emergency_mps2.times(kv).times(StepFunction.constant(_kr_int(factors, train.length_m)))
    stopping = target_speed_kmh == 0  # §3.13.3.4.3: cm0 for a target at standstill, cmt otherwise
    t_be = factors.kt_int * (converted.t_brake_emergency_cm0_s if stopping else converted.t_brake_emergency_cmt_s)
    t_bs = converted.t_brake_service_cm0_s if stopping else converted.t_brake_service_cmt_s
    return safe, t_be, t_bs


def _service_mps2(train: RailTrain) -> StepFunction:
    """A_brake_service(V): the Gamma train's, or the conversion model's for a Lambda train."""
    if isinstance(train.brakes, GammaBrakes):
        return train.brakes.service_mps2
    b = train.brakes
    return conversion_model(b.brake_percentage, train.brake_position, train.length_m, train.max_speed_kmh).service_mps2


def guidance_data(train: RailTrain) -> GuidanceData | None:
    """The normal service brake of ``train``'s guidance curve in SI on one set of speed steps (the union of the
    model's, Kn+'s and Kn-'s), or None without one. The set is the brake position's; in it the model is 0 when
    ``A_brake_service(V=0) <= A_SB01``, 1 up to A_SB12, 2 above (§3.13.2.2.3.1.10; the active special brakes are
    those whose models ``train`` carries, :func:`with_special_brakes`)."""
    normal = train.normal_service
    if normal is None:
        return None
    group = "G" if train.brake_position == "freight_G" else "P"
    if group not in normal.sets:
        raise TrainDataError(
            f"{train.name}: normal_service gives no models for the brake position {train.brake_position}"
        )
    a0 = _service_mps2(train).at(0)
    model = normal.sets[group][0 if a0 <= normal.a_sb01_mps2 else 1 if a0 <= normal.a_sb12_mps2 else 2]
    steps = sorted(set(model.speeds_kmh) | set(normal.kn_plus_mps2.speeds_kmh) | set(normal.kn_minus_mps2.speeds_kmh))
    return GuidanceData(
        normal_service_speeds_mps=tuple(v / KMH_PER_MPS for v in steps),
        normal_service_decelerations_mps2=tuple(model.at(v) for v in steps),
        kn_plus_mps2=tuple(normal.kn_plus_mps2.at(v) for v in steps),
        kn_minus_mps2=tuple(normal.kn_minus_mps2.at(v) for v in steps),
    )


def t_traction_s(train: RailTrain, national: NationalData, t_bs2_s: Fraction) -> Fraction:
    """§3.13.9.3.2: ``max(T_traction_cut_off - (T_warning + T_bs2), 0)`` with a traction cut-off command,
    ``T_traction_cut_off`` without."""
    if not train.traction_cut_off_command:
        return train.t_traction_cut_off_s
    return max(train.t_traction_cut_off_s - (national.t_warning_s + t_bs2_s), Fraction(0))


def t_indication_s(train: RailTrain, t_bs_s: Fraction) -> Fraction:
    """§3.13.9.3.6.2: ``max(0.8 * T_bs, 5 s)`` without service-brake feedback, 5 s with it."""
    return T_INDICATION_MIN_S if train.service_brake_feedback else max(Fraction(4, 5) * t_bs_s, T_INDICATION_MIN_S)


def curve_train_data(train: RailTrain, national: NationalData, target_speed_kmh) -> TrainData:
    """The :class:`~atcs.model.train_data.TrainData` of ``train`` for a target of ``target_speed_kmh``:
    ``A_brake_safe`` as the emergency steps (module docstring), T_be, and T_bs2 as ``t_bs_s`` (0 without a
    service-brake command, §3.13.9.3.3)."""
    safe, t_be, t_bs = _brakes(train, national.m_nvavadh, Fraction(target_speed_kmh))
    service = _service_mps2(train)
    rotating = train.rotating_mass_percent
    t_bs2 = t_bs if train.service_brake_command else Fraction(0)
    return TrainData(
        train_length_m=train.length_m,
        max_acceleration_mps2=train.max_acceleration_mps2,
        emergency_speeds_mps=tuple(s / KMH_PER_MPS for s in safe.speeds_kmh),
        emergency_decelerations_mps2=safe.values,
        service_speeds_mps=tuple(s / KMH_PER_MPS for s in service.speeds_kmh),
        service_decelerations_mps2=service.values,
        kdry_rst=Fraction(1),
        kwet_rst=Fraction(1),
        rotating_mass_uphill_percent=Fraction(15) if rotating is None else rotating,
        rotating_mass_downhill_percent=Fraction(2) if rotating is None else rotating,
        t_be_s=t_be,
        t_bs_s=t_bs2,
        t_traction_s=t_traction_s(train, national, t_bs2),
        v_ura_mps=train.v_ura_mps,
    )


def curve_national_data(train: RailTrain, national: NationalData, target_speed_kmh) -> NationalData:
    """``national`` with ``t_indication_s`` by the rule of §3.13.9.3.6.2 for ``train`` (it depends on the
    train's T_bs, not on a national value)."""
    _, _, t_bs = _brakes(train, national.m_nvavadh, Fraction(target_speed_kmh))
    return dataclasses.replace(national, t_indication_s=t_indication_s(train, t_bs))
