"""Headway at a steady speed (issue 8; seed 001 §3.2 Fig. 6, seed 000 §2.4-2.5): the least gap (front of the
follower to rear of the leader) and headway at which a follower can run at the leader's steady speed, in
relative-braking and brick-wall modes, three ways:

- ``invariant``: the least gap for which the proved separation invariant (SEP-01,
  :mod:`atcs.properties.separation`) holds of a follower at that speed, not braking, behind a leader at the same
  speed whose latest report is its true state: the physics (full traction until the cut-off, coasting through the
  brake build-up, the guaranteed deceleration to a stop at the leader's rear, in relative braking at its earliest
  stopping point, less the safety margin). No supervision curve, no position error.
- ``atp``: the least gap at which the follower's ATP lets it keep running at that speed: its max safe front
  (position error added) not past the indication point the ATO brakes at (:mod:`atcs.sim.simulator`), against the
  end of authority :mod:`atcs.model.authority` derives from the leader's report (min safe rear, min speed); the
  curves add the EBI's speed and acceleration terms and the SBI, warning, permitted and indication times to the
  invariant. The route's resources are not counted (see ``details["route_locked_m"]``).
- ``measured``: the steady-state gap of the closed-loop simulator (:class:`~atcs.sim.simulator.Simulation`), whose
  end of authority also stops at the first resource the leader still holds (one ``resource_length_m`` of
  granularity).

Headway time is ``(gap + train length) / speed``. Both theoretical figures are computed on exact numbers with the
model's own functions (nothing re-derived here), with the data the simulator uses for the same scenario.
"""

from __future__ import annotations

import dataclasses
import tempfile
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any

from atcs.model.authority import AuthorityInputs, AuthorityState, leader_limit_m, leader_reports, stopping_point_m
from atcs.model.closed_loop import worst_acceleration_mps2
from atcs.model.curves import Target, ebd_location_m
from atcs.model.dynamic_profile import CURVE_NAMES, Horizon, supervise_position
from atcs.model.node import as_dict
from atcs.model.ops.exact import EXACT
from atcs.model.plant import plant_gradient
from atcs.model.position import odometry_interval, speed_accuracy_mps
from atcs.model.profile import KMH_PER_MPS, Profile
from atcs.model.psl import extend_by_train_length
from atcs.model.separation import TwoTrainParams, TwoTrainState, earliest_stop_m
from atcs.model.train_data import TrainData
from atcs.properties.closed_loop import preset_data, whole_cycles, worst_case_at_brake
from atcs.properties.separation import separation_properties
from atcs.sim.scenario import PRESETS, Scenario, load_scenario
from atcs.sim.simulator import ATO_LOOKAHEAD_S, Simulation

MODES = {"relative_braking": "rbd", "brick_wall": "bw"}
"""The scenario's ``[atp] mode`` names and the separation properties' (``rbd``, ``bw``); either is accepted."""
KINDS = ("invariant", "atp", "measured")
GAP_TOLERANCE_M = Fraction(1, 1000)
"""The theoretical gaps are bisected to this (m) and rounded up to it."""
PROBE_M = Fraction(1, 1000)
"""How far below the invariant's gap its predicate is checked to fail."""
SEARCH_TOP_M = Fraction(10_000)
"""The largest gap searched (m)."""
TAG_SPACING_M = 100
"""Seed 000 §2.5: a tag every 100 m."""
LEADER_FRONT_M = 500
"""The leader's front at power-up; the follower powers up on the tag one spacing behind the leader's rear."""


class HeadwayError(ValueError):
    """A bad argument (named with its value), or a run that reaches no steady state."""


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
    """The theoretical figures' exact gap (None for a measurement)."""
    details: Mapping[str, Any] = field(default_factory=dict)
    """What else the figure depends on (data used, per-curve gaps, the run's window and spread)."""


def _mode(mode: str) -> str:
    """The scenario's name of ``mode``."""
    for name, short in MODES.items():
        if mode in (name, short):
            return name
    raise HeadwayError(f"mode must be one of {', '.join((*MODES, *MODES.values()))}, got {mode!r}")


def _positive(name: str, value, *, whole: bool = False) -> Fraction:
    try:
        exact = Fraction(value) if not isinstance(value, float) else Fraction(repr(value))
    except (TypeError, ValueError):
        raise HeadwayError(f"{name} must be a number, got {value!r}") from None
    if isinstance(value, bool) or not exact > 0 or (whole and exact.denominator != 1):
        raise HeadwayError(f"{name} must be a positive {'whole ' if whole else ''}number, got {value!r}")
    return exact


def _figure(mode, kind, speed_kmh: Fraction, gap_m, length_m, exact=None, **details) -> HeadwayFigure:
    speed_mps = speed_kmh / KMH_PER_MPS
    return HeadwayFigure(mode=mode, kind=kind, speed_kmh=float(speed_kmh), gap_m=float(gap_m),
                         headway_s=float((Fraction(gap_m) + length_m) / speed_mps), train_length_m=float(length_m),
                         exact_gap_m=exact, details=details)


# --- the scenario both the theory and the measurement use ---------------------------------------------------------


def scenario_text(mode: str, speed_kmh=80, *, resource_length_m=50, duration_s=300, follower_depart_s=0,
                  safety_margin_m=20, report_timeout_s=2, tag_window_m="2.5", tacho_error="0.01", max_ma_m=1500,
                  preset: str = "seed000") -> str:
    """A scenario (TOML, the format of ``sim/scenarios/seed000_slow_leader.toml``): a level line, tags every
    100 m, both trains of ``preset`` limited to ``speed_kmh``, the follower powered up on the tag one spacing
    behind the leader's rear, departing ``follower_depart_s`` after it (seed 000 §2.5)."""
    mode = _mode(mode)
    speed = _positive("speed_kmh", speed_kmh)
    duration = _positive("duration_s", duration_s)
    for name, value in (("resource_length_m", resource_length_m), ("max_ma_m", max_ma_m),
                        ("report_timeout_s", report_timeout_s)):
        _positive(name, value)
    depart = Fraction(follower_depart_s)
    if depart < 0 or depart >= duration:
        raise HeadwayError(f"follower_depart_s must lie in [0, duration_s = {duration}), got {follower_depart_s!r}")
    if preset not in PRESETS:
        raise HeadwayError(f"preset must be one of {', '.join(PRESETS)}, got {preset!r}")
    length = PRESETS[preset]().train_length_m
    follower_front = LEADER_FRONT_M - length - TAG_SPACING_M
    run_m = speed / KMH_PER_MPS * duration
    line_m = (int(LEADER_FRONT_M + run_m + 2 * Fraction(max_ma_m)) // TAG_SPACING_M + 1) * TAG_SPACING_M

    def toml(x) -> str:
        x = Fraction(x)
        return str(x.numerator) if x.denominator == 1 else repr(float(x))

    trains = "".join(
        f'\n[[trains]]\nname = "{name}"\npreset = "{preset}"\nfront_m = {front}\nmax_speed_kmh = {toml(speed)}\n'
        f"depart_s = {toml(dep)}\n"
        for name, front, dep in (("leader", LEADER_FRONT_M, 0), ("follower", follower_front, depart)))
    return (
        f'name = "headway_{mode}"\nseed = "001 §3.2, 000 §2.5"\n'
        f'description = "A leader at {toml(speed)} km/h and a follower right behind it: the steady-state headway."\n'
        f"duration_s = {toml(duration)}\ncycle_s = 0.1\n\n"
        f"[line]\nlength_m = {line_m}\ntag_spacing_m = {TAG_SPACING_M}\nresource_length_m = {toml(resource_length_m)}\n"
        f"max_ma_m = {toml(max_ma_m)}\nspeed_limits = [{{ start_m = 0, kmh = {toml(speed)} }}]\n\n"
        f'[atp]\nmode = "{mode}"\nsafety_margin_m = {toml(safety_margin_m)}\nreport_timeout_s = {toml(report_timeout_s)}\n'
        f"tag_window_m = {toml(tag_window_m)}\ntacho_error = {toml(tacho_error)}\n\n"
        f"[ato]\nplanning_decel_kmhps = 1.5\nmargin_m = 30\n{trains}"
    )


def headway_scenario(mode: str, speed_kmh=80, *, follower_data: TrainData | None = None, **options) -> Scenario:
    """:func:`scenario_text` written to a temporary file and read by :func:`~atcs.sim.scenario.load_scenario`;
    ``follower_data`` replaces the follower's train data (e.g. a weaker brake)."""
    with tempfile.TemporaryDirectory(prefix="atcs-headway-") as folder:
        path = Path(folder) / f"headway_{_mode(mode)}.toml"
        path.write_text(scenario_text(mode, speed_kmh, **options))
        scenario = load_scenario(path)
    if follower_data is not None:
        follower = dataclasses.replace(scenario.trains[1], data=follower_data)
        scenario = dataclasses.replace(scenario, trains=(scenario.trains[0], follower))
    return scenario


@dataclass(frozen=True)
class _Setting:
    """The follower's exact data as the simulator takes it for ``scenario`` (its ``_train``)."""

    scenario: Scenario
    params: TwoTrainParams
    data: dict
    """:func:`~atcs.properties.closed_loop.preset_data` of the follower."""
    position_error_m: Fraction
    speed_error_mps: Fraction


def _setting(scenario: Scenario, position_error_m=None, speed_error_mps=None) -> _Setting:
    simulation = Simulation(scenario)  # its follower's authority data: the leader's highest deceleration, margin
    follower = simulation.trains[1]
    spec, line_m = follower.spec, scenario.line_m
    if len(scenario.gradients_permille) != 1 or len(scenario.speed_limits_kmh) != 1:
        raise HeadwayError(f"{scenario.source}: the headway figures need one gradient and one speed limit, got "
                           f"{len(scenario.gradients_permille)} and {len(scenario.speed_limits_kmh)}")
    data = preset_data(spec.data, scenario.national, cycle_s=scenario.cycle_s)
    gradient = extend_by_train_length(EXACT, Profile((Fraction(0),), (scenario.gradients_permille[0].value,), line_m),
                                      spec.data.train_length_m)
    mrsp_mps = min(scenario.speed_limits_kmh[0].value, spec.max_speed_kmh) / KMH_PER_MPS
    # the position interval's half-width just before a tag, and the report's speed deficit (the position node's)
    position = follower.position.params
    exact_position = dataclasses.replace(position, **{
        name: Fraction(getattr(position, name)) for name in ("tag_window_m", "tacho_error", "cycle_s",
                                                              "max_acceleration_mps2", "max_deceleration_mps2")})
    if position_error_m is None:
        position_error_m = odometry_interval(EXACT, exact_position, Fraction(0), scenario.tag_spacing_m)[1] \
            - scenario.tag_spacing_m
    if speed_error_mps is None:
        speed_error_mps = speed_accuracy_mps(EXACT, exact_position, mrsp_mps)
    for name, value in (("position_error_m", position_error_m), ("speed_error_mps", speed_error_mps)):
        if Fraction(value) < 0:
            raise HeadwayError(f"{name} must be >= 0, got {value!r}")
    params = TwoTrainParams(**{
        **{k: v for k, v in data.items() if k not in ("gradient_permille",)},
        **as_dict(follower.authority_params),
        "gradient_starts_m": gradient.starts_m, "gradient_permille": gradient.values, "line_end_m": line_m,
        "mrsp_mps": mrsp_mps, "position_error_m": Fraction(position_error_m),
    })
    return _Setting(scenario, params, data, Fraction(position_error_m), Fraction(speed_error_mps))


def _separation_invariant(setting: _Setting):
    """The SEP-01 property of the setting's mode, on its data."""
    mode = MODES["brick_wall" if setting.params.brick_wall else "relative_braking"]
    return next(p for p in separation_properties("headway", setting.data, mode) if p.requirement == "SEP-01")


def steady_state(p: TwoTrainParams, gap_m, speed_mps, front_m=Fraction(0)) -> TwoTrainState:
    """The two-train state at a steady ``speed_mps``: the follower at ``front_m`` not braking, the leader's rear
    ``gap_m`` ahead, its latest report its true state (the best the follower can know)."""
    rear = front_m + gap_m
    stop = earliest_stop_m(EXACT, p, rear, speed_mps)
    return TwoTrainState(front_m=front_m, speed_mps=speed_mps, brake_cycles=Fraction(0), eb_latched=False,
                         sb_latched=False, leader_known=True, best_rear_m=rear,
                         best_stop_m=stopping_point_m(EXACT, p, rear, speed_mps), since_report_s=Fraction(0),
                         leader_rear_m=rear, leader_speed_mps=speed_mps, leader_stop_m=stop)


def invariant_holds(setting_or_params, gap_m, speed_mps, front_m=Fraction(0)) -> bool:
    """SEP-01's own predicate (:func:`~atcs.properties.separation.separation_properties`) of :func:`steady_state`."""
    setting = setting_or_params
    prop = _separation_invariant(setting)
    p = setting.params
    return bool(prop.holds(EXACT, p, steady_state(p, Fraction(gap_m), Fraction(speed_mps), Fraction(front_m)),
                           None, None, None))


def _invariant_gap(setting: _Setting, speed_mps: Fraction) -> tuple[Fraction, dict]:
    """The least gap for SEP-01 at ``speed_mps`` (module docstring), from the invariant's own terms: the worst-case
    front when the brake is effective (:func:`~atcs.properties.closed_loop.worst_case_at_brake`) and the EBD from
    there to a stop (:func:`~atcs.model.curves.ebd_location_m`), less the leader's stopping distance in relative
    braking (:func:`~atcs.model.authority.stopping_point_m`), plus the margin."""
    p, o, zero = setting.params, EXACT, Fraction(0)
    n_t, n_be = whole_cycles("headway", setting.data)
    front_at_brake, speed_at_brake = worst_case_at_brake(o, p, zero, speed_mps, 0, n_t, n_be)
    # the EBD of an end of authority at 0 reaches speed_at_brake this far behind it (a uniform gradient: the same
    # distance behind any end of authority)
    braking_m = max(zero, -ebd_location_m(o, p, p, plant_gradient(p), Target(zero, zero, zero), speed_at_brake))
    credit = zero if p.brick_wall else stopping_point_m(o, p, zero, speed_mps)
    gap = front_at_brake + braking_m + p.safety_margin_m - credit
    if not invariant_holds(setting, gap, speed_mps) or invariant_holds(setting, gap - PROBE_M, speed_mps):
        raise AssertionError(f"internal error: SEP-01's predicate does not change at the computed gap {float(gap)} m")
    return gap, {"run_to_brake_m": float(front_at_brake), "speed_at_brake_kmh": float(speed_at_brake * KMH_PER_MPS),
                 "braking_m": float(braking_m), "leader_stopping_m": float(credit),
                 "safety_margin_m": float(p.safety_margin_m)}


def _bisect(holds, low=Fraction(0), high=SEARCH_TOP_M) -> Fraction:
    """The least gap (to :data:`GAP_TOLERANCE_M`, rounded up) for which ``holds(gap)``, monotone in the gap."""
    if not holds(high):
        raise HeadwayError(f"no gap up to {high} m lets the follower run at that speed")
    if holds(low):
        return low
    while high - low > GAP_TOLERANCE_M:
        mid = (low + high) / 2
        low, high = (low, mid) if holds(mid) else (mid, high)
    return high


def _atp_gaps(setting: _Setting, speed_mps: Fraction) -> dict:
    """The least gap for each supervision limit at ``speed_mps``: the follower's max safe front (its true front at 0
    plus the position error) at or behind that curve's location for its speed; ``traction``: the ATO's
    lookahead ahead of it as well (the ATO still accelerates); ``route_locked_m``: the indication with the end of
    authority capped at the leader's min safe rear, where the simulator's route locking puts it at best."""
    p, o, zero = setting.params, EXACT, Fraction(0)
    front_max = setting.position_error_m
    report_speed = max(zero, speed_mps - setting.speed_error_mps)
    horizon_mrsp = Profile((zero,), (p.mrsp_mps,), p.line_end_m)
    t, n = TrainData(**{f.name: getattr(p, f.name) for f in dataclasses.fields(TrainData)}), p
    a_est = worst_acceleration_mps2(o, p)

    def curves(gap, route_locked=False):
        rear_min = gap - setting.position_error_m  # the leader's report: its true rear less the same error
        reports = leader_reports(o, p, AuthorityState(False, zero, zero, zero), AuthorityInputs(
            front_max_m=front_max, rear_min_m=-p.train_length_m, held=(), switch_locked=(), switch_reversed=(),
            report_delivered=True, report_rear_m=rear_min, report_speed_mps=report_speed, zone_active=False,
            zone_start_m=zero))
        eoa = leader_limit_m(o, p, reports)
        if route_locked:
            eoa = min(eoa, rear_min)
        horizon = Horizon(mrsp=horizon_mrsp, gradient=plant_gradient(p), eoa_m=eoa, eoa_speed_mps=zero)
        return supervise_position(o, t, n, horizon, front_max, speed_mps, a_est)[1]

    gaps = {name: _bisect(lambda g, name=name: front_max <= getattr(curves(g), f"{name}_m"))
            for name in CURVE_NAMES}
    lookahead = speed_mps * Fraction(ATO_LOOKAHEAD_S)
    gaps["traction"] = _bisect(lambda g: front_max + lookahead < curves(g).indication_m)
    gaps["route_locked"] = _bisect(lambda g: front_max <= curves(g, route_locked=True).indication_m)
    return gaps


def theoretical_minimum(mode: str, speed_kmh=80, *, limit: str = "atp", position_error_m=None, speed_error_mps=None,
                        follower_data: TrainData | None = None, **options) -> HeadwayFigure:
    """The least gap and headway at a steady ``speed_kmh`` behind a leader at the same speed (seed 001 §3.2
    Fig. 6): ``limit="invariant"`` the proved separation invariant's bound, ``limit="atp"`` the least the ATP's
    supervision lets the follower run at (module docstring). ``position_error_m``: how far the follower's max safe
    front is ahead of its true front, and the leader's reported min safe rear behind its true rear (default: the
    position interval's half-width just before a tag); ``speed_error_mps``: how far the reported min speed is under
    the true speed (default: the position node's speed accuracy); ``options``: :func:`scenario_text`'s."""
    if limit not in ("invariant", "atp"):
        raise HeadwayError(f"limit must be 'invariant' or 'atp', got {limit!r}")
    mode = _mode(mode)
    speed_kmh = _positive("speed_kmh", speed_kmh)
    scenario = headway_scenario(mode, speed_kmh, follower_data=follower_data, **options)
    setting = _setting(scenario, position_error_m, speed_error_mps)
    speed_mps = speed_kmh / KMH_PER_MPS
    length = setting.params.train_length_m
    common = {"leader_max_deceleration_mps2": float(setting.params.leader_max_deceleration_mps2),
              "guaranteed_deceleration_mps2": float(setting.params.guaranteed_deceleration_mps2)}
    if limit == "invariant":
        gap, terms = _invariant_gap(setting, speed_mps)
        return _figure(mode, limit, speed_kmh, gap, length, gap, **common, **terms)
    gaps = _atp_gaps(setting, speed_mps)
    gap = gaps["indication"]
    return _figure(mode, limit, speed_kmh, gap, length, gap, **common,
                   position_error_m=float(setting.position_error_m), speed_error_mps=float(setting.speed_error_mps),
                   **{f"{name}_m": float(g) for name, g in gaps.items()})


# --- the measurement ----------------------------------------------------------------------------------------------


def measured_minimum(mode: str, speed_kmh=80, *, resource_length_m=50, duration_s=300, follower_depart_s=0,
                     settle_s=60, settle_m=5, speed_tolerance_kmh=1, follower_data: TrainData | None = None,
                     **options) -> HeadwayFigure:
    """The steady-state gap of the closed-loop simulator (seed 000 §2.5): a leader at ``speed_kmh`` and a follower
    powered up right behind it (:func:`scenario_text`), run ``duration_s``; the figure is the least gap over the
    last ``settle_s`` seconds, in which both trains must stay within ``speed_tolerance_kmh`` of ``speed_kmh`` and
    the gap within ``settle_m`` (its spread), else :class:`HeadwayError`. The follower's end of authority stops at
    the first resource its leader holds: ``resource_length_m`` of granularity."""
    mode = _mode(mode)
    speed_kmh = _positive("speed_kmh", speed_kmh)
    settle_s, settle_m = _positive("settle_s", settle_s), _positive("settle_m", settle_m)
    tolerance = _positive("speed_tolerance_kmh", speed_tolerance_kmh)
    if settle_s >= _positive("duration_s", duration_s):
        raise HeadwayError(f"settle_s must be shorter than duration_s = {duration_s!r}, got {settle_s}")
    scenario = headway_scenario(mode, speed_kmh, resource_length_m=resource_length_m, duration_s=duration_s,
                                follower_depart_s=follower_depart_s, follower_data=follower_data, **options)
    leader_length = float(scenario.trains[0].data.train_length_m)
    samples: list[tuple[float, float, float, float]] = []

    def sample(sim: Simulation) -> None:
        leader, follower = sim.trains
        samples.append((sim.time_s, leader.speed_mps * float(KMH_PER_MPS), follower.speed_mps * float(KMH_PER_MPS),
                        leader.front_m - leader_length - follower.front_m))

    started = time.process_time()
    simulation = Simulation(scenario, on_cycle=sample).run()
    cpu_s = time.process_time() - started
    end_s = samples[-1][0]
    window = [s for s in samples if s[0] > end_s - float(settle_s)]
    target = float(speed_kmh)
    slow = [s for s in window if max(abs(s[1] - target), abs(s[2] - target)) > float(tolerance)]
    gaps = [s[3] for s in window]
    spread = max(gaps) - min(gaps)
    where = f"{mode} at {target:g} km/h, resource_length_m = {resource_length_m}, duration_s = {duration_s}"
    if slow:
        t, v_leader, v_follower, _ = slow[0]
        raise HeadwayError(f"no steady state ({where}): at t = {t:.1f} s the leader runs at {v_leader:.2f} and the "
                           f"follower at {v_follower:.2f} km/h, more than speed_tolerance_kmh = {tolerance} from "
                           f"{target:g} km/h within the last settle_s = {settle_s} s")
    if spread > settle_m:
        raise HeadwayError(f"no steady state ({where}): the gap spreads {spread:.2f} m (from {min(gaps):.2f} to "
                           f"{max(gaps):.2f} m) over the last settle_s = {settle_s} s, more than settle_m = {settle_m}")
    stats = simulation.trains[1].stats
    return _figure(mode, "measured", speed_kmh, min(gaps), scenario.trains[1].data.train_length_m,
                   resource_length_m=float(resource_length_m), duration_s=float(duration_s),
                   follower_depart_s=float(follower_depart_s), window_s=float(settle_s), spread_m=spread,
                   final_gap_m=gaps[-1], follower_speed_kmh=(min(s[2] for s in window), max(s[2] for s in window)),
                   leader_speed_kmh=(min(s[1] for s in window), max(s[1] for s in window)),
                   least_gap_of_run_m=stats.min_gap_m, emergency_brakes=stats.emergency_brakes,
                   service_brakes=stats.service_brakes, cycles=simulation.step_count, cpu_s=cpu_s)


def headway_report(speed_kmh=80, **options) -> list[dict]:
    """One row per mode: the measured gap and headway, the ATP-limited and the invariant's theoretical ones
    (issue 8), for printing as a table; ``options`` go to :func:`measured_minimum`."""
    rows = []
    for mode in MODES:
        measured = measured_minimum(mode, speed_kmh, **options)
        atp = theoretical_minimum(mode, speed_kmh, limit="atp")
        invariant = theoretical_minimum(mode, speed_kmh, limit="invariant")
        rows.append({
            "mode": mode, "speed_kmh": measured.speed_kmh,
            "measured_gap_m": measured.gap_m, "measured_headway_s": measured.headway_s,
            "atp_gap_m": atp.gap_m, "atp_headway_s": atp.headway_s,
            "invariant_gap_m": invariant.gap_m, "invariant_headway_s": invariant.headway_s,
            "resource_length_m": measured.details["resource_length_m"],
        })
    return rows
