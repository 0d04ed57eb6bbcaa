"""Headway at a steady speed (seed 001 §3.2 Fig. 6, seed 000 §2.4-2.5): the least gap (front of the
follower to rear of the leader) at which a follower can run at its leader's steady speed, in relative-braking and
brick-wall modes, three ways:

- ``invariant``: the least gap for which the proved separation invariant (SEP-01 of
  :mod:`atcs.properties.separation`) holds of a follower at that speed, not braking, behind a leader at the same
  speed whose latest report is its true state. This is the physics only: full traction until the cut-off, coasting
  through the brake build-up, then the guaranteed deceleration to a stop at the leader's rear (brick wall) or at
  its earliest stopping point (relative braking), less the safety margin. No supervision curve, no position error.
- ``atp``: the least gap at which the follower's ATP lets it keep running at that speed: its max safe front
  (position error added) not past its indication point (where the simulator's ATO brakes), against the end of
  authority :mod:`atcs.model.authority` derives from the leader's report (min safe rear, min speed). The curves
  add the EBI's speed and acceleration terms and the SBI, warning, permitted and indication times to the physics.
  The route's resources are not counted; ``details`` has every curve's figure, the ATO's (seed 003 target speed)
  and the same with the end of authority route-locked at the leader's min safe rear.
- ``measured``: the steady-state gap of the closed-loop simulator (:class:`~atcs.sim.simulator.Simulation`). Its
  follower's end of authority also stops at the first resource the leader still holds, so the relative-braking
  credit is lost and up to one ``resource_length_m`` of granularity is added.

Headway time is ``(gap + train length) / speed``. Both theoretical figures are computed on exact numbers with the
model's own functions (nothing re-derived here), on the data the simulator uses for the same scenario.
"""

from __future__ import annotations

import dataclasses
import itertools
import tempfile
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any

from atcs.model.ato import FAR, ato_target_speed
from atcs.model.authority import AuthorityInputs, AuthorityState, leader_limit_m, leader_reports, stopping_point_m
from atcs.model.closed_loop import whole_cycles, worst_acceleration_mps2, worst_case_at_brake
from atcs.model.curves import FAR_M, Target, ebd_location_m
from atcs.model.dynamic_profile import CURVE_NAMES, Horizon, supervise_position
from atcs.model.errors import AtcsInputError
from atcs.model.node import as_dict
from atcs.model.numbers import exact_number
from atcs.model.ops.exact import EXACT
from atcs.model.plant import plant_gradient
from atcs.model.position import odometry_interval, speed_accuracy_mps
from atcs.model.profile import KMH_PER_MPS, Profile
from atcs.model.psl import extend_by_train_length
from atcs.model.separation import TwoTrainParams, TwoTrainState, earliest_stop_m
from atcs.model.train_data import TrainData, preset_data
from atcs.sim.ato_driver import ATO_LOOKAHEAD_S
from atcs.sim.scenario import PRESETS, Scenario, load_scenario
from atcs.sim.simulator import Simulation

MODES = {"relative_braking": "rbd", "brick_wall": "bw"}
"""The scenario's ``[atp] mode`` names and the separation properties' (``rbd``, ``bw``); either is accepted."""
GAP_TOLERANCE_M = Fraction(1, 1000)
"""The ATP-limited gaps are bisected to this (m) and rounded up to it."""
SEARCH_TOP_M = Fraction(10_000)
"""The first upper end of the gap searched (m), doubled while no gap up to it satisfies the limit."""
SEARCH_LIMIT_M = Fraction(160_000)
"""The largest gap searched (m): four doublings, above any braking distance at the highest speed limit."""
TAG_SPACING_M = 100
"""Seed 000 §2.5: a tag every 100 m."""
LEADER_FRONT_M = 500
"""The leader's front at power-up; the follower powers up on the tag one spacing behind the leader's rear."""
CYCLE_S = Fraction(1, 10)
"""The scenario's ATP cycle (seed 001: 100 ms)."""
TAG_WINDOW_M = Fraction(5, 2)
"""The scenario's default ``atp.tag_window_m``: how far from a tag the reader may place its passage."""
LOWEST_STEADY_KMH = Fraction(65)
"""The lowest speed at which :func:`measured_minimum`, with its defaults, settles in both modes (measured: 65 km/h
does, 62 and 60 km/h do not): below it the follower, held back by its leader, dips more than
``speed_tolerance_kmh`` under the speed within the settling window."""
RUN_S = 200
"""A closed-loop measurement runs this long (s) by default."""


HIGHEST_KMH = Fraction(350)
"""The highest speed :func:`headway_report` runs at: the position holds at any speed (tags are read with the
odometer reading at their passage), and the measurement, with :func:`run_options`, settles up to here."""


def speed_range_kmh() -> tuple[Fraction, Fraction]:
    """The least and the greatest speed (km/h, both included) :func:`headway_report` runs at: from
    :data:`LOWEST_STEADY_KMH` to :data:`HIGHEST_KMH`."""
    return LOWEST_STEADY_KMH, HIGHEST_KMH


def run_options(speed_kmh) -> dict:
    """:func:`measured_minimum`'s defaults for ``speed_kmh``, scaled above 80 km/h by ``f = speed / 80``: the run
    ``f`` times longer (the trains take longer to reach the speed), the most authority ``f^2`` times larger (braking
    distances grow with the square of the speed), resources ``f`` times longer (a similar number in the window),
    the gap's and the speeds' settling tolerances ``f`` times wider (the follower's sawtooth grows with the run of a
    cycle)."""
    f = max(Fraction(1), _number("speed_kmh", speed_kmh) / 80)
    return {
        "duration_s": RUN_S * f,
        "max_ma_m": 1500 * f * f,
        "resource_length_m": 50 * f,
        "settle_m": 5 * f,
        "speed_tolerance_kmh": Fraction(5, 2) * f,
    }


class HeadwayError(AtcsInputError):
    """A bad argument (named, with its value), or a run that reaches no steady state."""


@dataclass(frozen=True)
class HeadwayFigure:
    """One headway figure at one speed and mode (module docstring for the three ``kind`` values)."""

    mode: str
    """``relative_braking`` or ``brick_wall``."""
    kind: str
    """``invariant``, ``atp`` or ``measured``."""
    speed_kmh: float
    gap_m: float
    """Front of the follower to rear of the leader."""
    headway_s: float
    """``(gap_m + train_length_m) / speed``."""
    train_length_m: float
    exact_gap_m: Fraction | None = None
    """A theoretical figure's exact gap (None for a measurement)."""
    details: Mapping[str, Any] = field(default_factory=dict)
    """What else the figure depends on or explains (data used, per-curve gaps, the run's window and spread)."""


def _mode(mode) -> str:
    """The scenario's name of ``mode``."""
    for name, short in MODES.items():
        if mode in (name, short):
            return name
    raise HeadwayError(f"mode must be one of {', '.join((*MODES, *MODES.values()))}, got {mode!r}")


def _number(name: str, value, *, zero_ok: bool = False) -> Fraction:
    """``value`` as an exact number, positive (or >= 0 with ``zero_ok``); a float as the decimal it prints as."""
    expected = "a number >= 0" if zero_ok else "a positive number"
    try:
        exact = exact_number(value)
    except ValueError:
        raise HeadwayError(f"{name} must be {expected}, got {value!r}") from None
    if exact < 0 or (exact == 0 and not zero_ok):
        raise HeadwayError(f"{name} must be {expected}, got {value!r}")
    return exact


def _figure(mode: str, kind: str, speed_kmh: Fraction, gap_m, length_m, exact=None, **details) -> HeadwayFigure:
    speed_mps = speed_kmh / KMH_PER_MPS
    headway = (Fraction(gap_m) + Fraction(length_m)) / speed_mps
    return HeadwayFigure(
        mode=mode,
        kind=kind,
        speed_kmh=float(speed_kmh),
        gap_m=float(gap_m),
        headway_s=float(headway),
        train_length_m=float(length_m),
        exact_gap_m=exact,
        details=details,
    )


# --- the scenario both the theory and the measurement use ---------------------------------------------------------


def _toml_number(x) -> str:
    x = Fraction(x)
    return str(x.numerator) if x.denominator == 1 else repr(float(x))


def scenario_text(
    mode: str,
    speed_kmh=80,
    *,
    resource_length_m=50,
    duration_s=200,
    follower_depart_s=0,
    safety_margin_m=20,
    report_timeout_s=2,
    tag_window_m=TAG_WINDOW_M,
    tacho_error="0.01",
    max_ma_m=1500,
    planning_decel_kmhps="1.5",
    ato_margin_m=30,
    preset: str = "seed000",
) -> str:
    """A scenario (the TOML of ``sim/scenarios/seed000_slow_leader.toml``, seed 000 §2.5): a level line limited to
    ``speed_kmh``, tags every 100 m, two trains of ``preset``, the follower powered up on the tag one spacing
    behind the leader's rear and departing ``follower_depart_s`` after it."""
    mode = _mode(mode)
    speed, duration = _number("speed_kmh", speed_kmh), _number("duration_s", duration_s)
    for name, value in (
        ("resource_length_m", resource_length_m),
        ("max_ma_m", max_ma_m),
        ("report_timeout_s", report_timeout_s),
        ("planning_decel_kmhps", planning_decel_kmhps),
    ):
        _number(name, value)
    depart = _number("follower_depart_s", follower_depart_s, zero_ok=True)
    if not depart < duration:
        raise HeadwayError(f"follower_depart_s must lie in [0, duration_s = {duration}), got {follower_depart_s!r}")
    if preset not in PRESETS:
        raise HeadwayError(f"preset must be one of {', '.join(PRESETS)}, got {preset!r}")
    follower_front = LEADER_FRONT_M - PRESETS[preset]().train_length_m - TAG_SPACING_M
    run_m = LEADER_FRONT_M + speed / KMH_PER_MPS * duration + Fraction(max_ma_m)  # the leader never sees the end
    line_m = (int(run_m) // TAG_SPACING_M + 1) * TAG_SPACING_M
    n = _toml_number
    trains = "".join(
        f'\n[[trains]]\nname = "{name}"\npreset = "{preset}"\nfront_m = {n(front)}\nmax_speed_kmh = {n(speed)}\n'
        f"depart_s = {n(dep)}\n"
        for name, front, dep in (("leader", LEADER_FRONT_M, 0), ("follower", follower_front, depart))
    )
    return "\n".join(
        (
            f'name = "headway_{mode}"',
            'seed = "001 §3.2, 000 §2.5"',
            f'description = "A leader at {n(speed)} km/h and a follower right behind it: the steady-state headway."',
            f"duration_s = {n(duration)}",
            f"cycle_s = {n(CYCLE_S)}",
            "",
            "[line]",
            f"length_m = {line_m}",
            f"tag_spacing_m = {TAG_SPACING_M}",
            f"resource_length_m = {n(resource_length_m)}",
            f"max_ma_m = {n(max_ma_m)}",
            f"speed_limits = [{{ start_m = 0, kmh = {n(speed)} }}]",
            "",
            "[atp]",
            f'mode = "{mode}"',
            f"safety_margin_m = {n(safety_margin_m)}",
            f"report_timeout_s = {n(report_timeout_s)}",
            f"tag_window_m = {n(tag_window_m)}",
            f"tacho_error = {n(tacho_error)}",
            "",
            "[ato]",
            f"planning_decel_kmhps = {n(planning_decel_kmhps)}",
            f"margin_m = {n(ato_margin_m)}",
            trains,
        )
    )


def headway_scenario(mode: str, speed_kmh=80, *, follower_data: TrainData | None = None, **options) -> Scenario:
    """:func:`scenario_text` (``options``) written to a temporary file and read by
    :func:`~atcs.sim.scenario.load_scenario`; ``follower_data`` replaces the follower's train data."""
    with tempfile.TemporaryDirectory(prefix="atcs-headway-") as folder:
        path = Path(folder) / f"headway_{_mode(mode)}.toml"
        path.write_text(scenario_text(mode, speed_kmh, **options))
        scenario = load_scenario(path)
    if follower_data is not None:
        if not isinstance(follower_data, TrainData):
            raise HeadwayError(f"follower_data must be TrainData, got {follower_data!r}")
        follower = dataclasses.replace(scenario.trains[1], data=follower_data)
        scenario = dataclasses.replace(scenario, trains=(scenario.trains[0], follower))
    return scenario


@dataclass(frozen=True)
class Setting:
    """The follower's exact data for a headway scenario, as the simulator takes it."""

    scenario: Scenario
    params: TwoTrainParams
    """The two-train node's parameters (:mod:`atcs.model.separation`): the follower's train, national, plant and
    authority data, on the scenario's (uniform) compensated gradient."""
    data: dict
    """:func:`~atcs.model.train_data.preset_data` of the follower (what the separation properties fix)."""
    position_error_m: Fraction
    speed_error_mps: Fraction


def headway_setting(scenario: Scenario, *, position_error_m=None, speed_error_mps=None) -> Setting:
    """The follower's data for ``scenario``: its authority data as the simulator builds it (the leader's highest
    deceleration, margin, timeout), the plant data of :func:`~atcs.model.train_data.preset_data` and the
    errors: ``position_error_m``, how far the follower's max safe front is ahead of its true front and the leader's
    reported min safe rear behind its true rear (default: the odometry interval's half-width just before a tag,
    :func:`~atcs.model.position.odometry_interval`), ``speed_error_mps``, how far the reported min speed is under
    the true speed (default: :func:`~atcs.model.position.speed_accuracy_mps` at the line speed)."""
    if len(scenario.gradients_permille) != 1 or len(scenario.speed_limits_kmh) != 1 or len(scenario.trains) != 2:
        raise HeadwayError(f"{scenario.source}: the headway figures need two trains, one gradient and one speed limit")
    follower = Simulation(scenario).trains[1]
    spec, line_m = follower.spec, scenario.line_m
    data = preset_data(spec.data, scenario.national, cycle_s=scenario.cycle_s)
    line = Profile((Fraction(0),), (scenario.gradients_permille[0].value,), line_m)
    gradient = extend_by_train_length(EXACT, line, spec.data.train_length_m)
    mrsp_mps = min(scenario.speed_limits_kmh[0].value, spec.max_speed_kmh) / KMH_PER_MPS
    floats = follower.position.params  # the simulator's (float) position data, taken exactly
    position = dataclasses.replace(
        floats,
        **{
            name: Fraction(getattr(floats, name))
            for name in ("tag_window_m", "tacho_error", "cycle_s", "max_acceleration_mps2", "max_deceleration_mps2")
        },
    )
    if position_error_m is None:
        spacing = max(b - a for a, b in itertools.pairwise(scenario.tags.positions_m))
        position_error_m = odometry_interval(EXACT, position, Fraction(0), spacing)[1] - spacing
    if speed_error_mps is None:
        speed_error_mps = speed_accuracy_mps(EXACT, position, mrsp_mps)
    errors = {
        name: _number(name, value, zero_ok=True)
        for name, value in (("position_error_m", position_error_m), ("speed_error_mps", speed_error_mps))
    }
    params = TwoTrainParams(
        **{
            **data,
            **as_dict(follower.authority_params),
            "gradient_starts_m": gradient.starts_m,
            "gradient_permille": gradient.values,
            "line_end_m": line_m,
            "mrsp_mps": mrsp_mps,
            "position_error_m": errors["position_error_m"],
        }
    )
    return Setting(scenario, params, data, **errors)


def steady_state(p: TwoTrainParams, gap_m, speed_mps, front_m=Fraction(0)) -> TwoTrainState:
    """The two-train state at a steady ``speed_mps``: the follower's front at ``front_m``, not braking; the
    leader's rear ``gap_m`` ahead at the same speed; its latest report its true state (the best the follower can
    know: the report's stopping point is the ATP's :func:`~atcs.model.authority.stopping_point_m`)."""
    rear = front_m + gap_m
    return TwoTrainState(
        front_m=front_m,
        speed_mps=speed_mps,
        brake_cycles=Fraction(0),
        eb_latched=False,
        sb_latched=False,
        leader_known=True,
        best_rear_m=rear,
        best_stop_m=stopping_point_m(EXACT, p, rear, speed_mps),
        last_seq=Fraction(1),
        freshest_sent_s=Fraction(0),
        leader_rear_m=rear,
        leader_speed_mps=speed_mps,
        leader_stop_m=earliest_stop_m(EXACT, p, rear, speed_mps),
    )


def _invariant_gap(setting: Setting, speed_mps: Fraction) -> tuple[Fraction, dict]:
    """The least gap for SEP-01 at ``speed_mps``, from the invariant's own terms (its case of no EB command,
    :func:`~atcs.properties.closed_loop.braking_invariant`): the worst-case front when the brake is effective
    (:func:`~atcs.model.closed_loop.worst_case_at_brake`) and the EBD from there to a stop
    (:func:`~atcs.model.curves.ebd_location_m`), plus the margin, less the leader's stopping distance in relative
    braking (:func:`~atcs.model.authority.stopping_point_m`)."""
    p, o, zero = setting.params, EXACT, Fraction(0)
    n_t, n_be = whole_cycles("headway", setting.data)
    run_m, speed_at_brake = worst_case_at_brake(o, p, zero, speed_mps, 0, n_t, n_be)
    # the EBD to an end of authority at 0 reaches that speed this far behind it (on a uniform gradient, the same
    # distance behind any end of authority)
    braking_m = max(zero, -ebd_location_m(o, p, p, plant_gradient(p), Target(zero, zero, zero), speed_at_brake))
    credit = zero if p.brick_wall else stopping_point_m(o, p, zero, speed_mps)
    gap = run_m + braking_m + p.safety_margin_m - credit
    return gap, {
        "run_to_brake_m": float(run_m),
        "speed_at_brake_kmh": float(speed_at_brake * KMH_PER_MPS),
        "braking_m": float(braking_m),
        "leader_stopping_m": float(credit),
        "safety_margin_m": float(p.safety_margin_m),
    }


def _bisect(holds, what: str) -> Fraction:
    """The least gap in ``[0, SEARCH_LIMIT_M]`` (to :data:`GAP_TOLERANCE_M`, rounded up) for which ``holds(gap)``,
    monotone in the gap: bisection from ``[0, SEARCH_TOP_M]``, the top doubled while it does not hold."""
    low, high = Fraction(0), SEARCH_TOP_M
    while not holds(high):
        if high >= SEARCH_LIMIT_M:
            raise HeadwayError(f"no gap up to {high} m satisfies {what} at that speed")
        low, high = high, 2 * high
    if holds(low):
        return low
    while high - low > GAP_TOLERANCE_M:
        mid = (low + high) / 2
        low, high = (low, mid) if holds(mid) else (mid, high)
    return high


def _atp_gaps(setting: Setting, speed_mps: Fraction, locked_behind_m=None) -> dict[str, Fraction]:
    """The least gap for each limit on running at ``speed_mps`` (the follower's true front at 0): its max safe front
    at or behind each curve's location for its speed (``ebd`` ... ``indication``, seed 000 §2.4); ``traction``:
    the ATO's lookahead ahead of it too (:data:`~atcs.sim.ato_driver.ATO_LOOKAHEAD_S`: the ATO still
    accelerates); ``ato``: the ATO's target speed (seed 003, :func:`~atcs.model.ato.ato_target_speed` with the
    scenario's planning deceleration and margin and an MA end at speed 0, as the simulator gives it) stays the line
    speed. ``route_locked_*``: the same with the end of authority capped at ``locked_behind_m`` behind the leader's
    min safe rear, where the simulator's route locking puts it (the first resource the leader holds starts at or
    behind that rear: 0 at best, one resource length at worst); none without ``locked_behind_m``."""
    p, o, zero = setting.params, EXACT, Fraction(0)
    front_max = setting.position_error_m
    report_speed = max(zero, speed_mps - setting.speed_error_mps)
    mrsp = Profile((zero,), (p.mrsp_mps,), p.line_end_m)
    a_est = worst_acceleration_mps2(o, p)
    planning_mps2 = setting.scenario.planning_decel_kmhps / KMH_PER_MPS
    lookahead_m = speed_mps * Fraction(ATO_LOOKAHEAD_S)

    def eoa_m(gap, route_locked):
        rear_min = gap - setting.position_error_m
        reports = leader_reports(
            o,
            p,
            AuthorityState(False, zero, zero, zero, zero),
            AuthorityInputs(
                front_max_m=front_max,
                rear_min_m=-p.train_length_m,
                rear_confirmed=True,
                held=(),
                switch_locked=(),
                switch_reversed=(),
                now_s=zero,
                report_delivered=True,
                report_intact=True,
                report_seq=Fraction(1),
                report_sent_s=zero,
                report_rear_m=rear_min,
                report_speed_mps=report_speed,
                zone_active=False,
                zone_start_m=zero,
            ),
        )
        limit = leader_limit_m(o, p, reports, zero)
        return min(limit, rear_min - locked_behind_m) if route_locked else limit

    def curves(gap, route_locked):
        horizon = Horizon(mrsp=mrsp, gradient=plant_gradient(p), eoa_m=eoa_m(gap, route_locked), eoa_speed_mps=zero)
        return supervise_position(o, p, p, horizon, front_max, speed_mps, a_est)[1]

    def ato_cruises(gap, route_locked):
        target = ato_target_speed(
            o,
            front_m=front_max,
            speed_mps=speed_mps,
            line_limit_mps=p.mrsp_mps,
            train_max_mps=p.mrsp_mps,
            next_limit_m=Fraction(FAR_M),
            next_limit_mps=p.mrsp_mps,
            ma_end_m=eoa_m(gap, route_locked),
            ma_speed_mps=zero,
            planning_decel_mps2=planning_mps2,
            margin_m=setting.scenario.ato_margin_m,
        )
        return target.reason == FAR

    gaps = {}
    for prefix, locked in (("", False), ("route_locked_", True))[: 1 if locked_behind_m is None else 2]:
        for name in CURVE_NAMES:
            gaps[prefix + name] = _bisect(
                lambda g, n=name, r=locked: front_max <= getattr(curves(g, r), f"{n}_m"), f"the {name} curve"
            )
        gaps[prefix + "traction"] = _bisect(
            lambda g, r=locked: front_max + lookahead_m < curves(g, r).indication_m, "the ATO's traction lookahead"
        )
        gaps[prefix + "ato"] = _bisect(lambda g, r=locked: ato_cruises(g, r), "the ATO's target speed")
    return gaps


def theoretical_minimum(
    mode: str,
    speed_kmh=80,
    *,
    limit: str = "atp",
    position_error_m=None,
    speed_error_mps=None,
    follower_data: TrainData | None = None,
    **options,
) -> HeadwayFigure:
    """The least gap and headway at a steady ``speed_kmh`` behind a leader at the same speed (seed 001 §3.2 Fig. 6):
    ``limit="invariant"``, the proved separation invariant's bound; ``limit="atp"``, the least the ATP's supervision
    lets the follower run at (module docstring). The errors: :func:`headway_setting`; ``follower_data``: the
    follower's train data instead of the preset's; ``options``: :func:`scenario_text`'s."""
    if limit not in ("invariant", "atp"):
        raise HeadwayError(f"limit must be 'invariant' or 'atp', got {limit!r}")
    mode, speed_kmh = _mode(mode), _number("speed_kmh", speed_kmh)
    scenario = headway_scenario(mode, speed_kmh, follower_data=follower_data, **options)
    setting = headway_setting(scenario, position_error_m=position_error_m, speed_error_mps=speed_error_mps)
    p, speed_mps = setting.params, speed_kmh / KMH_PER_MPS
    data = {
        "leader_max_deceleration_mps2": float(p.leader_max_deceleration_mps2),
        "guaranteed_deceleration_mps2": float(p.guaranteed_deceleration_mps2),
    }
    if limit == "invariant":
        gap, terms = _invariant_gap(setting, speed_mps)
        return _figure(mode, limit, speed_kmh, gap, p.train_length_m, gap, **data, **terms)
    gaps = _atp_gaps(setting, speed_mps, Fraction(0))
    return _figure(
        mode,
        limit,
        speed_kmh,
        gaps["indication"],
        p.train_length_m,
        gaps["indication"],
        **data,
        position_error_m=float(setting.position_error_m),
        speed_error_mps=float(setting.speed_error_mps),
        **{f"{name}_m": float(g) for name, g in gaps.items()},
    )


# --- the measurement ----------------------------------------------------------------------------------------------


def sim_limited_gap(
    mode: str,
    speed_kmh=80,
    *,
    locked_behind_m=0,
    position_error_m=None,
    speed_error_mps=None,
    follower_data: TrainData | None = None,
    **options,
) -> Fraction:
    """The least gap at which the simulator's follower cruises at ``speed_kmh`` by the theory: the larger of the
    gaps its indication point and its ATO's target speed need (:func:`theoretical_minimum`, ``route_locked_*``),
    with its end of authority ``locked_behind_m`` behind the leader's min safe rear (0: the first resource the
    leader holds starts at that rear, the best case; ``resource_length_m``: the worst)."""
    mode, speed_kmh = _mode(mode), _number("speed_kmh", speed_kmh)
    locked_behind_m = _number("locked_behind_m", locked_behind_m, zero_ok=True)
    scenario = headway_scenario(mode, speed_kmh, follower_data=follower_data, **options)
    setting = headway_setting(scenario, position_error_m=position_error_m, speed_error_mps=speed_error_mps)
    gaps = _atp_gaps(setting, speed_kmh / KMH_PER_MPS, locked_behind_m)
    return max(gaps["route_locked_indication"], gaps["route_locked_ato"])


def measured_minimum(
    mode: str,
    speed_kmh=80,
    *,
    resource_length_m=50,
    duration_s=RUN_S,
    follower_depart_s=None,
    approach_m=15,
    settle_s=60,
    settle_m=5,
    speed_tolerance_kmh=Fraction(5, 2),
    follower_data: TrainData | None = None,
    on_cycle: Callable[[Simulation], None] = lambda sim: None,
    **options,
) -> HeadwayFigure:
    """The steady-state gap of the closed-loop simulator (seed 000 §2.5): a leader at ``speed_kmh`` and a follower
    powered up one tag spacing behind it (:func:`scenario_text`, ``options``), run for ``duration_s``.

    The follower departs ``follower_depart_s`` after the leader; by default so late that, were it never held back,
    it would run ``approach_m`` closer than :func:`sim_limited_gap` with its end of authority one resource behind
    the leader's rear (the worst phase of the end of authority's sawtooth over a resource; it then settles from
    below, in a shorter run than from right behind). The figure is the least gap over the last ``settle_s`` seconds,
    in which both trains stay within ``speed_tolerance_kmh`` of ``speed_kmh`` (the ATO cruises up to 0.3 m/s under
    its target, and the follower brakes a little more at its limit) and the gap within ``settle_m``; the follower
    must have been held back (braked while running) and its end of authority not limited by ``max_ma_m``.
    Otherwise :class:`HeadwayError`. ``on_cycle`` is called after each cycle of the run."""
    mode, speed_kmh = _mode(mode), _number("speed_kmh", speed_kmh)
    settle_s, settle_m = _number("settle_s", settle_s), _number("settle_m", settle_m)
    tolerance, duration = _number("speed_tolerance_kmh", speed_tolerance_kmh), _number("duration_s", duration_s)
    if settle_s >= duration:
        raise HeadwayError(f"settle_s must be shorter than duration_s = {duration_s!r}, got {settle_s}")
    scenario = headway_scenario(
        mode,
        speed_kmh,
        resource_length_m=resource_length_m,
        duration_s=duration_s,
        follower_data=follower_data,
        **options,
    )
    leader, follower = scenario.trains
    if follower_depart_s is None:
        worst = sim_limited_gap(
            mode,
            speed_kmh,
            locked_behind_m=_number("resource_length_m", resource_length_m),
            follower_data=follower_data,
            resource_length_m=resource_length_m,
            **options,
        )
        start_gap = worst - _number("approach_m", approach_m)
        initial_gap = leader.front_m - leader.data.train_length_m - follower.front_m
        late = max(Fraction(0), (start_gap - initial_gap) / (speed_kmh / KMH_PER_MPS))
        follower_depart_s = Fraction(round(late / scenario.cycle_s)) * scenario.cycle_s
    depart = _number("follower_depart_s", follower_depart_s, zero_ok=True)
    if not depart < duration - settle_s:
        raise HeadwayError(
            f"follower_depart_s must lie in [0, duration_s - settle_s = {duration - settle_s}), got "
            f"{follower_depart_s!r}"
        )
    scenario = dataclasses.replace(scenario, trains=(leader, dataclasses.replace(follower, depart_s=depart)))
    leader_length, kmh = float(leader.data.train_length_m), float(KMH_PER_MPS)
    samples: list[tuple[float, float, float, float, float]] = []
    """Each cycle: time, leader's and follower's speeds (km/h), gap, how far the follower's EoA is ahead of it."""
    held_back = 0

    def sample(sim: Simulation) -> None:
        nonlocal held_back
        on_cycle(sim)
        lead, follow = sim.trains
        speed = follow.speed_mps * kmh
        held_back += bool(samples) and 0 < speed < samples[-1][2]  # braking on a level line: its limits hold it back
        samples.append(
            (
                sim.time_s,
                lead.speed_mps * kmh,
                speed,
                lead.front_m - leader_length - follow.front_m,
                follow.last["eoa_m"] - follow.last["front_max_m"],
            )
        )

    started = time.process_time()
    simulation = Simulation(scenario, on_cycle=sample).run()
    cpu_s = time.process_time() - started
    window = [s for s in samples if s[0] > samples[-1][0] - float(settle_s)]
    gaps = [s[3] for s in window]
    target = float(speed_kmh)
    where = f"{mode} at {target:g} km/h, resource_length_m = {resource_length_m}, duration_s = {duration_s}"
    off = [s for s in window if max(abs(s[1] - target), abs(s[2] - target)) > float(tolerance)]
    if off:
        t, v_leader, v_follower, *_ = off[0]
        raise HeadwayError(
            f"no steady state ({where}): at t = {t:.1f} s the leader runs at {v_leader:.2f} and the "
            f"follower at {v_follower:.2f} km/h, more than speed_tolerance_kmh = {tolerance} from "
            f"{target:g} km/h within the last settle_s = {settle_s} s"
        )
    spread = max(gaps) - min(gaps)
    if spread > settle_m:
        raise HeadwayError(
            f"no steady state ({where}): the gap spreads {spread:.2f} m (from {min(gaps):.2f} to "
            f"{max(gaps):.2f} m) over the last settle_s = {settle_s} s, more than settle_m = {settle_m}"
        )
    reach = max(s[4] for s in window)
    if reach >= float(scenario.max_ma_m) - 1:
        raise HeadwayError(
            f"no minimum ({where}): the follower's end of authority reaches {reach:.2f} m ahead of "
            f"it, so max_ma_m = {scenario.max_ma_m} limits it rather than its leader"
        )
    if not held_back:
        raise HeadwayError(
            f"no minimum ({where}): the follower, departing follower_depart_s = {depart} s after the "
            f"leader, was never held back; its gap {gaps[-1]:.2f} m is only where it started"
        )
    stats = simulation.trains[1].stats
    return _figure(
        mode,
        "measured",
        speed_kmh,
        min(gaps),
        follower.data.train_length_m,
        resource_length_m=float(resource_length_m),
        duration_s=float(duration),
        follower_depart_s=float(depart),
        window_s=float(settle_s),
        spread_m=spread,
        final_gap_m=gaps[-1],
        held_back_cycles=held_back,
        follower_speed_kmh=(min(s[2] for s in window), max(s[2] for s in window)),
        leader_speed_kmh=(min(s[1] for s in window), max(s[1] for s in window)),
        least_gap_of_run_m=stats.min_gap_m,
        emergency_brakes=stats.emergency_brakes,
        service_brakes=stats.service_brakes,
        cycles=simulation.step_count,
        cpu_s=cpu_s,
    )


def headway_report(
    speed_kmh=80,
    on_mode: Callable[[str], None] = lambda mode: None,
    progress: Callable[[int, int], None] = lambda done, total: None,
    **options,
) -> list[dict]:
    """One row per mode: the measured gap and headway (``options``: :func:`measured_minimum`'s), the
    ATP-limited and the invariant's theoretical ones, and the resource length the measurement used; ``on_mode``
    is called with each mode before its closed-loop run, ``progress(done, total)`` after each cycle of the runs.
    ``options`` not given take :func:`run_options`'s values for the speed."""
    options = {**run_options(speed_kmh), **options}
    rows = []
    cycles = round(_number("duration_s", options.get("duration_s", RUN_S)) / CYCLE_S)
    for n, mode in enumerate(MODES):
        on_mode(mode)
        measured = measured_minimum(
            mode,
            speed_kmh,
            on_cycle=lambda sim, n=n: progress(n * cycles + sim.step_count, len(MODES) * cycles),
            **options,
        )
        theory = {
            k: v
            for k, v in options.items()
            if k not in ("duration_s", "follower_depart_s", "approach_m", "settle_s", "settle_m", "speed_tolerance_kmh")
        }
        atp = theoretical_minimum(mode, speed_kmh, limit="atp", **theory)
        invariant = theoretical_minimum(mode, speed_kmh, limit="invariant", **theory)
        rows.append(
            {
                "mode": mode,
                "speed_kmh": measured.speed_kmh,
                "measured_gap_m": measured.gap_m,
                "measured_headway_s": measured.headway_s,
                "atp_gap_m": atp.gap_m,
                "atp_headway_s": atp.headway_s,
                "invariant_gap_m": invariant.gap_m,
                "invariant_headway_s": invariant.headway_s,
                "resource_length_m": measured.details["resource_length_m"],
            }
        )
    return rows
