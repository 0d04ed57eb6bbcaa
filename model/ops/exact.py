"""Exact backend: numbers are ``fractions.Fraction``, booleans are ``bool``.

Used to replay counterexamples and to compute test-vector outputs bit-exactly.
"""

from __future__ import annotations

import bisect
import math
from fractions import Fraction

from atcs.model.ops import (
    BitString,
    Constant,
    check_columns,
    check_table,
    pack_whole_numbers,
    to_fraction,
    unpack_whole_numbers,
    whole_index,
)


class ExactOps:
    name = "exact"

    def const(self, value: Constant) -> Fraction:
        return to_fraction(value)

    def const_bool(self, value: bool) -> bool:
        return bool(value)

    def ite(self, cond, then, else_):
        return then if _truth(cond) else else_

    def min(self, first, *rest):
        return min(first, *rest) if rest else first

    def max(self, first, *rest):
        return max(first, *rest) if rest else first

    def and_(self, *args) -> bool:
        return all(_truths(args))

    def or_(self, *args) -> bool:
        return any(_truths(args))

    def not_(self, arg) -> bool:
        return not _truth(arg)

    def implies(self, antecedent, consequent) -> bool:
        return (not _truth(antecedent)) or _truth(consequent)

    def eq(self, left, right) -> bool:
        return left == right

    def select(self, values, index):
        check_table("select", values)
        j = whole_index(index, len(values))
        return values[-1 if j is None else j]

    def find(self, keys, key):
        check_table("find", keys)
        for j, k in enumerate(keys):
            if k == key:
                return True, Fraction(j)
        return False, Fraction(0)

    def first_above(self, keys, key):
        return Fraction(bisect.bisect_right(keys, key))

    def floor(self, value) -> Fraction:
        return Fraction(math.floor(value))

    def sort_by_key(self, keys, *columns):
        check_columns(keys, columns)
        order = sorted(range(len(keys)), key=keys.__getitem__)
        return tuple(tuple(seq[k] for k in order) for seq in (keys, *columns))

    def pack_bits(self, fields) -> BitString:
        return pack_whole_numbers([(math.floor(value), width) for value, width in fields])

    def unpack_bits(self, bits: BitString, widths) -> tuple[Fraction, ...]:
        return tuple(Fraction(field) for field in unpack_whole_numbers(bits, widths))


_BOOL = frozenset({bool})


def _truths(values: tuple) -> tuple:
    """``values``, every one checked a bool (in C; the loop only to name the first that is not)."""
    if not _BOOL.issuperset(map(type, values)):
        for value in values:
            _truth(value)
    return values


def _truth(value) -> bool:
    if not isinstance(value, bool):
        raise TypeError(f"exact backend expected a bool, got {type(value).__name__} {value!r}")
    return value


EXACT = ExactOps()
