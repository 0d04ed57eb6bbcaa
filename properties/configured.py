"""The train- and line-dependent properties of a user's configuration (:mod:`atcs.model.configuration`), for
``atcs prove --config``; docs/configuration.md states what they cover and what not.

For each train on each line, with the train's data and the configuration's national values:

- every **gradient transition** of the line (each pair of adjacent values of its profile compensated by the
  train's length, the breakpoint symbolic; a line of one gradient gives the pair of it with itself): the curve
  properties (CRV-01, 02, 06, 08, 10, 11; CRV-12 for a train with a normal service brake) and the closed-loop
  theorems (CL-00 to CL-06: no EoA overrun, under the ceiling, for any end of authority and any constant MRSP);
- the **whole line**: CRV-08, the EBD the braking curve through every segment of the line's compensated profile
  (breakpoints and values fixed), to any target on the line.

The closed loop runs on whole cycles: the train's T_be and T_traction are rounded up to whole cycles of the
configuration's ``cycle_s`` (at least one), so the ATP and the plant both assume the (not shorter) rounded times.
Names: ``curves.<kind>_<train>_<line>_<j>`` and ``closed_loop.<kind>_<train>_<line>_<j>`` for the transition
``j``, ``curves.ebd_is_braking_curve_<train>_<line>_whole``.
"""

from __future__ import annotations

import dataclasses
import itertools
import re
from fractions import Fraction

from atcs.model.braking_data import guidance_data
from atcs.model.closed_loop import CLOSED_LOOP
from atcs.model.configuration import Configuration, ConfiguredTrain, Line
from atcs.model.node import as_dict
from atcs.model.ops.exact import EXACT
from atcs.model.profile import Profile
from atcs.model.psl import extend_by_train_length
from atcs.model.train_data import preset_data, whole_cycle_train
from atcs.properties.closed_loop import closed_loop_properties
from atcs.properties.curves import curve_properties, sized_node
from atcs.properties.property import Property

__all__ = [
    "closed_loop_gap",
    "compensated_gradients",
    "configuration_gaps",
    "configuration_properties",
    "curve_family",
    "gradient_transitions",
    "loop_family",
]


def _slug(name: str) -> str:
    """``name`` as a part of a property name: lower case letters, digits and underscores, a letter first."""
    slug = re.sub(r"[^a-z0-9_]+", "_", name.lower()).strip("_")
    return slug if slug[:1].isalpha() else f"t_{slug}"


def compensated_gradients(line: Line, train_length_m) -> Profile:
    """``line``'s gradient profile compensated by the train's length (:func:`~atcs.model.psl.extend_by_train_length`)
    as a well-formed profile for the proofs: adjacent equal values merged, segments of no length on the line
    dropped (a lower gradient binds a train's length past the line's end, where no target lies), except a
    leading one whose value the braking walk extends behind the line's start: that one is given 1 m, the rest
    shifted 1 m ahead (the proofs hold for every target on the line, so a shift changes nothing they cover)."""
    c = extend_by_train_length(EXACT, line.gradients, train_length_m)
    ends = (*c.starts_m[1:], c.end_m)
    behind = c.values[0]
    starts, values = [], []
    for start, end, value in zip(c.starts_m, ends, c.values, strict=True):
        if start < min(end, c.end_m) and not (values and values[-1] == value):
            starts.append(start)
            values.append(value)
    if values[0] == behind:
        return Profile(tuple(starts), tuple(values), c.end_m)
    return Profile((Fraction(0), *(s + 1 for s in starts)), (behind, *values), c.end_m + 1)


def gradient_transitions(profile: Profile) -> tuple[tuple[Fraction, Fraction], ...]:
    """The distinct pairs of adjacent values of ``profile``, in order of first appearance; ``(g, g)`` for a
    profile of one value."""
    values = profile.values
    pairs = tuple(dict.fromkeys(itertools.pairwise(values)))
    return pairs or ((values[0], values[0]),)


def _train_line(config: Configuration, t: ConfiguredTrain, line: Line) -> tuple[Property, ...]:
    return curve_family(config, t, line) + loop_family(config, t, line)


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


def loop_family(config: Configuration, t: ConfiguredTrain, line: Line, train=None, suffix="") -> tuple[Property, ...]:
    """The closed-loop theorems of train ``t`` on ``line`` (module docstring; none when :func:`closed_loop_gap`
    says why), with ``train``'s data and ``suffix`` as :func:`curve_family`."""
    if closed_loop_gap(t):
        return ()
    train = t.train if train is None else train
    tag = f"{_slug(t.name)}_{_slug(line.name)}{suffix}"
    loop_data = preset_data(whole_cycle_train(train, config.cycle_s), t.national, config.cycle_s)
    props = []
    for j, pair in enumerate(gradient_transitions(compensated_gradients(line, train.train_length_m))):
        fixed = {**loop_data, "gradient_permille": pair}
        loop_node = sized_node(CLOSED_LOOP, fixed)
        props += [dataclasses.replace(p, node=loop_node) for p in closed_loop_properties(f"{tag}_{j}", fixed)]
    return tuple(props)


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
