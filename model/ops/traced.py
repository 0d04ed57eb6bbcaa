"""Straight-line programs traced from a step function or a predicate, for a concrete backend.

A function written against :class:`~atcs.model.ops.Ops` is run once on :class:`Term` placeholders for its
arguments' numbers and booleans; every operation it performs is recorded as one assignment, and the record is
compiled into a Python function that performs the same operations, in the same order, with the concrete
backend's own operations for ``const``, ``min``, ``max``, ``select``, ``find``, ``first_above``, ``floor`` and
``sort_by_key``, and Python's operators for the rest (what :class:`~atcs.model.ops.exact.ExactOps` and
:class:`~atcs.model.ops.floating.FloatOps` do on scalars; comparisons of two Fractions as Fraction's own
cross-multiplication, without its dispatch). On a batch (an argument holds numpy arrays) every Ops operation is the
backend's own call. What it saves is the dispatch and the function calls, not arithmetic: the program computes what
the function computes, to the bit.

A trace holds for the shape it was made on: the lengths of the tuples and the types of the leaves of every
argument (:func:`shape`; an array's type, dtype and dimensions, not its length). A function that branches in Python
on a traced value (``if``, ``and``, ``==``, an index) cannot be traced, as it cannot be proved: :class:`Term`
refuses ``bool()``, ``==`` and ``__index__``, and :func:`trace` raises :class:`Untraceable`. A check that looks at
an argument's type (the concrete-only validation of, e.g., ``ato_target_speed``) sees a placeholder as it sees a z3
term, and is not in the program: validate data before tracing a function of it.
"""

from __future__ import annotations

import dataclasses
import itertools
import sys
from collections.abc import Callable
from fractions import Fraction
from math import gcd
from typing import Any

from atcs.model.errors import AtcsError

LEAVES = (Fraction, float, int, bool)
"""The types traced as values, besides numpy arrays; any other leaf (None, a string) makes an argument
untraceable."""


class Untraceable(AtcsError, TypeError):
    """The function or an argument cannot be traced (see the module docstring)."""


class Term:
    """A value in a trace: the name of the variable that holds it in the program."""

    __slots__ = ("_program", "kind", "name")

    def __init__(self, program: _Program, name: str, kind: type | None = None):
        self._program, self.name, self.kind = program, name, kind
        """``kind``: the type of the value where the trace knows it (an argument's leaf, arithmetic on Fractions)."""

    def bind(self) -> str:
        """The name the program reads this value by."""
        return self.name

    def __bool__(self):
        raise Untraceable("a traced value has no Python truth value (the function branches on it)")

    def __eq__(self, other):
        raise Untraceable("a traced value cannot be compared with == (the function should use o.eq)")

    __ne__ = __eq__
    __hash__ = None  # type: ignore[assignment]

    def __index__(self):
        raise Untraceable("a traced value cannot be an index (the function should use o.select)")

    def _binary(self, symbol: str, other, reflected: bool = False) -> Term:
        left, right = (other, self) if reflected else (self, other)
        program = self._program
        kinds = {_kind(left), _kind(right)}
        if symbol in _ORDER:
            if kinds == {Fraction}:  # Fraction's own comparison, without its dispatch (denominators are positive)
                a, b = program.ref(left), program.ref(right)
                return program.assign(f"{a}._numerator * {b}._denominator {symbol} {b}._numerator * {a}._denominator")
            return program.assign(f"{program.ref(left)} {symbol} {program.ref(right)}", bool)
        if kinds == {Fraction}:  # Fraction's own arithmetic, without its dispatch
            arithmetic = _FRACTION_ARITHMETIC[symbol]
            return program.assign(f"{arithmetic}({program.ref(left)}, {program.ref(right)})", Fraction)
        kind = Fraction if kinds <= {Fraction, int} and Fraction in kinds else None
        return program.assign(f"{program.ref(left)} {symbol} {program.ref(right)}", kind)

    def __add__(self, other):
        return self._binary("+", other)

    def __radd__(self, other):
        return self._binary("+", other, reflected=True)

    def __sub__(self, other):
        return self._binary("-", other)

    def __rsub__(self, other):
        return self._binary("-", other, reflected=True)

    def __mul__(self, other):
        return self._binary("*", other)

    def __rmul__(self, other):
        return self._binary("*", other, reflected=True)

    def __truediv__(self, other):
        return self._binary("/", other)

    def __rtruediv__(self, other):
        return self._binary("/", other, reflected=True)

    def __neg__(self):
        if self.kind is Fraction:
            return self._program.assign(f"_fraction_neg({self._program.ref(self)})", Fraction)
        return self._program.assign(f"-{self._program.ref(self)}", self.kind)

    def __lt__(self, other):
        return self._binary("<", other)

    def __le__(self, other):
        return self._binary("<=", other)

    def __gt__(self, other):
        return self._binary(">", other)

    def __ge__(self, other):
        return self._binary(">=", other)

    def __repr__(self):
        return f"Term({self.name})"


_ORDER = frozenset({"<", "<=", ">", ">="})
_NUMBERS = frozenset({Fraction, float, int})


# --- Fraction arithmetic without Fraction's dispatch ----------------------------------------------------------------
# Python's own algorithms (``fractions.Fraction._add`` and the others), on two Fractions in lowest terms, with the
# result made directly in lowest terms: the same value, numerator and denominator as ``a + b`` and the others.

_new_object = object.__new__


def _fraction(numerator: int, denominator: int) -> Fraction:
    made = _new_object(Fraction)
    made._numerator, made._denominator = numerator, denominator
    return made


def _fraction_sum(na: int, da: int, nb: int, db: int) -> Fraction:
    """``na/da + nb/db``, both in lowest terms."""
    g = gcd(da, db)
    if g == 1:
        return _fraction(na * db + da * nb, da * db)
    s = da // g
    t = na * (db // g) + nb * s
    g2 = gcd(t, g)
    if g2 == 1:
        return _fraction(t, s * db)
    return _fraction(t // g2, s * (db // g2))


def _fraction_add(a: Fraction, b: Fraction) -> Fraction:
    return _fraction_sum(a._numerator, a._denominator, b._numerator, b._denominator)


def _fraction_sub(a: Fraction, b: Fraction) -> Fraction:
    return _fraction_sum(a._numerator, a._denominator, -b._numerator, b._denominator)


def _fraction_mul(a: Fraction, b: Fraction) -> Fraction:
    na, da, nb, db = a._numerator, a._denominator, b._numerator, b._denominator
    g1 = gcd(na, db)
    if g1 > 1:
        na //= g1
        db //= g1
    g2 = gcd(nb, da)
    if g2 > 1:
        nb //= g2
        da //= g2
    return _fraction(na * nb, db * da)


def _fraction_div(a: Fraction, b: Fraction) -> Fraction:
    na, da, nb, db = a._numerator, a._denominator, b._numerator, b._denominator
    if nb == 0:
        raise ZeroDivisionError(f"Fraction({na * db}, 0)")
    g1 = gcd(na, nb)
    if g1 > 1:
        na //= g1
        nb //= g1
    g2 = gcd(db, da)
    if g2 > 1:
        da //= g2
        db //= g2
    n, d = na * db, nb * da
    if d < 0:
        n, d = -n, -d
    return _fraction(n, d)


def _fraction_neg(a: Fraction) -> Fraction:
    return _fraction(-a._numerator, a._denominator)


_FRACTION_ARITHMETIC = {"+": "_fraction_add", "-": "_fraction_sub", "*": "_fraction_mul", "/": "_fraction_div"}
_FRACTION_FUNCTIONS = {
    f.__name__: f for f in (_fraction_add, _fraction_sub, _fraction_mul, _fraction_div, _fraction_neg)
}


def _kind(value) -> type | None:
    return value.kind if isinstance(value, Term) else type(value)


def _truth(value):
    """``value`` where a boolean is due: refused if the trace knows it is not one (the function as it is then
    runs, and its backend names the error)."""
    kind = _kind(value)
    if kind not in (bool, None):
        raise Untraceable(f"a {kind.__name__} where a boolean is due")
    return value


def _common_kind(values) -> type | None:
    kinds = {_kind(v) for v in values}
    return kinds.pop() if len(kinds) == 1 else None


class _Leaf(Term):
    """An argument's number or boolean: read into a variable where the function first uses it (so the program
    reads only what the function does)."""

    __slots__ = ("_source",)

    def __init__(self, program: _Program, source: str, kind: type):
        super().__init__(program, "", kind)
        self._source = source

    def bind(self) -> str:
        if not self.name:
            self.name = self._program.assign(self._source).name
        return self.name


class _Program:
    """The assignments recorded so far and the names they refer to.

    Every operation a program performs is pure and every name is assigned once, so an expression already assigned
    is not computed again: its name is used (common subexpressions computed once, as where a property's predicate
    recomputes what the step computed)."""

    def __init__(self, ops):
        self.ops = ops
        self.lines: list[str] = []
        self.namespace: dict[str, Any] = {"_ops": ops, **_FRACTION_FUNCTIONS}
        self._counter = itertools.count()
        self._assigned: dict[str, Term] = {}
        self._constants: dict[tuple[type, str], str] = {}
        self.arrays = False
        """An argument has numpy arrays (a batch): every Ops operation is then the backend's own call."""

    def fresh(self, prefix: str = "t") -> str:
        return f"{prefix}{next(self._counter)}"

    def assign(self, expression: str, kind: type | None = None) -> Term:
        known = self._assigned.get(expression)
        if known is not None:
            return known if kind is None or kind is known.kind else Term(self, known.name, kind)
        name = self.fresh()
        self.lines.append(f"{name} = {expression}")
        term = self._assigned[expression] = Term(self, name, kind)
        return term

    def ref(self, value) -> str:
        """``value`` in the program's source: a term's name, a tuple's entries, a constant bound to a name."""
        if isinstance(value, Term):
            if value._program is not self:
                raise Untraceable("a term of another trace")
            return value.bind()
        if type(value) is _ArgumentTuple and value._program is self:
            return value.bind()
        if isinstance(value, tuple):
            return "(" + "".join(f"{self.ref(v)}, " for v in value) + ")"
        if type(value) in (bool, type(None)):
            return repr(value)
        key = (type(value), repr(value)) if type(value) in _NUMBERS else None  # repr: -0.0 is not 0.0
        if key in self._constants:
            return self._constants[key]
        name = self.fresh("c")
        self.namespace[name] = value
        if key is not None:
            self._constants[key] = name
        return name


class TraceOps:
    """The Ops that records (see the module docstring); one per trace."""

    def __init__(self, program: _Program):
        self._p = program
        self.name = program.ops.name  # a function that asks which backend it runs on is traced for that backend

    def _call(self, method: str, *args, kind: type | None = None) -> Term:
        return self._p.assign(f"_ops.{method}({', '.join(self._p.ref(a) for a in args)})", kind)

    def const(self, value):
        number = self._p.ops.const(value)
        return Term(self._p, self._p.ref(number), type(number))

    def const_bool(self, value):
        return Term(self._p, repr(bool(value)), bool)

    def ite(self, cond, then, else_):
        if self._p.arrays:
            return self._call("ite", cond, then, else_)
        r = self._p.ref
        return self._p.assign(f"{r(then)} if {r(_truth(cond))} else {r(else_)}", _common_kind((then, else_)))

    def min(self, first, *rest):
        return self._call("min", first, *rest, kind=_common_kind((first, *rest)))

    def max(self, first, *rest):
        return self._call("max", first, *rest, kind=_common_kind((first, *rest)))

    def and_(self, *args):
        if self._p.arrays:
            return self._call("and_", *args)
        return self._p.assign(" and ".join(self._p.ref(_truth(a)) for a in args) if args else "True", bool)

    def or_(self, *args):
        if self._p.arrays:
            return self._call("or_", *args)
        return self._p.assign(" or ".join(self._p.ref(_truth(a)) for a in args) if args else "False", bool)

    def not_(self, arg):
        if self._p.arrays:
            return self._call("not_", arg)
        return self._p.assign(f"not {self._p.ref(_truth(arg))}", bool)

    def implies(self, antecedent, consequent):
        if self._p.arrays:
            return self._call("implies", antecedent, consequent)
        r = self._p.ref
        return self._p.assign(f"not {r(_truth(antecedent))} or {r(_truth(consequent))}", bool)

    def eq(self, left, right):
        if self._p.arrays:
            return self._call("eq", left, right)
        a, b = self._p.ref(left), self._p.ref(right)
        if _kind(left) is Fraction and _kind(right) is Fraction:  # Fractions are kept in lowest terms
            return self._p.assign(f"{a}._numerator == {b}._numerator and {a}._denominator == {b}._denominator", bool)
        return self._p.assign(f"{a} == {b}", bool)

    def select(self, values, index):
        return self._call("select", _as_tuple(values), index, kind=_common_kind(values))

    def find(self, keys, key):
        pair = self._call("find", _as_tuple(keys), key)
        return self._p.assign(f"{pair.name}[0]"), self._p.assign(f"{pair.name}[1]")

    def first_above(self, keys, key):
        return self._call("first_above", _as_tuple(keys), key)

    def floor(self, value):
        return self._call("floor", value)

    def pack_bits(self, fields):
        return self._call("pack_bits", tuple((value, width) for value, width in fields))

    def unpack_bits(self, bits, widths):
        fields = self._call("unpack_bits", bits, tuple(widths))
        return tuple(self._p.assign(f"{fields.name}[{k}]") for k in range(len(widths)))

    def sort_by_key(self, keys, *columns):
        result = self._call("sort_by_key", _as_tuple(keys), *(_as_tuple(c) for c in columns))
        return tuple(
            tuple(self._p.assign(f"{result.name}[{c}][{k}]") for k in range(len(keys))) for c in range(len(columns) + 1)
        )


_LEAF_TYPES = frozenset(LEAVES)


def _is_array(value) -> bool:
    """A numpy array: a batch, one element per train (numpy is not imported here: see the float backend)."""
    numpy = sys.modules.get("numpy")
    return numpy is not None and type(value) is numpy.ndarray


_FIELD_NAMES: dict[type, tuple[str, ...]] = {}


def shape(value) -> Any:
    """What a trace of a function of ``value`` depends on: its dataclass and tuple structure and its leaves' types
    (raises :class:`Untraceable` on any other leaf)."""
    kind = type(value)
    if kind in _LEAF_TYPES:
        return kind
    if kind is tuple:
        return _tuple_shape(value)
    if _is_array(value):
        return (kind, value.dtype.str, value.ndim)
    names = _FIELD_NAMES.get(kind)
    if names is None:
        if not dataclasses.is_dataclass(value):
            raise Untraceable(f"a {kind.__name__} leaf cannot be traced")
        names = _FIELD_NAMES[kind] = tuple(f.name for f in dataclasses.fields(value))
    shapes: list[Any] = [kind]
    for name in names:  # the leaves and tuples of a record inline: this runs for every checked step
        field = getattr(value, name)
        field_kind = type(field)
        if field_kind in _LEAF_TYPES:
            shapes.append(field_kind)
        elif field_kind is tuple:
            shapes.append(_tuple_shape(field))
        else:
            shapes.append(shape(field))
    return tuple(shapes)


def _tuple_shape(value: tuple) -> Any:
    kinds = set(map(type, value))
    if len(kinds) == 1 and kinds <= _LEAF_TYPES:  # the common case, kept short: a table of numbers
        return (len(value), *kinds)
    return tuple(map(type, value)) if kinds <= _LEAF_TYPES else tuple(map(shape, value))


class _ArgumentTuple(tuple):
    """An argument's tuple of numbers or booleans, as the function received it: passed whole to an Ops operation
    (a table lookup), the program passes the argument itself rather than a tuple rebuilt from its entries."""

    def __new__(cls, entries, program: _Program, source: str):
        made = super().__new__(cls, entries)
        made._program, made._source, made._name = program, source, ""
        return made

    def bind(self) -> str:
        if not self._name:
            self._name = self._program.assign(self._source).name
        return self._name


def _as_tuple(values) -> tuple:
    return values if isinstance(values, tuple) else tuple(values)


def _placeholder(program: _Program, value, source: str):
    """``value`` with every leaf replaced by a term read from ``source``."""
    kind = type(value)
    if kind in LEAVES:
        return _Leaf(program, source, kind)
    if _is_array(value):
        program.arrays = True
        return _Leaf(program, source, None)
    if kind is tuple:
        entries = [_placeholder(program, v, f"{source}[{j}]") for j, v in enumerate(value)]
        return _ArgumentTuple(entries, program, source) if all(type(v) in LEAVES for v in value) else tuple(entries)
    fields = {
        f.name: _placeholder(program, getattr(value, f.name), f"{source}.{f.name}") for f in dataclasses.fields(value)
    }
    try:
        return dataclasses.replace(value, **fields)
    except (TypeError, ValueError) as exc:  # a field the constructor does not take, a check of the values
        raise Untraceable(f"{kind.__name__} cannot hold traced values: {exc}") from None


def _rebuild(program: _Program, value) -> str:
    """Source that builds ``value`` (terms, tuples, dataclasses, constants) from the program's variables."""
    if type(value) is tuple:
        return "(" + "".join(f"{_rebuild(program, v)}, " for v in value) + ")"
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        if not all(f.init for f in dataclasses.fields(value)):
            raise Untraceable(f"{type(value).__name__} has a field its constructor does not take")
        kind = program.fresh("k")
        program.namespace[kind] = type(value)
        fields = ", ".join(f"{f.name}={_rebuild(program, getattr(value, f.name))}" for f in dataclasses.fields(value))
        return f"{kind}({fields})"
    return program.ref(value)


def _compile(program: _Program, arguments: list[str], lines: list[str], what: str) -> Callable[..., Any]:
    source = f"def program({', '.join(arguments)}):\n" + "".join(f"    {line}\n" for line in lines)
    exec(compile(source, f"<trace of {what}>", "exec"), program.namespace)
    compiled = program.namespace["program"]
    compiled.source = source
    return compiled


def _name(function) -> str:
    return getattr(function, "__qualname__", repr(function))


def _traced(program: _Program, function, placeholders):
    try:
        return function(TraceOps(program), *placeholders)
    except Untraceable:
        raise
    except TypeError as exc:  # e.g. range() of a traced number: a Python-level use of a value
        raise Untraceable(f"{_name(function)}: {exc}") from None


def trace(function: Callable[..., Any], ops, *examples) -> Callable[..., Any]:
    """``function(ops, *args)`` as a compiled program for arguments of the shape of ``examples`` (which are only
    read for their shape): returns ``program(*args)``, which computes what ``function(ops, *args)`` does.

    The result may be numbers, booleans, tuples and dataclasses of them. Raises :class:`Untraceable` if the
    function branches on a traced value or an example has a leaf that is not a number or a boolean."""
    for example in examples:
        shape(example)
    program = _Program(ops)
    arguments = [f"a{j}" for j in range(len(examples))]
    placeholders = [_placeholder(program, example, name) for example, name in zip(examples, arguments, strict=True)]
    result = _rebuild(program, _traced(program, function, placeholders))  # may read arguments: before the lines
    return _compile(program, arguments, [*program.lines, f"return {result}"], _name(function))


def _all(value) -> bool:
    """A predicate's value on a batch holds: it holds for every train."""
    return value if type(value) is bool else bool(sys.modules["numpy"].all(value))


def _append_checks(program: _Program, predicates, placeholders, trial, arguments: list[str], returned) -> None:
    """Append to ``program`` each predicate's check in turn, on ``placeholders`` (read from the sources
    ``arguments``): ``return returned(index)`` where it is false. Each is traced first on ``trial`` (a program
    thrown away, with placeholders of the same shapes), so that one that cannot be traced leaves nothing behind
    here: it is called as it is."""
    trial_program, trial_placeholders = trial
    for index, predicate in enumerate(predicates):
        try:
            _traced(trial_program, predicate, trial_placeholders)
        except Untraceable:
            called = program.fresh("f")
            program.namespace[called] = predicate
            program.lines.append(f"if not {called}(_ops, {', '.join(arguments)}): return {returned(index)}")
            continue
        held = program.ref(_traced(program, predicate, placeholders))
        program.lines.append(f"if not {f'_all({held})' if program.arrays else held}: return {returned(index)}")


def _programs(ops, examples) -> tuple[_Program, list, _Program, list]:
    """A program and a trial program (:func:`_append_checks`), each with placeholders for the arguments."""
    for example in examples:
        shape(example)
    made = []
    for _ in range(2):
        program = _Program(ops)
        program.namespace["_all"] = _all
        made += [program, [_placeholder(program, e, f"a{j}") for j, e in enumerate(examples)]]
    return tuple(made)


def trace_first_false(predicates, ops, *examples) -> Callable[..., int]:
    """One program for the predicates ``predicate(ops, *args) -> bool`` in turn, for arguments of the shape of
    ``examples``: returns the index of the first that is false (on a batch: false for some train), or -1 if all
    hold. Each predicate is evaluated
    only if those before it hold (as one checks them in turn); one that cannot be traced is called as it is."""
    program, placeholders, trial, trial_placeholders = _programs(ops, examples)
    arguments = [f"a{j}" for j in range(len(examples))]
    _append_checks(program, predicates, placeholders, (trial, trial_placeholders), arguments, str)
    return _compile(program, arguments, [*program.lines, "return -1"], "predicates")


def trace_step_first_false(step, predicates, ops, *examples) -> Callable[..., tuple]:
    """One program for a node's ``step(ops, *args) -> (next state, outputs)`` and then the predicates
    ``predicate(ops, *args, outputs, next state) -> bool`` on its result in turn (as :func:`trace_first_false`),
    for arguments of the shape of ``examples``: returns (next state, outputs, the index of the first predicate that
    is false or -1). What a predicate computes that the step has computed already is not computed again."""
    program, placeholders, trial, trial_placeholders = _programs(ops, examples)
    arguments = [f"a{j}" for j in range(len(examples))]
    nxt, out = _traced(program, step, placeholders)
    trial_nxt, trial_out = _traced(trial, step, trial_placeholders)
    built = _rebuild(program, (nxt, out))
    result = program.fresh("r")
    program.lines.append(f"{result} = {built}")
    _append_checks(
        program,
        predicates,
        [*placeholders, out, nxt],
        (trial, [*trial_placeholders, trial_out, trial_nxt]),
        [*arguments, f"{result}[1]", f"{result}[0]"],
        lambda index: f"{result}[0], {result}[1], {index}",
    )
    lines = [*program.lines, f"return {result}[0], {result}[1], -1"]
    return _compile(program, arguments, lines, f"{_name(step)} and predicates")


__all__ = ["LEAVES", "Term", "TraceOps", "Untraceable", "shape", "trace", "trace_first_false", "trace_step_first_false"]
