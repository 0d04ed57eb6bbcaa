"""Symbolic backend: z3 real and boolean terms, wrapped so that they cannot be misused.

z3 raises when most symbolic booleans are truth-tested, but not for ``==``:
``bool(x == y)`` on two z3 terms is *structural* equality and silently takes a
branch. The wrappers here refuse ``bool()``, ``==`` and ``!=`` outright (as
Amaranth's values refuse ``bool()``), and refuse Python floats as constants, so a
step function that would behave differently under the proof than under the
simulator fails loudly instead.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from contextlib import contextmanager
from fractions import Fraction

import z3

from atcs.model.errors import AtcsError
from atcs.model.ops import Constant, check_columns, check_table, check_widths, to_fraction

_contexts: list[z3.Context | None] = [None]


def context() -> z3.Context | None:
    """The z3 context new terms are made in (None: z3's main context)."""
    return _contexts[-1]


@contextmanager
def fresh_context() -> Iterator[z3.Context]:
    """Within the block, every new term is made in a new z3 context of its own. z3's search follows term ids,
    so a query built in a fresh context is solved the same way whatever the process did before."""
    _contexts.append(z3.Context())
    try:
        yield _contexts[-1]
    finally:
        _contexts.pop()


class SymbolicValueError(AtcsError, TypeError):
    """A symbolic value was used where Python needs a concrete one (``if``, ``==``, ``and`` ...)."""


_BOOL_HINT = (
    "a symbolic value has no Python truth value: a step function must branch with "
    "o.ite(...) and combine conditions with o.and_/o.or_/o.not_, never with if/and/or/not"
)
_EQ_HINT = "symbolic values cannot be compared with == or !=: use o.eq(a, b) or o.not_(o.eq(a, b))"


def _term(value) -> z3.ArithRef:
    if isinstance(value, Real):
        return value.term
    if isinstance(value, bool) or not isinstance(value, (int, Fraction)):
        raise SymbolicValueError(
            f"cannot mix {type(value).__name__} {value!r} into a symbolic expression; "
            "use o.const(...) with an int, a Fraction or a decimal string"
        )
    value = Fraction(value)
    return z3.Q(value.numerator, value.denominator, context())


class _Symbolic:
    """A wrapped z3 term: no Python truth value, no ``==`` or ``!=``, not hashable."""

    __slots__ = ("term",)

    def __init__(self, term: z3.ExprRef):
        self.term = term

    def __eq__(self, other):
        raise SymbolicValueError(_EQ_HINT)

    def __ne__(self, other):
        raise SymbolicValueError(_EQ_HINT)

    __hash__ = None

    def __bool__(self):
        raise SymbolicValueError(_BOOL_HINT)

    def __repr__(self):
        return f"{type(self).__name__}({self.term})"


class Real(_Symbolic):
    """A z3 real term. Arithmetic and ordering comparisons build new terms."""

    __slots__ = ()

    def __add__(self, other):
        return Real(self.term + _term(other))

    def __radd__(self, other):
        return Real(_term(other) + self.term)

    def __sub__(self, other):
        return Real(self.term - _term(other))

    def __rsub__(self, other):
        return Real(_term(other) - self.term)

    def __mul__(self, other):
        return Real(self.term * _term(other))

    def __rmul__(self, other):
        return Real(_term(other) * self.term)

    def __truediv__(self, other):
        return Real(self.term / _term(other))

    def __rtruediv__(self, other):
        return Real(_term(other) / self.term)

    def __neg__(self):
        return Real(-self.term)

    def __lt__(self, other):
        return Bool(self.term < _term(other))

    def __le__(self, other):
        return Bool(self.term <= _term(other))

    def __gt__(self, other):
        return Bool(self.term > _term(other))

    def __ge__(self, other):
        return Bool(self.term >= _term(other))


class Bool(_Symbolic):
    """A z3 boolean term. Combine with ``o.and_``, ``o.or_``, ``o.not_``."""

    __slots__ = ()


def _bool_term(value) -> z3.BoolRef:
    if isinstance(value, Bool):
        return value.term
    if isinstance(value, bool):
        return z3.BoolVal(value, context())
    raise SymbolicValueError(f"expected a symbolic or Python bool, got {type(value).__name__} {value!r}")


def _any_term(value):
    if isinstance(value, (Bool, bool)):
        return _bool_term(value)
    return _term(value)


def wrap(term: z3.ExprRef) -> Real | Bool:
    """Wrap a raw z3 term of sort Real or Bool."""
    if z3.is_bool(term):
        return Bool(term)
    if z3.is_real(term):
        return Real(term)
    raise SymbolicValueError(f"unsupported z3 sort {term.sort()} of {term}")


def unwrap(value) -> z3.ExprRef:
    """The z3 term of a wrapped value (or of a Python bool, int or Fraction)."""
    return _any_term(value)


class SymbolicOps:
    name = "symbolic"

    def const(self, value: Constant) -> Real:
        return Real(_term(to_fraction(value)))

    def const_bool(self, value: bool) -> Bool:
        return Bool(z3.BoolVal(bool(value), context()))

    def ite(self, cond, then, else_):
        return wrap(z3.If(_bool_term(cond), _any_term(then), _any_term(else_)))

    def min(self, first, *rest):
        result = _term(first)
        for other in rest:
            o = _term(other)
            result = z3.If(o < result, o, result)
        return Real(result)

    def max(self, first, *rest):
        result = _term(first)
        for other in rest:
            o = _term(other)
            result = z3.If(o > result, o, result)
        return Real(result)

    def and_(self, *args) -> Bool:
        return Bool(z3.And(*[_bool_term(a) for a in args]) if args else z3.BoolVal(True, context()))

    def or_(self, *args) -> Bool:
        return Bool(z3.Or(*[_bool_term(a) for a in args]) if args else z3.BoolVal(False, context()))

    def not_(self, arg) -> Bool:
        return Bool(z3.Not(_bool_term(arg)))

    def implies(self, antecedent, consequent) -> Bool:
        return Bool(z3.Implies(_bool_term(antecedent), _bool_term(consequent)))

    def eq(self, left, right) -> Bool:
        return Bool(_any_term(left) == _any_term(right))

    def select(self, values, index):
        check_table("select", values)
        j = _term(index)
        result = _any_term(values[-1])
        for k in range(len(values) - 2, -1, -1):
            result = z3.If(j == k, _any_term(values[k]), result)
        return wrap(result)

    def find(self, keys, key):
        check_table("find", keys)
        k = _term(key)
        found, index = z3.BoolVal(False, context()), z3.RealVal(0, context())
        for j in range(len(keys) - 1, -1, -1):
            match = _term(keys[j]) == k
            found, index = z3.Or(match, found), z3.If(match, z3.RealVal(j, context()), index)
        return Bool(found), Real(index)

    def first_above(self, keys, key):
        k, terms = _term(key), [_term(v) for v in keys]

        def search(low: int, high: int):  # bisect_right's comparisons, every path: a tree of len(keys) nodes
            if low >= high:
                return z3.RealVal(low, context())
            middle = (low + high) // 2
            return z3.If(k < terms[middle], search(low, middle), search(middle + 1, high))

        return Real(search(0, len(keys)))

    def floor(self, value) -> Real:
        return Real(z3.ToReal(z3.ToInt(_term(value))))

    def sort_by_key(self, keys, *columns):
        check_columns(keys, columns)
        wires = [[_term(k) for k in keys], *([_any_term(v) for v in column] for column in columns)]
        n = len(keys)
        for round_ in range(n):  # odd-even transposition: n rounds sort any input; swaps only on > (stable)
            for j in range(round_ % 2, n - 1, 2):
                swap = wires[0][j] > wires[0][j + 1]
                for wire in wires:
                    wire[j], wire[j + 1] = z3.If(swap, wire[j + 1], wire[j]), z3.If(swap, wire[j], wire[j + 1])
        return tuple(tuple(wrap(term) for term in wire) for wire in wires)

    def pack_bits(self, fields) -> Bits:
        check_widths([width for _, width in fields])
        return Bits(tuple((_whole_mod(_term(value), 1 << width), width) for value, width in fields))

    def unpack_bits(self, bits: Bits, widths) -> tuple[Real, ...]:
        if not isinstance(bits, Bits):
            raise SymbolicValueError(f"unpack_bits needs a bit string from pack_bits, got {type(bits).__name__}")
        check_widths(widths, bits.width)
        read, start = [], 0
        for width in widths:
            end, parts = start + width, []
            for number, (first, last) in zip(bits.numbers, bits.spans, strict=True):
                low, high = max(start, first), min(end, last)  # the bits of this read in this packed field
                if low < high:
                    if (low, high) != (first, last):
                        number = (number / (1 << (last - high))) % (1 << (high - low))
                    parts.append(number * (1 << (end - high)) if end > high else number)
            read.append(Real(_as_real(parts[0] if len(parts) == 1 else z3.Sum(parts))))
            start = end
        return tuple(read)


def _whole_mod(term: z3.ArithRef, modulus: int) -> z3.ArithRef:
    """``floor(term) mod modulus`` as an integer, taken into each branch of an ``ite`` (a field written only in some
    cases): the same value, in the form z3 decides at once."""
    if z3.is_app_of(term, z3.Z3_OP_ITE):
        cond, then, else_ = term.children()
        return z3.If(cond, _whole_mod(then, modulus), _whole_mod(else_, modulus))
    if z3.is_rational_value(term):
        return z3.IntVal(math.floor(Fraction(term.as_fraction())) % modulus, term.ctx)
    return z3.ToInt(term) % modulus


def _as_real(term: z3.ArithRef) -> z3.ArithRef:
    """An integer ``term`` as a real, taken into each branch of an ``ite``."""
    if z3.is_app_of(term, z3.Z3_OP_ITE):
        cond, then, else_ = term.children()
        return z3.If(cond, _as_real(then), _as_real(else_))
    return z3.ToReal(term)


class Bits:
    """A symbolic bit string (:meth:`SymbolicOps.pack_bits`): its fields as whole numbers, each ``floor(value) mod
    2^width``; only :meth:`SymbolicOps.unpack_bits` reads it, each field it reads the sum of the packed fields' bits
    it covers (integer division and remainder by powers of two). The same function as a bit-vector's concatenation
    and extraction, stated in integer arithmetic: z3 decides a codec's round trips at once this way, where its
    bit-vector conversions (``int2bv``, ``bv2int``) grow exponentially with the fields."""

    __slots__ = ("numbers", "spans", "width")

    def __init__(self, fields: tuple[tuple[z3.ArithRef, int], ...]):
        self.numbers = tuple(number for number, _ in fields)
        spans, start = [], 0
        for _, width in fields:
            spans.append((start, start + width))
            start += width
        self.spans, self.width = tuple(spans), start

    def __bool__(self):
        raise SymbolicValueError(_BOOL_HINT)

    def __eq__(self, other):
        raise SymbolicValueError(_EQ_HINT)

    __ne__ = __eq__
    __hash__ = None  # type: ignore[assignment]

    def __repr__(self):
        return f"Bits({self.width} bits)"


SYMBOLIC = SymbolicOps()
