"""The minimum-running-time speed profile between two station stops, for the ATO to follow (cvxpy, CLARABEL).

In specific kinetic energy ``E = v^2/2`` over distance the problem is convex (docs/design.md): on a uniform
grid ``x_0 = start_m < ... < x_N = stop_m`` of step ``ds``, with ``E_0 = E_N = 0``,

- ceiling: ``0 <= E_i <= c_i^2 / 2``, ``c_i`` the caller's ceiling (the lowest of ``x_{i-1}, x_i, x_{i+1}``
  when ``conservative``);
- traction: ``(E_{i+1} - E_i) / ds <= accel_mps2``; braking: ``(E_i - E_{i+1}) / ds <= decel_mps2``;
- running time: ``sum_i 2 ds / (sqrt(2 E_i) + sqrt(2 E_{i+1}))``, convex (``inv_pos`` of a concave sum).

``E`` linear between grid points is a constant acceleration, for which ``2 ds / (v_i + v_{i+1})`` is the
exact time over the step, so the objective is the running time of the returned profile, not an estimate.

:func:`atp_ceiling` builds a ceiling from the model: the ATP's indication curve for a horizon
(:func:`~atcs.model.dynamic_profile.curve_speeds_at`, the MRSP included), less a speed margin, so that
a train on the profile is never even shown an indication.
"""

from __future__ import annotations

import math
import numbers
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import lru_cache
from itertools import pairwise

import numpy as np

from atcs.model.dynamic_profile import CURVE_NAMES, Horizon, curve_speeds_at
from atcs.model.errors import AtcsError
from atcs.model.ops.floating import float_record
from atcs.model.restrictions import as_float
from atcs.model.train_data import NationalData, TrainData

SOLVER = "CLARABEL"
TOLERANCE = 1e-6
"""Relative slack allowed on the traction and braking limits after the solve (solver accuracy)."""
DEFAULT_STEP_M = 5.0


class ReferenceProfileError(AtcsError, RuntimeError):
    """No trustworthy profile on the stretch ``start_m .. stop_m``: ``status`` is the solver's (not optimal),
    or ``infeasible`` when the ceiling is 0 at two neighbouring grid points (the train cannot pass)."""

    def __init__(self, status: str, start_m: float, stop_m: float, detail: str = ""):
        self.status, self.start_m, self.stop_m = status, start_m, stop_m
        super().__init__(
            f"no reference profile on the stretch start_m = {start_m:g} .. stop_m = {stop_m:g}: "
            f"status {status!r}" + (f" ({detail})" if detail else "")
        )


@dataclass(frozen=True)
class ReferenceProfile:
    """The optimal profile on its grid: speed ``speeds_mps[i]`` at ``positions_m[i]``, constant acceleration
    in between; ``running_time_s`` recomputed from the solution."""

    positions_m: np.ndarray
    speeds_mps: np.ndarray
    running_time_s: float
    solver_status: str

    def speed_at(self, x_m):
        """The target speed at ``x_m`` (float or array): ``E`` linear between grid points, 0 outside the
        stretch (standstill at both stops)."""
        x = np.asarray(x_m, dtype=float)
        if np.isnan(x).any():
            raise ValueError(f"x_m must be a number, got {x_m!r}")
        energy = np.interp(x, self.positions_m, self.speeds_mps**2 / 2, left=0.0, right=0.0)
        speed = np.sqrt(2 * np.maximum(energy, 0.0))
        return float(speed) if speed.ndim == 0 else speed


def _positive(name: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value) or value <= 0:
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")
    return float(value)


def _finite(name: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value):
        raise ValueError(f"{name} must be a finite number, got {value!r}")
    return float(value)


def _ceiling_speeds(ceiling_mps: Callable[[float], float], positions_m: np.ndarray) -> np.ndarray:
    speeds = np.empty(len(positions_m))
    for i, x in enumerate(positions_m):
        v = ceiling_mps(float(x))
        if isinstance(v, bool) or not isinstance(v, numbers.Real) or math.isnan(v) or v < 0:
            raise ValueError(f"ceiling_mps({float(x)!r}) must be a speed >= 0 (or inf), got {v!r}")
        speeds[i] = float(v)
    return speeds


def _time_s(energy: np.ndarray, ds: float) -> float:
    speeds = np.sqrt(2 * energy)
    sums = speeds[:-1] + speeds[1:]
    if (sums <= 0).any():
        return math.inf
    return float(np.sum(2 * ds / sums))


def minimum_time_profile(
    ceiling_mps: Callable[[float], float],
    start_m: float,
    stop_m: float,
    *,
    accel_mps2: float,
    decel_mps2: float,
    step_m: float = DEFAULT_STEP_M,
    conservative: bool = True,
) -> ReferenceProfile:
    """The fastest profile from standstill at ``start_m`` to standstill at ``stop_m`` under ``ceiling_mps``
    (x_m -> m/s, everything included; ``inf`` for no limit), traction ``accel_mps2`` and braking
    ``decel_mps2``, on a uniform grid of step at most ``step_m`` (at least two steps).

    ``conservative``: each inner point keeps under the ceiling at its neighbours too, so that over every
    step (``E`` linear, so under its higher end) the profile is under the ceiling wherever the ceiling is
    monotone on the step (e.g. one MRSP change per step); without it the ceiling holds at grid points only.
    Either way the end points are standstill; over the last step, a ceiling falling to 0 at ``stop_m``
    faster than a constant deceleration does can be exceeded.

    Raises :class:`ReferenceProfileError` unless the solver reports ``optimal`` (and the solution keeps
    the limits within :data:`TOLERANCE`), ``ValueError`` for bad arguments.
    """
    import cvxpy as cp  # heavy: only when a profile is computed

    if not callable(ceiling_mps):
        raise ValueError(f"ceiling_mps must be a callable x_m -> speed, got {ceiling_mps!r}")
    start = _finite("start_m", start_m)
    stop = _finite("stop_m", stop_m)
    if not stop > start:
        raise ValueError(f"stop_m must be after start_m = {start_m!r}, got {stop_m!r}")
    step = _positive("step_m", step_m)
    accel = _positive("accel_mps2", accel_mps2)
    decel = _positive("decel_mps2", decel_mps2)
    steps = max(2, math.ceil((stop - start) / step - 1e-9))
    positions = np.linspace(start, stop, steps + 1)
    ds = (stop - start) / steps
    speeds = _ceiling_speeds(ceiling_mps, positions)
    if conservative:
        ends_free = speeds.copy()
        ends_free[[0, -1]] = math.inf  # the end points are standstill by definition, not a limit
        inner = np.minimum(np.minimum(ends_free[:-2], ends_free[1:-1]), ends_free[2:])
        speeds = np.concatenate(([math.inf], inner, [math.inf]))
    cap = speeds**2 / 2
    bounded = np.flatnonzero(np.isfinite(cap[1:-1])) + 1

    stuck = np.flatnonzero((cap[:-1] == 0) & (cap[1:] == 0))
    if stuck.size:
        x = positions[stuck[0]]
        raise ReferenceProfileError(
            "infeasible", start, stop, f"the ceiling is 0 at the neighbouring grid points {x:g} m and {x + ds:g} m"
        )
    energy = cp.Variable(steps + 1, nonneg=True)
    constraints = [energy[0] == 0, energy[steps] == 0, cp.diff(energy) <= accel * ds, -cp.diff(energy) <= decel * ds]
    if bounded.size:
        constraints.append(energy[bounded] <= cap[bounded])
    running = 2 * ds * cp.sum(cp.inv_pos(cp.sqrt(2 * energy[:-1]) + cp.sqrt(2 * energy[1:])))
    problem = cp.Problem(cp.Minimize(running), constraints)
    try:
        with warnings.catch_warnings():  # an inaccurate solution raises below
            warnings.filterwarnings("ignore", message="Solution may be inaccurate", category=UserWarning)
            problem.solve(solver=SOLVER)
    except cp.SolverError as exc:
        raise ReferenceProfileError("solver_error", start, stop, f"{SOLVER}: {exc}") from exc
    status = str(problem.status)
    if status != cp.OPTIMAL or energy.value is None:
        raise ReferenceProfileError(status, start, stop, f"{SOLVER} did not report {cp.OPTIMAL!r}")

    e = np.clip(np.asarray(energy.value, dtype=float), 0.0, cap)  # solver noise off the ceiling
    e[0] = e[-1] = 0.0
    rise = np.diff(e)
    slack = TOLERANCE * np.maximum(1.0, e[1:])
    if (rise > accel * ds + slack).any() or (-rise > decel * ds + slack).any():
        worst = int(np.argmax(np.maximum(rise / accel, -rise / decel)))
        raise ReferenceProfileError(
            status, start, stop, f"the solution is off the traction or braking limit at {positions[worst]:g} m"
        )
    return ReferenceProfile(positions, np.sqrt(2 * e), _time_s(e, ds), status)


def reference_profiles(
    stops_m: Sequence[float],
    ceiling_for: Callable[[float, float], Callable[[float], float]],
    *,
    accel_mps2: float,
    decel_mps2: float,
    step_m: float = DEFAULT_STEP_M,
    conservative: bool = True,
) -> tuple[ReferenceProfile, ...]:
    """One profile per pair of consecutive ``stops_m`` (increasing); ``ceiling_for(start_m, stop_m)`` gives
    each stretch's ceiling (e.g. :func:`atp_ceiling` for an authority ending at or beyond the stop)."""
    stops = [_finite(f"stops_m[{k}]", s) for k, s in enumerate(stops_m)]
    if len(stops) < 2:
        raise ValueError(f"stops_m needs at least two stops, got {list(stops_m)!r}")
    for k in range(1, len(stops)):
        if not stops[k] > stops[k - 1]:
            raise ValueError(f"stops_m[{k}] = {stops_m[k]!r} is not after stops_m[{k - 1}] = {stops_m[k - 1]!r}")
    return tuple(
        minimum_time_profile(
            ceiling_for(a, b),
            a,
            b,
            accel_mps2=accel_mps2,
            decel_mps2=decel_mps2,
            step_m=step_m,
            conservative=conservative,
        )
        for a, b in pairwise(stops)
    )


def atp_ceiling(
    train_data: TrainData,
    national: NationalData,
    horizon: Horizon,
    *,
    a_est_mps2: float | None = None,
    margin_mps: float = 0.5,
    curve: str = "indication",
    tolerance_mps: float = 1e-4,
) -> Callable[[float], float]:
    """The ceiling x_m -> m/s of a train supervised on ``horizon`` (MRSP, gradient, EoA; exact or float data,
    run on floats): ``curve``'s speed from :func:`~atcs.model.dynamic_profile.curve_speeds_at` (capped by
    the MRSP; the indication curve, the earliest, by default) less ``min(margin_mps, v / 2)``, so strictly
    under the curve wherever it is positive. ``a_est_mps2`` defaults to the train's max acceleration.
    Positions are the max safe front's, as in supervision: the ATO drives its estimated front, so
    ``margin_mps`` should cover the gap.

    The indication curve reaches 0 a few metres short of the EoA (the reaction and build-up times) and
    only about linearly in distance before it: a stop at the EoA itself means a crawl; stop short of it.
    Each evaluation is a bisection (cached per position)."""
    if curve not in CURVE_NAMES:
        raise ValueError(f"curve must be one of {CURVE_NAMES}, got {curve!r}")
    margin = _finite("margin_mps", margin_mps)
    if margin < 0:
        raise ValueError(f"margin_mps must be >= 0, got {margin_mps!r}")
    _positive("tolerance_mps", tolerance_mps)
    train_data, national = float_record(train_data), float_record(national)
    horizon = Horizon(
        as_float(horizon.mrsp), as_float(horizon.gradient), float(horizon.eoa_m), float(horizon.eoa_speed_mps)
    )
    a_est = float(train_data.max_acceleration_mps2) if a_est_mps2 is None else _finite("a_est_mps2", a_est_mps2)
    field = f"{curve}_mps"

    @lru_cache(maxsize=65536)
    def ceiling_mps(x_m: float) -> float:
        speeds = curve_speeds_at(train_data, national, horizon, float(x_m), a_est, tolerance_mps=tolerance_mps)
        v = max(float(getattr(speeds, field)), 0.0)  # bisection gives the low end: at or under the curve
        return v - min(margin, v / 2)

    return ceiling_mps
