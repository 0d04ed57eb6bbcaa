"""A train data file (TOML): a train as Subset-026 §3.13.2 describes it, Gamma or Lambda, with its interfaces
(docs/train-data.md is the reference: every key, its unit, default and range).

Every error names the file, the field and the value (:class:`~atcs.model.train_data.TrainDataError`).
"""

from __future__ import annotations

import itertools
from fractions import Fraction
from pathlib import Path

from atcs.model.braking_data import (
    BRAKE_POSITIONS,
    DEPENDS_ON,
    SPECIAL_BRAKES,
    BrakeCombination,
    GammaBrakes,
    IntegratedFactors,
    LambdaBrakes,
    NormalServiceBrake,
    RailTrain,
    StepFunction,
    conversion_model,
)
from atcs.model.data_files import TableReader, read_toml
from atcs.model.profile import KMH_PER_MPS, MAX_SPEED_KMH
from atcs.model.train_data import MAX_BUILD_UP_S, TrainDataError

__all__ = ["FIELDS", "load_train", "shipped_trains"]

MAX_LENGTH_M = 4095
"""The longest train (m): the range of L_TRAIN (Subset-026 Appendix A.3.11); a Lambda train is held to the
conversion model's own limits too (§3.13.3.2.1: 900 m in passenger P, 1,500 m in freight)."""
MAX_DECELERATION_MPS2 = 5
"""The highest brake deceleration accepted (m/s^2): above any adhesion-limited train brake."""
MAX_ACCELERATION_MPS2 = 5
MAX_TIME_S = MAX_BUILD_UP_S

FIELDS = {
    "": (
        "name",
        "length_m",
        "max_speed_kmh",
        "brake_position",
        "t_traction_cut_off_s",
        "rotating_mass_percent",
        "max_acceleration_mps2",
        "v_ura_kmh",
        "interfaces",
        "gamma",
        "lambda",
        "normal_service",
    ),
    "interfaces": ("service_brake_command", "service_brake_feedback", "traction_cut_off_command"),
    "gamma": (
        "t_brake_emergency_s",
        "t_brake_service_s",
        "emergency",
        "service",
        "kdry_rst",
        "kwet_rst",
        "combination",
    ),
    "gamma.combination": (
        "active",
        "t_brake_emergency_s",
        "t_brake_service_s",
        "emergency",
        "service",
        "kdry_rst",
        "kwet_rst",
    ),
    "normal_service": ("a_sb01_mps2", "a_sb12_mps2", "kn_plus", "kn_minus", "p", "g"),
    "normal_service.p": ("model_0", "model_1", "model_2"),
    "normal_service.g": ("model_0", "model_1", "model_2"),
    "lambda": ("brake_percentage", "kv_int", "a_nvp12_mps2", "a_nvp23_mps2", "kr_int", "kt_int"),
}
"""The fields of each table of a train data file (docs/train-data.md documents each)."""


class _Reader(TableReader):
    error = TrainDataError

    def bounded(self, key: str, low, high, default=None, *, low_open: bool = False) -> Fraction:
        value = self.number(key, default)
        if value < low or value > high or (low_open and value == low):
            shown = f"({low}, {high}]" if low_open else f"[{low}, {high}]"
            self.fail(key, f"is outside {shown}")
        return value

    def flag(self, key: str, default: bool) -> bool:
        value = self.table.get(key, default)
        if not isinstance(value, bool):
            self.fail(key, "must be true or false")
        return value


def _steps(
    source: str, reader: _Reader, key: str, value_key: str, high, *, max_steps: int = 7, zero: bool = False
) -> StepFunction:
    """``[{from_kmh = 0, <value_key> = ...}, ...]``: a step function of speed, up to seven steps (§3.13.2.2.3.1.2;
    ``max_steps`` for others), values in (0, high] (``zero``: [0, high])."""
    rows = reader.rows(key)
    if not 1 <= len(rows) <= max_steps:
        reader.fail(key, f"must be a list of 1 to {max_steps} steps")
    speeds, values = [], []
    for k, row in enumerate(rows):
        r = _Reader(source, row, f"{reader.name(key)}[{k}]", ("from_kmh", value_key))
        speeds.append(r.bounded("from_kmh", 0, MAX_SPEED_KMH))
        values.append(r.bounded(value_key, 0, high, low_open=not zero))
    if speeds[0] != 0 or any(a >= b for a, b in itertools.pairwise(speeds)):
        reader.fail(key, "must start at from_kmh = 0 with increasing from_kmh")
    return StepFunction(tuple(speeds), tuple(values))


def _gamma(source: str, table) -> tuple[GammaBrakes, tuple[BrakeCombination, ...]]:
    """The models with no special brake active, and each ``[[gamma.combination]]``'s: the keys it gives (each one
    Table 4 makes depend on one of its active brakes), the rest as with none active."""
    r = _Reader(source, table, "gamma", FIELDS["gamma"])
    one = [{"from_kmh": 0, "value": 1}]
    for key in ("kdry_rst", "kwet_rst"):
        if key not in r.table:
            r.table = {**r.table, key: one}
    base = _gamma_brakes(source, r)
    combinations, seen = [], set()
    for k, row in enumerate(r.rows("combination")):
        c = _Reader(source, row, f"gamma.combination[{k}]", FIELDS["gamma.combination"])
        active = c.table.get("active")
        if (
            not isinstance(active, list)
            or not active
            or any(b not in SPECIAL_BRAKES for b in active)
            or len(set(active)) != len(active)
        ):
            c.fail("active", f"must list distinct special brakes among {', '.join(SPECIAL_BRAKES)}")
        active = frozenset(active)
        if active in seen:
            c.fail("active", "repeats an earlier combination")
        seen.add(active)
        for key in FIELDS["gamma.combination"][1:]:
            if key in c.table and not DEPENDS_ON[key] & active:
                c.fail(key, f"does not depend on {', '.join(sorted(active))} (Subset-026 §3.13.2.2.6.2 Table 4)")
        c.table = {**{key: value for key, value in r.table.items() if key != "combination"}, **c.table}
        combinations.append(BrakeCombination(active, _gamma_brakes(source, c)))
    return base, tuple(combinations)


def _gamma_brakes(source: str, r: _Reader) -> GammaBrakes:
    return GammaBrakes(
        emergency_mps2=_steps(source, r, "emergency", "mps2", MAX_DECELERATION_MPS2),
        kdry_rst=_steps(source, r, "kdry_rst", "value", 1),
        kwet_rst=_steps(source, r, "kwet_rst", "value", 1),
        t_brake_emergency_s=r.bounded("t_brake_emergency_s", 0, MAX_TIME_S, low_open=True),
        service_mps2=_steps(source, r, "service", "mps2", MAX_DECELERATION_MPS2),
        t_brake_service_s=r.bounded("t_brake_service_s", 0, MAX_TIME_S, low_open=True),
    )


MAX_KN_MPS2 = 10
"""Kn+(V), Kn-(V) range from 0 to 10 m/s^2 (Subset-026 §3.13.2.2.9.2.1), up to five steps (§3.13.2.2.9.2.2)."""


def _normal_service(source: str, table, brake_position: str) -> NormalServiceBrake:
    """``[normal_service]``: the pivots, Kn+ and Kn-, and ``[normal_service.p]`` / ``[normal_service.g]`` with the
    set's three models (at least the set of the train's brake position)."""
    r = _Reader(source, table, "normal_service", FIELDS["normal_service"])
    a_sb01 = r.bounded("a_sb01_mps2", 0, MAX_DECELERATION_MPS2)
    a_sb12 = r.bounded("a_sb12_mps2", 0, MAX_DECELERATION_MPS2)
    if not a_sb01 < a_sb12:
        r.fail("a_sb12_mps2", f"must be above a_sb01_mps2 = {float(a_sb01):g}")
    sets = {}
    for group in ("p", "g"):
        if group in r.table:
            c = _Reader(source, r.table[group], f"normal_service.{group}", FIELDS[f"normal_service.{group}"])
            sets[group.upper()] = tuple(
                _steps(source, c, f"model_{m}", "mps2", MAX_DECELERATION_MPS2) for m in range(3)
            )
    needed = "g" if brake_position == "freight_G" else "p"
    if needed.upper() not in sets:
        r.fail(needed, f"is missing: brake_position = {brake_position!r} uses the models of [normal_service.{needed}]")
    return NormalServiceBrake(
        sets=sets,
        a_sb01_mps2=a_sb01,
        a_sb12_mps2=a_sb12,
        kn_plus_mps2=_steps(source, r, "kn_plus", "mps2", MAX_KN_MPS2, max_steps=5, zero=True),
        kn_minus_mps2=_steps(source, r, "kn_minus", "mps2", MAX_KN_MPS2, max_steps=5, zero=True),
    )


def _kv_int(source: str, r: _Reader, brake_position: str) -> tuple[StepFunction, StepFunction]:
    """``kv_int = [{from_kmh = 0, a = ..., b = ...}, ...]``: the national Kv_int(V) (§3.13.6.2.2), a and b per step
    for a passenger train (interpolated by A_ebmax between the pivots), ``a`` alone for a freight train."""
    passenger = brake_position == "passenger_P"
    rows = r.rows("kv_int")
    if not 1 <= len(rows) <= 7:
        r.fail("kv_int", "must be a list of 1 to 7 steps")
    speeds, a, b = [], [], []
    for k, row in enumerate(rows):
        c = _Reader(source, row, f"lambda.kv_int[{k}]", ("from_kmh", "a", "b") if passenger else ("from_kmh", "a"))
        speeds.append(c.bounded("from_kmh", 0, MAX_SPEED_KMH))
        a.append(c.bounded("a", 0, 1, low_open=True))
        b.append(c.bounded("b", 0, 1, low_open=True) if passenger else a[-1])
    if speeds[0] != 0 or any(x >= y for x, y in itertools.pairwise(speeds)):
        r.fail("kv_int", "must start at from_kmh = 0 with increasing from_kmh")
    return StepFunction(tuple(speeds), tuple(a)), StepFunction(tuple(speeds), tuple(b))


def _lambda(source: str, table, brake_position: str) -> LambdaBrakes:
    r = _Reader(source, table, "lambda", FIELDS["lambda"])
    neutral = IntegratedFactors.neutral()
    kv_a, kv_b = _kv_int(source, r, brake_position) if "kv_int" in r.table else (neutral.kv_int_a, neutral.kv_int_b)
    p12 = r.bounded("a_nvp12_mps2", 0, MAX_DECELERATION_MPS2, neutral.a_nvp12_mps2)
    p23 = r.bounded("a_nvp23_mps2", 0, MAX_DECELERATION_MPS2, neutral.a_nvp23_mps2)
    if not p12 < p23:  # name the pivot the file gives (both given: the upper one)
        if "a_nvp23_mps2" in r.table:
            r.fail("a_nvp23_mps2", f"must be above a_nvp12_mps2 = {float(p12):g}")
        r.fail("a_nvp12_mps2", f"must be below a_nvp23_mps2 = {float(p23):g}")
    return LambdaBrakes(
        brake_percentage=r.number("brake_percentage"),
        factors=IntegratedFactors(
            kv_int_a=kv_a,
            kv_int_b=kv_b,
            a_nvp12_mps2=p12,
            a_nvp23_mps2=p23,
            kr_int_lengths_m=neutral.kr_int_lengths_m,
            kr_int_values=(r.bounded("kr_int", 0, 1, 1, low_open=True),),
            kt_int=r.bounded("kt_int", 1, 2, 1),
        ),
    )


def load_train(path: str | Path) -> RailTrain:
    """The train of the TOML file at ``path``; a Lambda train is checked against the conversion model's validity
    limits here, so that a refusal names the file."""
    source = str(path)
    doc = read_toml(path, TrainDataError, "the train data")
    top = _Reader(source, doc, "", FIELDS[""])
    kinds = [k for k in ("gamma", "lambda") if k in doc]
    if len(kinds) != 1:
        raise TrainDataError(f"{source}: give exactly one of [gamma] (brake models) or [lambda] (brake percentage)")
    interfaces = _Reader(source, doc.get("interfaces", {}), "interfaces", FIELDS["interfaces"])
    rotating = top.optional_number("rotating_mass_percent")
    if rotating is not None and not 0 <= rotating <= 50:
        top.fail("rotating_mass_percent", "is outside [0, 50]")
    brakes, combinations = (
        _gamma(source, doc["gamma"])
        if kinds == ["gamma"]
        else (_lambda(source, doc["lambda"], top.table.get("brake_position")), ())
    )
    train = RailTrain(
        name=top.text("name"),
        length_m=top.bounded("length_m", 0, MAX_LENGTH_M, low_open=True),
        max_speed_kmh=top.bounded("max_speed_kmh", 0, MAX_SPEED_KMH, low_open=True),
        brake_position=top.text("brake_position", choices=BRAKE_POSITIONS),
        brakes=brakes,
        t_traction_cut_off_s=top.bounded("t_traction_cut_off_s", 0, MAX_TIME_S, 0),
        service_brake_command=interfaces.flag("service_brake_command", False),
        service_brake_feedback=interfaces.flag("service_brake_feedback", False),
        traction_cut_off_command=interfaces.flag("traction_cut_off_command", False),
        rotating_mass_percent=rotating,
        max_acceleration_mps2=top.bounded("max_acceleration_mps2", 0, MAX_ACCELERATION_MPS2, 0),
        v_ura_mps=top.bounded("v_ura_kmh", 0, 20, 0) / KMH_PER_MPS,
        brake_combinations=combinations,
        normal_service=None
        if "normal_service" not in doc
        else _normal_service(source, doc["normal_service"], top.table.get("brake_position")),
    )
    if isinstance(train.brakes, LambdaBrakes):
        try:
            conversion_model(train.brakes.brake_percentage, train.brake_position, train.length_m, train.max_speed_kmh)
        except TrainDataError as exc:
            raise TrainDataError(f"{source}: {exc}") from None
    return train


def shipped_trains() -> dict[str, Path]:
    """The train data files shipped with atcs (``model/trains``), by name."""
    return {p.stem: p for p in sorted((Path(__file__).parent / "trains").glob("*.toml"))}
