"""The train- and line-dependent properties of a user's configuration (:mod:`atcs.model.configuration`), for
``atcs prove --config``; docs/configuration.md states what they cover and what not.

For each train on each line, with the train's data and the configuration's national values:

- every **gradient transition** of the line (each pair of adjacent values of its profile compensated by the
  train's length, the breakpoint symbolic; a line of one gradient gives the pair of it with itself): the curve
  properties (CRV-01, 02, 06, 08, 10, 11; CRV-12 for a train with a normal service brake), and those of the
  curves preprocessed per authority (CRV-13, 14, 16, 17; not for a train given as ranges);
- the **whole line**: CRV-08, the EBD the braking curve through every segment of the line's compensated profile
  (breakpoints and values fixed), to any target on the line;
- the **closed loop on the line's profile**: CL-00 to CL-06 (no EoA overrun, under the ceiling) for an end of
  authority anywhere on the line and any MRSP up to the line's top speed limit, one :class:`Window` per stretch of
  at most 800 m of ends of authority, each with its CL-07 obligation (docs/configuration.md "Windows" argues why
  the windows' theorems hold on the line);
- **each speed decrease** of the line's MRSP as a target: CL-08 and CL-09 (past the decrease, under the lower
  limit's EBI ceiling with the closed loop's margin) in a :class:`DecreaseWindow`, with its CL-07 obligation;
- a **limit of authority** (an end of authority of target speed above 0, supervised as a speed decrease) anywhere
  in each window's stretch, of any target speed up to the top limit: CL-08 and CL-09, with a CL-07 for every
  target speed;
- each window's side condition CL-10 (more braking commanded admits fewer motions).

The closed loop runs on whole cycles: the train's T_be and T_traction are rounded up to whole cycles of the
configuration's ``cycle_s`` (at least one), so the ATP and the plant both assume the (not shorter) rounded times.
Names: ``curves.<kind>_<train>_<line>_<j>`` for the transition ``j``, ``curves.ebd_is_braking_curve_<train>_<line>
_whole``, ``closed_loop.<kind>_<train>_<line>_w<k>`` for the window ``k``, ``..._d<k>`` for the ``k``-th decrease.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import re
from dataclasses import dataclass
from fractions import Fraction

from atcs.model.braking_data import guidance_data
from atcs.model.closed_loop import CLOSED_LOOP, DECREASE_LOOP, ClosedLoopParams, whole_cycles, worst_acceleration_mps2
from atcs.model.configuration import Configuration, ConfiguredTrain, Line, train_with
from atcs.model.curves import CURVES, Target, bec_speed_and_distance, curve_gradient, curve_target, ebd_speed2_at
from atcs.model.dynamic_profile import ceilings, ebd_foot_mps
from atcs.model.node import as_dict
from atcs.model.ops.exact import EXACT
from atcs.model.plant import plant_gradient
from atcs.model.profile import KMH_PER_MPS, Profile
from atcs.model.psl import extend_by_train_length
from atcs.model.train_data import preset_data, whole_cycle_train
from atcs.properties.closed_loop import (
    braking_order_property,
    ceiling_margin_mps,
    closed_loop_properties,
    decrease_properties,
)
from atcs.properties.curves import curve_properties, sized_node, table_properties
from atcs.properties.property import Assumption, Property

__all__ = [
    "closed_loop_gap",
    "compensated_gradients",
    "configuration_gaps",
    "configuration_properties",
    "curve_family",
    "decrease_windows",
    "gradient_transitions",
    "layout_train",
    "loa_in_bands",
    "loop_family",
    "speed_decreases",
    "table_family",
]


def _slug(name: str) -> str:
    """``name`` as a part of a property name: lower case letters, digits and underscores, a letter first."""
    slug = re.sub(r"[^a-z0-9_]+", "_", name.lower()).strip("_")
    return slug if slug[:1].isalpha() else f"t_{slug}"


def compensated_gradients(line: Line, train_length_m) -> Profile:
    """``line``'s gradient profile compensated by the train's length (:func:`~atcs.model.psl.extend_by_train_length`)
    as a well-formed profile for the proofs: adjacent equal values merged, segments of no length on the line
    dropped (a lower gradient binds a train's length past the line's end, where no target lies). Its first value is
    the line's first, the one a braking walk extends behind the line's start: at the start only the first segment
    binds the front."""
    c = extend_by_train_length(EXACT, line.gradients, train_length_m)
    ends = (*c.starts_m[1:], c.end_m)
    starts, values = [], []
    for start, end, value in zip(c.starts_m, ends, c.values, strict=True):
        if start < min(end, c.end_m) and not (values and values[-1] == value):
            starts.append(start)
            values.append(value)
    return Profile(tuple(starts), tuple(values), c.end_m)


def gradient_transitions(profile: Profile) -> tuple[tuple[Fraction, Fraction], ...]:
    """The distinct pairs of adjacent values of ``profile``, in order of first appearance; ``(g, g)`` for a
    profile of one value."""
    values = profile.values
    pairs = tuple(dict.fromkeys(itertools.pairwise(values)))
    return pairs or ((values[0], values[0]),)


def _train_line(config: Configuration, t: ConfiguredTrain, line: Line) -> tuple[Property, ...]:
    return curve_family(config, t, line) + table_family(t, line) + loop_family(config, t, line)


def table_family(t: ConfiguredTrain, line: Line) -> tuple[Property, ...]:
    """The properties of the curves preprocessed per authority (CRV-13, 14, 16, 17) of train ``t`` on every
    gradient transition of ``line``, named as :func:`curve_family`'s (a train given as ranges does not have them)."""
    tag = f"{_slug(t.name)}_{_slug(line.name)}"
    data = {**as_dict(t.train), **as_dict(t.national)}
    compensated = compensated_gradients(line, t.train.train_length_m)
    return tuple(
        prop
        for j, pair in enumerate(gradient_transitions(compensated))
        for prop in table_properties(f"{tag}_{j}", {**data, "gradient_permille": pair})
    )


def curve_family(config: Configuration, t: ConfiguredTrain, line: Line, train=None, suffix="") -> tuple[Property, ...]:
    """The curve properties of train ``t`` on ``line`` (module docstring), with ``train``'s data in place of the
    train's own when given, and ``suffix`` after the train and line in their names."""
    train = t.train if train is None else train
    tag = f"{_slug(t.name)}_{_slug(line.name)}{suffix}"
    guidance = None if t.rail is None else guidance_data(t.rail)
    guidance = None if guidance is None else as_dict(guidance)
    curve_data = {**as_dict(train), **as_dict(t.national)}
    compensated = compensated_gradients(line, train.train_length_m)
    props = []
    for j, pair in enumerate(gradient_transitions(compensated)):
        props += curve_properties(f"{tag}_{j}", {**curve_data, "gradient_permille": pair}, guidance)
    whole = {
        **curve_data,
        "gradient_starts_m": compensated.starts_m,
        "gradient_permille": compensated.values,
        "line_end_m": compensated.end_m,
    }
    props += [p for p in curve_properties(f"{tag}_whole", whole) if p.requirement == "CRV-08"]
    return tuple(props)


@dataclass(frozen=True)
class Window:
    """A window of a line for the closed loop (docs/configuration.md "Windows"): the closed-loop theorems for an
    end of authority in ``[eoa_from_m, eoa_to_m]`` are proved on ``profile``, which is the line's compensated
    profile from ``start_m`` to ``eoa_to_m`` and its steepest downhill elsewhere; ``speed_cap_mps`` bounds every
    speed the ATP computes a curve location for (the measured speed, and V_bec, at the ceiling of the line's top
    speed limit plus the closed loop's margin)."""

    index: int
    eoa_from_m: Fraction
    eoa_to_m: Fraction
    start_m: Fraction
    profile: Profile
    speed_cap_mps: Fraction


def _merged(starts, values, end_m) -> Profile:
    kept_starts, kept_values = [], []
    for start, value in zip(starts, values, strict=True):
        if not (kept_values and kept_values[-1] == value):
            kept_starts.append(start)
            kept_values.append(value)
    return Profile(tuple(kept_starts), tuple(kept_values), end_m)


def _loop_params(loop_data: dict, line: Line, profile: Profile, eoa_m):
    """The closed loop's parameters with the line's top speed limit as the MRSP and no odometry error."""
    values = {
        **loop_data,
        "gradient_starts_m": profile.starts_m,
        "gradient_permille": profile.values,
        "line_end_m": profile.end_m,
        "mrsp_mps": max(line.speed_limits.values),
        "eoa_m": eoa_m,
        "position_error_m": Fraction(0),
    }
    return ClosedLoopParams(**values)


class _WithCycle:
    """Train and national parameters (a curve's, or a closed loop's) read as a closed loop's, with the cycle
    given apart."""

    def __init__(self, p, cycle_s):
        self._p, self.cycle_s = p, cycle_s

    def __getattr__(self, name):
        return getattr(self._p, name)


def speed_cap(o, p, top_mps, cycle_s, n_t: int, n_be: int):
    """The highest speed the ATP computes a curve location for (:class:`Window`), from the train and national
    parameters ``p`` (symbolic or not) with ``n_t``/``n_be`` whole cycles of ``cycle_s`` to traction cut-off and
    brake build-up: V_bec at the measured speed ``MRSP + dV_ebi + the closed loop's margin + V_ura``, the MRSP
    ``top_mps``, the line's top speed limit."""
    q = _WithCycle(p, o.const(cycle_s))
    measured = ceilings(o, p, o.const(top_mps)).ebi_mps + ceiling_margin_mps(o, q, n_be, n_t) + p.v_ura_mps
    zero = o.const(0)
    v_bec, _ = bec_speed_and_distance(o, p, p, Target(zero, zero, zero), measured, worst_acceleration_mps2(o, p))
    return o.max(measured, v_bec)


def speed_cap_mps(loop_data: dict, line: Line, profile: Profile) -> Fraction:
    """:func:`speed_cap` of the closed loop's data on ``line``, exactly."""
    p = _loop_params(loop_data, line, profile, Fraction(0))
    n_t, n_be = whole_cycles("window", loop_data)
    return speed_cap(EXACT, p, max(line.speed_limits.values), loop_data["cycle_s"], n_t, n_be)


MAX_WINDOW_EOA_M = 800
"""The longest stretch of ends of authority one window covers (m): a segment longer than this gets several windows.
z3 proves a window's braking invariant in seconds for an 800 m stretch and not in 600 s for 1,600 m
(docs/configuration.md "Windows")."""


def _window_start(profile: Profile, loop_data: dict, line: Line, target: Target, k: int, cap_mps) -> int:
    """The index of the last breakpoint of ``profile``, behind ``target`` and at most segment ``k``, at which the
    EBD of ``target`` is already above the speed cap (0 if there is none)."""
    p = _loop_params(loop_data, line, profile, target.location_m)
    reached = (
        j
        for j in range(k, 0, -1)  # nearest first: the EBD's speed only grows backward
        if profile.starts_m[j] < target.location_m
        and ebd_speed2_at(EXACT, p, p, plant_gradient(p), target, profile.starts_m[j]) >= cap_mps * cap_mps
    )
    return next(reached, 0)


def _window_profile(profile: Profile, first: int, k: int, to_m) -> Profile:
    """``profile`` on segments ``first`` to ``k`` up to ``to_m``, its steepest downhill elsewhere."""
    steepest = min(profile.values)
    starts = [profile.starts_m[j] for j in range(first, k + 1)]
    values = [profile.values[j] for j in range(first, k + 1)]
    if first > 0:
        starts, values = [Fraction(0), *starts], [steepest, *values]
    if to_m < profile.end_m:
        starts, values = [*starts, to_m], [*values, steepest]
    return _merged(starts, values, profile.end_m)


def line_windows(profile: Profile, loop_data: dict, line: Line) -> tuple[Window, ...]:
    """The windows of the compensated ``profile``: each segment's ends of authority in stretches of at most
    :data:`MAX_WINDOW_EOA_M`, one window each. A window starts at the last breakpoint behind its stretch where
    the EBD of an end of authority at the stretch's start is already above the speed cap (at the line's start if
    there is none)."""
    cap = speed_cap_mps(loop_data, line, profile)
    ends = (*profile.starts_m[1:], profile.end_m)
    stretches = []
    for k, (start, end) in enumerate(zip(profile.starts_m, ends, strict=True)):
        pieces = math.ceil((end - start) / MAX_WINDOW_EOA_M)
        stretches += [
            (k, start + (end - start) * m / pieces, start + (end - start) * (m + 1) / pieces) for m in range(pieces)
        ]
    windows = []
    for index, (k, eoa_from, eoa_to) in enumerate(stretches):
        first = _window_start(profile, loop_data, line, Target(eoa_from, Fraction(0), Fraction(0)), k, cap)
        window = _window_profile(profile, first, k, eoa_to)
        windows.append(Window(index, eoa_from, eoa_to, profile.starts_m[first], window, cap))
    return tuple(windows)


@dataclass(frozen=True)
class DecreaseWindow:
    """A window of a line for one speed decrease of its speed limits (docs/configuration.md "Speed decreases"): the
    decrease's theorems are proved on ``profile``, the line's compensated profile from ``start_m`` to the decrease
    and its steepest downhill elsewhere, with the MRSP the line's top speed limit before the decrease and
    ``speed_after_mps`` from it on."""

    index: int
    location_m: Fraction
    speed_after_mps: Fraction
    start_m: Fraction
    profile: Profile
    speed_cap_mps: Fraction


def speed_decreases(line: Line) -> tuple[tuple[Fraction, Fraction], ...]:
    """``(location, lower speed)`` of each decrease of ``line``'s speed limits."""
    limits = line.speed_limits
    return tuple(
        (start, after)
        for start, before, after in zip(limits.starts_m[1:], limits.values, limits.values[1:], strict=False)
        if after < before
    )


def decrease_windows(profile: Profile, loop_data: dict, line: Line, national) -> tuple[DecreaseWindow, ...]:
    """One window per speed decrease of ``line`` on its compensated ``profile``: from the last breakpoint behind it
    where the decrease's EBD is already above the speed cap (as :func:`line_windows`) to the decrease."""
    cap = speed_cap_mps(loop_data, line, profile)
    windows = []
    for index, (location, after) in enumerate(speed_decreases(line)):
        k = max(j for j, start in enumerate(profile.starts_m) if start < location)
        target = Target(location, after, ebd_foot_mps(EXACT, national, after))
        first = _window_start(profile, loop_data, line, target, k, cap)
        window = _window_profile(profile, first, k, location)
        windows.append(DecreaseWindow(index, location, after, profile.starts_m[first], window, cap))
    return tuple(windows)


def _in_window(w: Window, top_mps: Fraction) -> Assumption:
    def holds(o, p, s, i):
        return o.and_(o.const(w.eoa_from_m) <= p.eoa_m, p.eoa_m <= o.const(w.eoa_to_m), p.mrsp_mps <= o.const(top_mps))

    return Assumption(
        "window",
        f"the end of authority lies in [{w.eoa_from_m}, {w.eoa_to_m}] m, the MRSP is at most the line's top speed "
        f"limit ({float(top_mps * KMH_PER_MPS):g} km/h)",
        holds,
    )


def _reach(
    name: str, what: str, start_m, cap_mps, loop_data: dict, profile: Profile, top_mps, target: dict, assumptions
):
    """CL-07: the EBD of ``what`` (the target ``target`` fixes, under ``assumptions``), on the line's own profile,
    is above the speed cap (:func:`speed_cap`, of the node's own parameters, so a train data range covers it too)
    at the window's start ``start_m``, so every curve location the ATP computes for it lies within the window."""
    fixed = {key: loop_data[key] for key in CURVES.sorts("params") if key in loop_data}
    fixed |= {
        "gradient_starts_m": profile.starts_m,
        "gradient_permille": profile.values,
        "line_end_m": profile.end_m,
        **target,
    }
    n_t, n_be = whole_cycles("window", loop_data)
    cycle_s = loop_data["cycle_s"]

    def holds(o, p, s, i, out, nxt):
        speed2 = ebd_speed2_at(o, p, p, curve_gradient(p), curve_target(p), o.const(start_m))
        cap = speed_cap(o, p, top_mps, cycle_s, n_t, n_be)
        return cap * cap <= speed2

    return Property(
        name=name,
        requirement="CL-07",
        seed="000 §2.4; docs/configuration.md windows",
        text=(
            f"the EBD of {what} is above the speed cap (V_bec at the measured speed of the closed loop's ceiling at "
            f"{float(top_mps * KMH_PER_MPS):g} km/h; {float(cap_mps * KMH_PER_MPS):.3f} km/h with the train's "
            f"data) at the window's start, {start_m} m"
        ),
        node=sized_node(CURVES, fixed),
        holds=holds,
        assumptions=assumptions,
        fixed_params=fixed,
        max_k=0,
    )


def _window_reach(name: str, w: Window, loop_data: dict, profile: Profile, top_mps) -> Property:
    """CL-07 for the ends of authority of window ``w``."""

    def in_window(o, p, s, i):
        return o.and_(o.const(w.eoa_from_m) <= p.target_m, p.target_m <= o.const(w.eoa_to_m))

    stretch = f"[{w.eoa_from_m}, {w.eoa_to_m}] m"
    return _reach(
        name,
        f"an end of authority anywhere in {stretch}",
        w.start_m,
        w.speed_cap_mps,
        loop_data,
        profile,
        top_mps,
        {"target_speed_mps": Fraction(0), "target_ebd_foot_mps": Fraction(0)},
        (Assumption("eoa_in_window", f"the target lies in {stretch}", in_window),),
    )


def _loa_reach(name: str, w: Window, loop_data: dict, profile: Profile, top_mps) -> Property:
    """CL-07 for a limit of authority anywhere in window ``w``'s stretch, of any target speed up to ``top_mps``."""

    def loa(o, p, s, i):
        return o.and_(
            o.const(w.eoa_from_m) <= p.target_m,
            p.target_m <= o.const(w.eoa_to_m),
            o.const(0) <= p.target_speed_mps,
            p.target_speed_mps <= o.const(top_mps),
            o.eq(p.target_ebd_foot_mps, ebd_foot_mps(o, p, p.target_speed_mps)),
        )

    stretch = f"[{w.eoa_from_m}, {w.eoa_to_m}] m"
    what = f"a limit of authority anywhere in {stretch}, of any target speed up to the top limit"
    text = f"the target lies in {stretch}, its speed up to the top limit, its EBD's foot V + dV_ebi(V)"
    assumption = Assumption("loa_in_window", text, loa)
    return _reach(name, what, w.start_m, w.speed_cap_mps, loop_data, profile, top_mps, {}, (assumption,))


def _loa_in_window(w: Window) -> Assumption:
    def holds(o, p, s, i):
        return o.and_(o.const(w.eoa_from_m) <= p.decrease_m, p.decrease_m <= o.const(w.eoa_to_m))

    return Assumption("window", f"the limit of authority lies in [{w.eoa_from_m}, {w.eoa_to_m}] m", holds)


def _decrease_reach(name: str, w: DecreaseWindow, foot_mps, loop_data: dict, profile: Profile, top_mps) -> Property:
    """CL-07 for the speed decrease of window ``w``."""
    target = {"target_m": w.location_m, "target_speed_mps": w.speed_after_mps, "target_ebd_foot_mps": foot_mps}
    what = f"the speed decrease to {float(w.speed_after_mps * KMH_PER_MPS):g} km/h at {w.location_m} m"
    return _reach(name, what, w.start_m, w.speed_cap_mps, loop_data, profile, top_mps, target, ())


def loop_family(config: Configuration, t: ConfiguredTrain, line: Line, train=None, suffix="") -> tuple[Property, ...]:
    """The closed-loop theorems of train ``t`` on ``line`` (module docstring; none when :func:`closed_loop_gap`
    says why), one set per :class:`Window`, with each window's CL-07 obligation (for a window not from the line's
    start), with ``train``'s data and ``suffix`` as :func:`curve_family`. The windows are laid out with
    :func:`layout_train` (so the family has the same properties whatever ``train`` is); CL-07 is proved with
    ``train``'s data, or over a cell of its ranges."""
    if closed_loop_gap(t):
        return ()
    train = t.train if train is None else train
    tag = f"{_slug(t.name)}_{_slug(line.name)}{suffix}"
    loop_data = preset_data(whole_cycle_train(train, config.cycle_s), t.national, config.cycle_s)
    del loop_data["gradient_permille"]
    own_data = preset_data(whole_cycle_train(layout_train(t), config.cycle_s), t.national, config.cycle_s)
    del own_data["gradient_permille"]
    profile = compensated_gradients(line, train.train_length_m)
    top = max(line.speed_limits.values)
    props = []
    for w in line_windows(profile, own_data, line):
        fixed = {
            **loop_data,
            "gradient_starts_m": w.profile.starts_m,
            "gradient_permille": w.profile.values,
            "line_end_m": w.profile.end_m,
        }
        loop_node = sized_node(CLOSED_LOOP, fixed)
        window = _in_window(w, top)
        props += [
            dataclasses.replace(p, node=loop_node, assumptions=(*p.assumptions, window))
            for p in closed_loop_properties(f"{tag}_w{w.index}", fixed)
        ]
        if w.start_m > 0:
            props.append(_window_reach(f"closed_loop.window_reach_{tag}_w{w.index}", w, loop_data, profile, top))
        props.append(braking_order_property(f"closed_loop.braking_order_{tag}_w{w.index}", fixed))
        loa = {key: value for key, value in fixed.items() if key in DECREASE_LOOP.sorts("params")} | {"mrsp_mps": top}
        loa_node, in_window = sized_node(DECREASE_LOOP, loa), _loa_in_window(w)
        invariant, under = (
            dataclasses.replace(p, node=loa_node, assumptions=(*p.assumptions, in_window))
            for p in decrease_properties(f"{tag}_w{w.index}", loa, target="loa")
        )
        props += loa_in_bands(invariant, under, Fraction(0), top)
        if w.start_m > 0:
            props.append(_loa_reach(f"closed_loop.loa_reach_{tag}_w{w.index}", w, loop_data, profile, top))
    for w in decrease_windows(profile, own_data, line, t.national):
        foot = ebd_foot_mps(EXACT, t.national, w.speed_after_mps)
        fixed = {
            **loop_data,
            "gradient_starts_m": w.profile.starts_m,
            "gradient_permille": w.profile.values,
            "line_end_m": w.profile.end_m,
            "mrsp_mps": top,
            "decrease_m": w.location_m,
            "mrsp_after_mps": w.speed_after_mps,
        }
        decrease_node = sized_node(DECREASE_LOOP, fixed)
        props += [dataclasses.replace(p, node=decrease_node) for p in decrease_properties(f"{tag}_d{w.index}", fixed)]
        if w.start_m > 0:
            props.append(
                _decrease_reach(f"closed_loop.decrease_reach_{tag}_d{w.index}", w, foot, loop_data, profile, top)
            )
        props.append(braking_order_property(f"closed_loop.braking_order_{tag}_d{w.index}", fixed))
    return tuple(props)


LOA_BAND_RESOLUTION_MPS = Fraction(10) / KMH_PER_MPS
"""The narrowest band of target speeds a limit of authority's theorems are split into (:func:`loa_in_bands`)."""


@dataclass(frozen=True)
class _SpeedBand:
    """``low <= mrsp_after_mps <= high``; compared by value, so that a part and its lemma share the assumption."""

    low_mps: Fraction
    high_mps: Fraction

    def __call__(self, o, p, s, i):
        return o.and_(o.const(self.low_mps) <= p.mrsp_after_mps, p.mrsp_after_mps <= o.const(self.high_mps))


def loa_in_bands(invariant: Property, under: Property, low_mps, high_mps) -> tuple[Property, Property]:
    """A limit of authority's CL-08 ``invariant`` and CL-09 ``under`` (its lemma), each claimed for target speeds in
    ``[low_mps, high_mps]``, with a split (:mod:`atcs.proofs.engine.split`) into the lower and upper half of that band
    while it is wider than :data:`LOA_BAND_RESOLUTION_MPS`: the half of CL-09 rests on the same half of CL-08. The
    target speed is a parameter, fixed for a run, so the bands' theorems together are the whole band's."""
    if high_mps - low_mps <= LOA_BAND_RESOLUTION_MPS:
        return invariant, under
    middle = (low_mps + high_mps) / 2
    given = tuple(tuple(a for a in p.assumptions if a.name != "target_speed_band") for p in (invariant, under))

    def half(j: int, low, high) -> tuple[Property, Property]:
        band = Assumption(
            "target_speed_band",
            f"the target speed is in [{float(low * KMH_PER_MPS):g}, {float(high * KMH_PER_MPS):g}] km/h",
            _SpeedBand(low, high),
        )
        part = dataclasses.replace(invariant, name=f"{invariant.name}_h{j}", assumptions=(*given[0], band), split=None)
        lemmas = tuple(part.name if lemma == invariant.name else lemma for lemma in under.lemmas)
        above = dataclasses.replace(
            under, name=f"{under.name}_h{j}", assumptions=(*given[1], band), lemmas=lemmas, split=None
        )
        return loa_in_bands(part, above, low, high)

    def halves(which: int) -> tuple[Property, Property]:
        lower, upper = half(0, low_mps, middle), half(1, middle, high_mps)
        return lower[which], upper[which]

    return (
        dataclasses.replace(invariant, split=lambda: halves(0)),
        dataclasses.replace(under, split=lambda: halves(1)),
    )


_FARTHEST_REACH = {
    "t_be_s": max,
    "t_traction_s": max,
    "max_acceleration_mps2": max,
    "v_ura_mps": max,
    "emergency_deceleration_scale": min,
    "service_deceleration_scale": min,
    "rotating_mass_uphill_percent": max,
    "rotating_mass_downhill_percent": min,
}
"""For each range field, the end of its range that raises the speed cap or weakens the EBD."""


def layout_train(t: ConfiguredTrain):
    """The train data the windows of ``t`` are laid out with: its own, each range field at the end of its range
    that raises the speed cap or weakens the EBD (:data:`_FARTHEST_REACH`), so one layout serves every cell.
    The layout is a choice, not an assumption: CL-07 is proved for every value of a cell, and fails where the
    layout does not hold."""
    train = t.train
    for r in t.ranges:
        train = train_with(train, r.field, _FARTHEST_REACH[r.field](r.min, r.max))
    return train


def closed_loop_gap(t: ConfiguredTrain) -> str:
    """Why the closed-loop theorems are not made for train ``t`` (empty if they are): the closed loop's plant
    guarantees one emergency deceleration at every speed, so a brake of several speed steps is not modelled."""
    steps = len(t.train.emergency_decelerations_mps2)
    if steps == 1:
        return ""
    return (
        f"{t.name}: the closed-loop theorems (CL-00 to CL-06) are not made: its emergency brake has {steps} speed "
        "steps, and the closed loop's plant guarantees one deceleration at every speed"
    )


def configuration_gaps(config: Configuration) -> tuple[str, ...]:
    """What ``atcs prove --config`` does not prove for ``config`` (one line each)."""
    return tuple(gap for t in config.trains if (gap := closed_loop_gap(t)))


def configuration_properties(config: Configuration) -> tuple[Property, ...]:
    """Every train- and line-dependent property of ``config`` (module docstring)."""
    return tuple(p for t in config.trains for line in config.lines for p in _train_line(config, t, line))
