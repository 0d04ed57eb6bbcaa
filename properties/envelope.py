"""A configured train's properties over a cell of its ranges of train data (``[trains.ranges]``,
docs/configuration.md "Ranges of train data"): proofs that hold for every value in the cell, never for samples.

A cell gives each range field an interval. The properties of the train on a line are made again with the cell's
fields as symbolic parameters, each constrained to its interval by an assumption (:func:`range_assumption`):

- a scalar field (T_be, T_traction, A_max, V_ura, M_rotating) is its own parameter;
- a brake's deceleration scale makes every step of that brake's deceleration table symbolic, tied to the train's
  own table by one factor in the interval (``a_j * a0_0 == a_0 * a0_j``: linear, the table's shape kept); the
  closed loop's plant then brakes at K times the scaled table's lowest step, as :func:`preset_data` makes it.

The closed loop acts on whole cycles: its plant's delays and the ATP's rounded T_be and T_traction
(:func:`~atcs.model.train_data.whole_cycle_train`) are whole numbers of cycles, which unroll the node. A cell's
interval of T_be or T_traction therefore rounds to a finite set of whole-cycle times, and the closed-loop
theorems are made once for each (:func:`cell_families`): every value of the interval rounds to one of them.
"""

from __future__ import annotations

import dataclasses
import hashlib
import itertools
import math
from dataclasses import dataclass
from fractions import Fraction

from atcs.model.configuration import Configuration, ConfiguredTrain, Line, train_with
from atcs.model.curves import adhesion_factor
from atcs.model.ops.exact import EXACT
from atcs.properties.configured import curve_family, loop_family
from atcs.properties.property import Assumption, Property

__all__ = ["WHOLE_CYCLE_FIELDS", "Cell", "cell_families", "range_assumption"]

WHOLE_CYCLE_FIELDS = ("t_be_s", "t_traction_s")
"""The range fields the closed loop takes in whole cycles (module docstring)."""


@dataclass(frozen=True)
class Cell:
    """An interval ``[low, high]`` for each range field, in the order of the configuration's ranges."""

    bounds: tuple[tuple[str, Fraction, Fraction], ...]

    @property
    def id(self) -> str:
        """A short name of the cell, the same in every run (its bounds' digest)."""
        text = ";".join(f"{f}={lo}..{hi}" for f, lo, hi in self.bounds)
        return hashlib.sha256(text.encode()).hexdigest()[:8]

    def low(self) -> dict[str, Fraction]:
        return {f: lo for f, lo, _ in self.bounds}

    def describe(self) -> str:
        return ", ".join(f"{f} in [{float(lo):g}, {float(hi):g}]" for f, lo, hi in self.bounds)


def range_assumption(field: str, low: Fraction, high: Fraction, train) -> Assumption:
    """The assumption that the parameter(s) of range field ``field`` lie in ``[low, high]`` (module docstring);
    ``train`` is the configured train's own data, whose brake tables a scale multiplies."""
    text = f"{field} in [{low}, {high}]"
    if field.endswith("_deceleration_scale"):
        key = f"{field.removesuffix('_deceleration_scale')}_decelerations_mps2"
        own = getattr(train, key)

        def holds(o, p, s, i):
            a = getattr(p, key)
            shape = [o.eq(a[j] * o.const(own[0]), a[0] * o.const(own[j])) for j in range(1, len(own))]
            return o.and_(o.const(own[0] * low) <= a[0], a[0] <= o.const(own[0] * high), *shape)

        return Assumption(f"range_{field}", text, holds)

    def holds(o, p, s, i):
        value = getattr(p, field)
        return o.and_(o.const(low) <= value, value <= o.const(high))

    return Assumption(f"range_{field}", text, holds)


def _params(field: str) -> tuple[str, ...]:
    """The node parameters a range field sets."""
    if field == "emergency_deceleration_scale":
        return ("emergency_decelerations_mps2", "guaranteed_deceleration_mps2")
    if field == "service_deceleration_scale":
        return ("service_decelerations_mps2",)
    return (field,)


def _guaranteed_deceleration(t: ConfiguredTrain) -> Assumption:
    """The closed loop's plant brakes at K times the scaled table's lowest step (:func:`preset_data`), tied to the
    symbolic table's first step: ``g * a0_0 == K * min(a0) * a_0``."""
    own = t.train.emergency_decelerations_mps2
    g0 = adhesion_factor(EXACT, t.train, t.national) * min(own)

    def holds(o, p, s, i):
        return o.eq(p.guaranteed_deceleration_mps2 * o.const(own[0]), o.const(g0) * p.emergency_decelerations_mps2[0])

    return Assumption("range_guaranteed_deceleration", "the plant brakes at K * min(A_brake_emergency)", holds)


def _symbolic(prop: Property, cell: Cell, t: ConfiguredTrain, enumerated: tuple[str, ...]) -> Property:
    """``prop`` with the cell's fields (but ``enumerated``) symbolic within their intervals."""
    fixed = dict(prop.fixed_params)
    added = []
    for field, low, high in cell.bounds:
        if field in enumerated:
            continue
        params = [key for key in _params(field) if key in fixed]
        if not params:
            continue
        for key in params:
            del fixed[key]
        added.append(range_assumption(field, low, high, t.train))
        if "guaranteed_deceleration_mps2" in params:
            added.append(_guaranteed_deceleration(t))
    return dataclasses.replace(prop, fixed_params=fixed, assumptions=prop.assumptions + tuple(added))


def _whole_cycle_times(field: str, low: Fraction, high: Fraction, cycle_s: Fraction) -> tuple[Fraction, ...]:
    """The whole-cycle times the values of ``[low, high]`` round up to (T_traction to at least one cycle)."""
    first, last = math.ceil(low / cycle_s), math.ceil(high / cycle_s)
    if field == "t_traction_s":
        first, last = max(first, 1), max(last, 1)
    return tuple(n * cycle_s for n in range(first, last + 1))


def cell_families(
    config: Configuration, t: ConfiguredTrain, line: Line, cell: Cell
) -> tuple[tuple[Property, ...], tuple[tuple[Property, ...], ...]]:
    """The properties of train ``t`` on ``line`` for every value in ``cell``: the curve family (in the order of
    :func:`~atcs.properties.configured.curve_family`), and one closed-loop family per whole-cycle rounding of the
    cell's T_be and T_traction (each in the order of :func:`~atcs.properties.configured.loop_family`). Their names
    carry the cell's id, and the rounding's index."""
    train = t.train
    for field, value in cell.low().items():
        train = train_with(train, field, value)
    curves = tuple(_symbolic(p, cell, t, ()) for p in curve_family(config, t, line, train, f"_c{cell.id}"))
    enumerated = tuple(f for f, _, _ in cell.bounds if f in WHOLE_CYCLE_FIELDS)
    choices = [_whole_cycle_times(f, lo, hi, config.cycle_s) for f, lo, hi in cell.bounds if f in enumerated]
    loops = []
    for k, times in enumerate(itertools.product(*choices)):
        rounded = train
        for field, value in zip(enumerated, times, strict=True):
            rounded = dataclasses.replace(rounded, **{field: value})
        family = loop_family(config, t, line, rounded, f"_c{cell.id}_{k}")
        loops.append(tuple(_symbolic(p, cell, t, enumerated) for p in family))
    return curves, tuple(loops)
