"""Float backend: IEEE doubles, as scalars or numpy arrays (one element per train).

A step function called with numpy arrays steps a whole batch in one call; scalars
and arrays mix by broadcasting. Used by the simulator and the benchmarks.
"""

from __future__ import annotations

import bisect
import dataclasses
import math
import sys
from fractions import Fraction
from functools import reduce

from atcs.model.ops import (
    Constant,
    check_columns,
    check_table,
    pack_whole_numbers,
    to_fraction,
    unpack_whole_numbers,
    whole_index,
)

_SCALARS = frozenset({float, int, bool})
_CONSTANT_TYPES = frozenset({int, str, Fraction})


class _LoadedNumpy:
    """numpy, looked up when an array is at hand (so its caller has imported it)."""

    def __getattr__(self, name):
        return getattr(sys.modules["numpy"], name)


np = _LoadedNumpy()


def _is_array(value) -> bool:
    """A numpy array (numpy is not imported here: an array exists only once its caller imported it)."""
    if type(value) in _SCALARS:
        return False
    numpy = sys.modules.get("numpy")
    return numpy is not None and isinstance(value, numpy.ndarray)


def _any_array(*values) -> bool:
    for v in values:  # noqa: SIM110 - a loop is faster than any() over a generator, and this runs millions of times
        if type(v) not in _SCALARS and _is_array(v):  # a plain number checked inline: the common case
            return True
    return False


class FloatOps:
    name = "float"

    def __init__(self):
        self._constants: dict[Constant, float] = {}

    def const(self, value: Constant) -> float:
        if type(value) in _CONSTANT_TYPES:  # not a bool or a float, which equal (and hash as) ints and Fractions
            try:
                return self._constants[value]
            except KeyError:
                converted = self._constants[value] = float(to_fraction(value))
                return converted
        return float(to_fraction(value))  # which refuses it, or a subclass

    def const_bool(self, value: bool) -> bool:
        return bool(value)

    def ite(self, cond, then, else_):
        if type(cond) in _SCALARS and type(then) in _SCALARS and type(else_) in _SCALARS:
            return then if cond else else_
        if _any_array(cond, then, else_):
            return np.where(cond, then, else_)
        return then if cond else else_

    def min(self, first, *rest):
        if len(rest) == 1:
            other = rest[0]
            if type(first) is float and type(other) is float:  # the common case, as the builtin min does it
                return other if other < first else first
            if type(first) in _SCALARS and type(other) in _SCALARS:
                return min(first, other)
        if _any_array(first, *rest):
            return reduce(np.minimum, rest, np.asarray(first))
        return min(first, *rest) if rest else first

    def max(self, first, *rest):
        if len(rest) == 1:
            other = rest[0]
            if type(first) is float and type(other) is float:  # the common case, as the builtin max does it
                return other if other > first else first
            if type(first) in _SCALARS and type(other) in _SCALARS:
                return max(first, other)
        if _any_array(first, *rest):
            return reduce(np.maximum, rest, np.asarray(first))
        return max(first, *rest) if rest else first

    def and_(self, *args):
        if _any_array(*args):
            return reduce(np.logical_and, args, np.True_)
        return all(args)

    def or_(self, *args):
        if _any_array(*args):
            return reduce(np.logical_or, args, np.False_)
        return any(args)

    def not_(self, arg):
        if _is_array(arg):
            return np.logical_not(arg)
        return not arg

    def implies(self, antecedent, consequent):
        return self.or_(self.not_(antecedent), consequent)

    def eq(self, left, right):
        if _is_array(left) or _is_array(right):
            return np.equal(left, right)
        return bool(left == right)

    def select(self, values, index):
        if type(index) is float and index.is_integer() and 0 <= index < len(values):  # the common case, at once
            return values[int(index)]
        check_table("select", values)
        if not _is_array(index):  # one entry, whatever the others are (an array entry stays an array)
            j = whole_index(index, len(values))
            return values[-1 if j is None else j]
        *columns, index = np.broadcast_arrays(*values, np.asarray(index, dtype=float))
        whole = (index == np.floor(index)) & (index >= 0) & (index < len(values))
        j = np.where(whole, index, len(values) - 1).astype(int)
        return np.take_along_axis(np.stack(columns), j[None], axis=0)[0]

    def find(self, keys, key):
        check_table("find", keys)
        scalars = type(key) in _SCALARS and _SCALARS.issuperset(map(type, keys))
        if scalars and key == key:  # the search in C (a NaN key, which would match itself there, takes the loop)
            try:
                return True, float(tuple(keys).index(key))  # the first entry equal to the key
            except ValueError:
                return False, 0.0
        if not _any_array(key, *keys):
            for j, k in enumerate(keys):
                if k == key:
                    return True, float(j)
            return False, 0.0
        table = np.stack(np.broadcast_arrays(*keys, key))
        matches = table[:-1] == table[-1]
        return matches.any(axis=0), matches.argmax(axis=0).astype(float)

    def first_above(self, keys, key):
        if not keys:
            return np.zeros(np.shape(key)) if _is_array(key) else 0.0
        if not _is_array(key) and not _is_array(keys[0]) and not _is_array(keys[-1]):
            try:  # an array among the keys makes a comparison ambiguous, so it raises, never misleads
                return float(bisect.bisect_right(keys, key))
            except ValueError:
                pass
        table = np.stack(np.broadcast_arrays(*keys, key))  # a batch: bisect_right's steps for every train at once
        keys_, key = table[:-1], table[-1]
        low, high = np.zeros(key.shape, int), np.full(key.shape, len(keys))
        while (low < high).any():
            middle = (low + high) // 2
            searching = low < high
            below = key < np.take_along_axis(keys_, np.minimum(middle, len(keys) - 1)[None], axis=0)[0]
            high = np.where(searching & below, middle, high)
            low = np.where(searching & ~below, middle + 1, low)
        return low.astype(float)

    def floor(self, value):
        if _is_array(value):
            return np.floor(value)
        return float(math.floor(value))

    def sort_by_key(self, keys, *columns):
        check_columns(keys, columns)
        if not _any_array(*keys, *(v for column in columns for v in column)):
            order = sorted(range(len(keys)), key=keys.__getitem__)
            return tuple(tuple(seq[k] for k in order) for seq in (keys, *columns))
        # a batch: sort each train's keys (axis 0 runs over the keys, the rest over the batch)
        stacked = np.stack(np.broadcast_arrays(*keys)).astype(float)
        shape = np.broadcast_shapes(stacked.shape[1:], *(np.shape(v) for column in columns for v in column))
        stacked = np.broadcast_to(stacked, (len(keys), *shape))
        order = np.argsort(stacked, axis=0, kind="stable")
        result = [tuple(np.take_along_axis(stacked, order, axis=0))]
        for column in columns:
            values = np.stack([np.broadcast_to(v, shape) for v in column])
            result.append(tuple(np.take_along_axis(values, order, axis=0)))
        return tuple(result)

    def pack_bits(self, fields):
        values = [value for value, _ in fields]
        if not _any_array(*values):
            return pack_whole_numbers([(math.floor(value), width) for value, width in fields])
        # a batch: one bit string per train, as an array of them
        columns = np.broadcast_arrays(*values)
        packed = np.empty(columns[0].shape, dtype=object)
        for j in np.ndindex(packed.shape):
            packed[j] = pack_whole_numbers([(math.floor(c[j]), w) for c, (_, w) in zip(columns, fields, strict=True)])
        return packed

    def unpack_bits(self, bits, widths) -> tuple:
        if not _is_array(bits):
            return tuple(float(field) for field in unpack_whole_numbers(bits, widths))
        rows = [unpack_whole_numbers(bits[j], widths) for j in np.ndindex(bits.shape)]
        return tuple(np.array([float(row[k]) for row in rows]).reshape(bits.shape) for k in range(len(widths)))


FLOAT = FloatOps()


def floats(value):
    """An exact number (or a tuple of them, nested) as float(s), for the float backend; anything else as it is."""
    if isinstance(value, tuple):
        return tuple(floats(v) for v in value)
    return float(value) if isinstance(value, Fraction) else value


def float_record(record):
    """A frozen dataclass (train data, parameters) with its exact numbers as floats."""
    return dataclasses.replace(record, **{f.name: floats(getattr(record, f.name)) for f in dataclasses.fields(record)})
