"""The three interpretations of a step function (docs/design.md, "The step-function pattern").

Every step function in :mod:`atcs.model` takes an ``Ops`` as its first argument and
uses it for constants, branching and extrema; arithmetic and ordering comparisons
use plain operators. Running the same function with a different ``Ops`` gives the
simulator (float), the bit-exact replay (exact) or the proof obligation (symbolic).

``N`` and ``B`` are the type variables for the number and boolean types of a
backend. State, input, output and parameter dataclasses annotate their fields with
them; the proof engine reads the annotations to create z3 variables of the right
sort.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Protocol, TypeVar

N = TypeVar("N")
B = TypeVar("B")

Constant = int | Fraction | str
"""What ``Ops.const`` accepts: an int, a Fraction, or a decimal string such as ``"0.1"``.

Python floats are refused: ``0.1`` is not one tenth, and a proof about a model
with binary-rounded constants would be about a different model."""


@dataclass(frozen=True)
class BitString:
    """A concrete backend's bit string (:meth:`Ops.pack_bits`): ``value``'s ``width`` bits, most significant
    first."""

    value: int
    width: int

    def __post_init__(self):
        if not 0 <= self.value < 1 << self.width:
            raise ValueError(f"bit string: {self.value} does not fit {self.width} bits")


class Ops(Protocol[N, B]):
    """The operations a step function may use besides ``+ - * /`` and ``< <= > >=``."""

    name: str

    def const(self, value: Constant) -> N:
        """A numeric constant."""

    def const_bool(self, value: bool) -> B:
        """A boolean constant."""

    def ite(self, cond: B, then: N | B, else_: N | B) -> N | B:
        """``then`` where ``cond`` holds, else ``else_`` (both are evaluated)."""

    def min(self, first: N, *rest: N) -> N:
        """The smallest argument."""

    def max(self, first: N, *rest: N) -> N:
        """The largest argument."""

    def and_(self, *args: B) -> B:
        """Conjunction (true for no arguments)."""

    def or_(self, *args: B) -> B:
        """Disjunction (false for no arguments)."""

    def not_(self, arg: B) -> B:
        """Negation."""

    def implies(self, antecedent: B, consequent: B) -> B:
        """``not antecedent or consequent``."""

    def eq(self, left: N | B, right: N | B) -> B:
        """Equality; the only way to compare for equality in a step function."""

    def select(self, values: Sequence[N | B], index: N) -> N | B:
        """``values[index]`` for a whole ``index`` in ``0 .. len(values) - 1``; the last value for any other
        ``index`` (the same total function in every backend; the symbolic one is a chain of ``ite``)."""

    def find(self, keys: Sequence[N], key: N) -> tuple[B, N]:
        """``(found, index)``: whether ``key`` is among ``keys``, and the first index where it is (0 if it is
        not). A table lookup such as a tag id to its entry."""

    def first_above(self, keys: Sequence[N], key: N) -> N:
        """Python's ``bisect.bisect_right(keys, key)``: for ascending ``keys``, the index of the first one above
        ``key`` (``len(keys)`` if none). The lookup of a preprocessed table: ``log2(len(keys))`` comparisons in the
        concrete backends; the symbolic one is the tree of ``ite`` over every path of the search (as many nodes
        as keys), so all three answer alike for any keys, ascending or not."""

    def floor(self, value: N) -> N:
        """The largest whole number at or below ``value`` (a quantity rounded down to its unit for a message:
        ``o.floor(x * 100) / 100`` in cm). The symbolic one is z3's ``to_int``, so a proof reasons about it
        exactly."""

    def pack_bits(self, fields: Sequence[tuple[N, int]]) -> Any:
        """The ``(value, width)`` fields as one bit string, most significant first, as an ETCS packet or a T2T
        report carries them (Subset-026-7 §7.3): each field is ``floor(value) mod 2^width`` in ``width`` bits (the
        same total function in every backend; a codec keeps its values within their fields). Concrete backends give
        a :class:`BitString`; the symbolic one the fields as whole numbers, each field read the sum of the packed bits
        it covers (integer division and remainder by powers of two), so a proof reasons about the fields exactly."""

    def unpack_bits(self, bits: Any, widths: Sequence[int]) -> tuple[N, ...]:
        """The unsigned fields of ``bits`` (from :meth:`pack_bits`), most significant first; ``widths`` sum to its
        width."""

    def sort_by_key(self, keys: Sequence[N], *columns: Sequence[N | B]) -> tuple[tuple, ...]:
        """``keys`` in ascending order, stable, and each column permuted alike: ``(keys, *columns)``.

        The one data-dependent reordering a step function may use (merging
        profiles' breakpoints). Concrete backends sort; the symbolic backend
        builds an odd-even transposition network (``n (n - 1) / 2`` compare-swaps,
        meant for the small capacities of proofs).
        """


def check_columns(keys: Sequence, columns: Sequence[Sequence]) -> None:
    """``Ops.sort_by_key``'s argument check, shared by the backends."""
    for index, column in enumerate(columns):
        if len(column) != len(keys):
            raise ValueError(f"sort_by_key: columns[{index}] has {len(column)} entries, keys has {len(keys)}")


def check_widths(widths: Sequence[int], total: int | None = None) -> None:
    """``Ops.pack_bits`` and ``Ops.unpack_bits``'s argument check, shared by the backends: whole positive widths,
    summing to the bit string's ``total`` when one is given."""
    for width in widths:
        if isinstance(width, bool) or not isinstance(width, int) or width < 1:
            raise ValueError(f"bit field width must be a whole number >= 1, got {width!r}")
    if total is not None and sum(widths) != total:
        raise ValueError(f"bit field widths sum to {sum(widths)}, the bit string has {total} bits")


def pack_whole_numbers(numbers: Sequence[tuple[int, int]]) -> BitString:
    """The concrete backends' :meth:`Ops.pack_bits`, on ``(floor(value), width)``."""
    check_widths([width for _, width in numbers])
    value = 0
    for number, width in numbers:
        value = (value << width) | (number % (1 << width))
    return BitString(value, sum(width for _, width in numbers))


def unpack_whole_numbers(bits: BitString, widths: Sequence[int]) -> list[int]:
    """The concrete backends' :meth:`Ops.unpack_bits`, as ints."""
    check_widths(widths, bits.width)
    fields, shift = [], bits.width
    for width in widths:
        shift -= width
        fields.append((bits.value >> shift) & ((1 << width) - 1))
    return fields


def check_table(what: str, values: Sequence) -> None:
    """``Ops.select`` and ``Ops.find``'s argument check, shared by the backends."""
    if len(values) == 0:
        raise ValueError(f"{what}: the table is empty")


def whole_index(index, size: int) -> int | None:
    """A concrete ``index`` as an int if it is a whole number in ``0 .. size - 1``, else None."""
    if isinstance(index, bool):
        return None
    try:
        j = int(index)
    except (TypeError, ValueError, OverflowError):
        return None
    return j if j == index and 0 <= j < size else None


def to_fraction(value: Constant, *, what: str = "constant") -> Fraction:
    """Convert an ``Ops.const`` argument to a Fraction, refusing floats and bools."""
    if isinstance(value, bool) or not isinstance(value, (int, Fraction, str)):
        raise TypeError(
            f"{what} must be an int, a Fraction or a decimal string, "
            f"not {type(value).__name__} {value!r}; write o.const(Fraction('0.1')) or o.const('0.1')"
        )
    try:
        return Fraction(value)
    except (ValueError, ZeroDivisionError) as exc:
        raise ValueError(f"{what} {value!r} is not a number: {exc}") from None


def backends() -> dict[str, Ops]:
    """The registered backends by name: ``float``, ``exact`` and ``symbolic``."""
    from atcs.model.ops.exact import EXACT
    from atcs.model.ops.floating import FLOAT
    from atcs.model.ops.symbolic import SYMBOLIC

    return {ops.name: ops for ops in (FLOAT, EXACT, SYMBOLIC)}


__all__ = [
    "B",
    "BitString",
    "Constant",
    "N",
    "Ops",
    "backends",
    "check_columns",
    "check_table",
    "check_widths",
    "pack_whole_numbers",
    "to_fraction",
    "unpack_whole_numbers",
    "whole_index",
]
