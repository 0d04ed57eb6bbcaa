"""The Ops backends: semantics each backend must share, and the symbolic backend's refusals."""

import bisect
from fractions import Fraction

import numpy as np
import pytest
import z3

from atcs.model.ops import backends
from atcs.model.ops.exact import EXACT
from atcs.model.ops.floating import FLOAT
from atcs.model.ops.symbolic import SYMBOLIC, Bool, Real, SymbolicValueError, fresh_context, unwrap


def sym_value(value):
    """Evaluate a closed symbolic term to a Fraction or bool."""
    term = z3.simplify(unwrap(value))
    if z3.is_true(term) or z3.is_false(term):
        return z3.is_true(term)
    return term.as_fraction()


class TestRegistry:
    def test_three_backends_by_name(self):
        assert set(backends()) == {"float", "exact", "symbolic"}


class TestSharedSemantics:
    @pytest.mark.parametrize("name", ["float", "exact", "symbolic"])
    def test_operations_agree(self, name):
        o = backends()[name]
        read = sym_value if name == "symbolic" else (lambda v: v)
        two, three = o.const(2), o.const("3")
        assert read(o.min(three, two, o.const(5))) == 2
        assert read(o.max(two, three)) == 3
        assert read(o.min(two)) == 2 and read(o.max(three)) == 3
        assert read(o.ite(two < three, two, three)) == 2
        assert read(o.ite(o.const_bool(False), two, three)) == 3
        assert read(o.and_()) is True and read(o.or_()) is False
        assert read(o.and_(two < three, o.not_(three < two))) is True
        assert read(o.or_(three < two, two < two)) is False
        assert read(o.implies(three < two, two < two)) is True
        assert read(o.eq(two + 1, three)) is True
        assert read(o.eq(two < three, o.const_bool(True))) is True
        assert read(o.const("0.1") * 10) == 1

    @pytest.mark.parametrize("name", ["float", "exact", "symbolic"])
    def test_const_refuses_floats_and_bools(self, name):
        o = backends()[name]
        with pytest.raises(TypeError, match=r"0\.1"):
            o.const(0.1)
        with pytest.raises(TypeError):
            o.const(True)
        with pytest.raises(ValueError, match="'x'"):
            o.const("x")


class TestTableLookup:
    """``select`` and ``find`` are the same total functions in every backend."""

    @pytest.mark.parametrize("name", ["float", "exact", "symbolic"])
    def test_select_and_find_agree(self, name):
        o = backends()[name]
        read = sym_value if name == "symbolic" else (lambda v: v)
        table = (o.const(5), o.const(6), o.const(7))
        assert [read(o.select(table, o.const(j))) for j in range(3)] == [5, 6, 7]
        # outside 0 .. n-1, or not whole: the last value
        assert [read(o.select(table, o.const(j))) for j in ("-1", "3", "0.5")] == [7, 7, 7]
        assert read(o.select((o.const_bool(True), o.const_bool(False)), o.const(0))) is True
        found, index = o.find((o.const(4), o.const(9), o.const(4)), o.const(4))
        assert (read(found), read(index)) == (True, 0)  # the first match
        found, index = o.find(table, o.const(8))
        assert (read(found), read(index)) == (False, 0)

    @pytest.mark.parametrize("name", ["float", "exact", "symbolic"])
    def test_empty_table_refused(self, name):
        o = backends()[name]
        with pytest.raises(ValueError, match="select: the table is empty"):
            o.select((), o.const(0))
        with pytest.raises(ValueError, match="find: the table is empty"):
            o.find((), o.const(0))

    @pytest.mark.parametrize("name", ["float", "exact", "symbolic"])
    def test_first_above_on_ascending_keys(self, name):
        o = backends()[name]
        read = sym_value if name == "symbolic" else (lambda v: v)
        keys = tuple(o.const(k) for k in (1, 3, 3, 8))
        got = [read(o.first_above(keys, o.const(x))) for x in (0, 1, 2, 3, "7.5", 8, 9)]
        assert got == [0, 1, 1, 3, 3, 4, 4]

    @pytest.mark.parametrize("name", ["float", "exact", "symbolic"])
    def test_first_above_is_bisect_right_on_any_keys(self, name):
        """Not ascending: the search's own answer in every backend, so the backends agree on any data."""
        o = backends()[name]
        read = sym_value if name == "symbolic" else (lambda v: v)
        for keys, key in [((5, 1, 2), 1), ((5, 1, 2), 6), ((3, 9, 0, 4, 1), 2), ((2,), 2), ((), 4)]:
            got = read(o.first_above(tuple(o.const(k) for k in keys), o.const(key)))
            assert got == bisect.bisect_right(keys, key), (keys, key)

    @pytest.mark.parametrize("name", ["float", "exact", "symbolic"])
    def test_floor_rounds_down_to_a_whole_number(self, name):
        o = backends()[name]
        read = sym_value if name == "symbolic" else (lambda v: v)
        got = [read(o.floor(o.const(x))) for x in ("2.5", 3, "-0.25", "-3", "1/3")]
        assert got == [2, 3, -1, -3, 0]

    def test_floor_float_batch(self):
        assert FLOAT.floor(np.array([2.5, -0.25, 7.0])).tolist() == [2.0, -1.0, 7.0]

    def test_first_above_float_batch(self):
        index = FLOAT.first_above((1.0, 3.0, 3.0, 8.0), np.array([0.0, 3.0, 7.5, 9.0]))
        assert index.tolist() == [0.0, 3.0, 3.0, 4.0]
        assert FLOAT.first_above((), np.array([1.0, 2.0])).tolist() == [0.0, 0.0]

    def test_float_batch(self):
        picked = FLOAT.select((5.0, 6.0, 7.0), np.array([0.0, 2.0, 5.0, 1.5]))
        assert picked.tolist() == [5.0, 7.0, 7.0, 7.0]
        found, index = FLOAT.find((5.0, 6.0, 7.0), np.array([7.0, 1.0, 6.0]))
        assert found.tolist() == [True, False, True] and index.tolist() == [2.0, 0.0, 1.0]


class TestSortByKey:
    KEYS = (3, 1, 2, 1, 0, 3)
    TAGS = ("a", "b", "c", "d", "e", "f")  # which input each key came from: ties keep their order

    @pytest.mark.parametrize("name", ["float", "exact", "symbolic"])
    def test_sorts_stably_and_permutes_columns_alike(self, name):
        o = backends()[name]
        read = sym_value if name == "symbolic" else (lambda v: v)
        keys = tuple(o.const(k) for k in self.KEYS)
        positions = tuple(o.const(j) for j in range(len(keys)))
        flags = tuple(o.const_bool(k == 1) for k in self.KEYS)
        sorted_keys, sorted_positions, sorted_flags = o.sort_by_key(keys, positions, flags)
        assert [read(k) for k in sorted_keys] == [0, 1, 1, 2, 3, 3]
        assert [self.TAGS[int(read(j))] for j in sorted_positions] == ["e", "b", "d", "c", "a", "f"]
        assert [read(f) for f in sorted_flags] == [False, True, True, False, False, False]

    @pytest.mark.parametrize("name", ["float", "exact", "symbolic"])
    def test_column_length_must_match(self, name):
        o = backends()[name]
        with pytest.raises(ValueError, match=r"columns\[1\] has 1 entries, keys has 2"):
            o.sort_by_key((o.const(1), o.const(2)), (o.const(0), o.const(0)), (o.const(0),))

    def test_float_batch_sorts_each_train(self):
        keys = (np.array([2.0, 0.0]), 1.0, np.array([0.0, 5.0]))
        sorted_keys, tags = FLOAT.sort_by_key(keys, ("x", "y", "z"))
        assert np.stack(sorted_keys).T.tolist() == [[0.0, 1.0, 2.0], [0.0, 1.0, 5.0]]
        assert np.stack(tags).T.tolist() == [["z", "y", "x"], ["x", "y", "z"]]


class TestBitFields:
    """``pack_bits`` and ``unpack_bits``: fields most significant first, each ``floor(value) mod 2^width``, the
    same in every backend (a negative value in two's complement, a fraction rounded down)."""

    FIELDS = (("5", 3), ("-1", 4), ("7.9", 5), ("-2.5", 8))
    READ = (5, 15, 7, 253)

    @pytest.mark.parametrize("name", ["float", "exact", "symbolic"])
    def test_round_trip_and_wrap(self, name):
        o = backends()[name]
        read = sym_value if name == "symbolic" else (lambda v: v)
        bits = o.pack_bits(tuple((o.const(v), w) for v, w in self.FIELDS))
        assert tuple(read(f) for f in o.unpack_bits(bits, (3, 4, 5, 8))) == self.READ
        halves = o.unpack_bits(bits, (10, 10))  # any widths summing to the string's: the fields' bits regrouped
        assert [read(f) for f in halves] == [(5 << 7 | 15 << 3 | 7 >> 2), ((7 & 3) << 8 | 253)]

    @pytest.mark.parametrize("name", ["float", "exact", "symbolic"])
    @pytest.mark.parametrize(("widths", "message"), [((3, 4), "sum to 7, the bit string has 20"), ((20, 0), ">= 1")])
    def test_widths_are_checked(self, name, widths, message):
        o = backends()[name]
        bits = o.pack_bits(tuple((o.const(v), w) for v, w in self.FIELDS))
        with pytest.raises(ValueError, match=message):
            o.unpack_bits(bits, widths)

    def test_float_batch_packs_each_train(self):
        bits = FLOAT.pack_bits(((np.array([1.0, 2.0]), 4), (3.0, 4)))
        assert [b.value for b in bits] == [0x13, 0x23]
        assert [f.tolist() for f in FLOAT.unpack_bits(bits, (4, 4))] == [[1.0, 2.0], [3.0, 3.0]]

    def test_symbolic_bits_refuse_python_use(self):
        bits = SYMBOLIC.pack_bits(((SYMBOLIC.const(1), 4),))
        with pytest.raises(SymbolicValueError):
            bool(bits)
        with pytest.raises(SymbolicValueError):
            SYMBOLIC.unpack_bits(SYMBOLIC.const(1), (4,))


class TestSymbolicRefusals:
    def setup_method(self):
        self.x, self.y = Real(z3.Real("x")), Real(z3.Real("y"))

    def test_bool_of_comparison_refused(self):
        with pytest.raises(SymbolicValueError, match=r"o\.ite"):
            bool(self.x < self.y)
        with pytest.raises(SymbolicValueError):
            if self.x:
                pass

    def test_equality_refused(self):
        # z3's own `==` would be silently decided by structural equality in an `if`
        with pytest.raises(SymbolicValueError, match=r"o\.eq"):
            _ = self.x == self.y
        with pytest.raises(SymbolicValueError, match=r"o\.eq"):
            _ = self.x != self.y
        b = self.x < self.y
        with pytest.raises(SymbolicValueError):
            _ = b == b

    def test_python_and_or_not_refused(self):
        b = self.x < self.y
        with pytest.raises(SymbolicValueError):
            _ = b and b
        with pytest.raises(SymbolicValueError):
            _ = not b

    def test_builtin_min_refused(self):
        with pytest.raises(SymbolicValueError):
            min(self.x, self.y)

    def test_float_operand_refused(self):
        with pytest.raises(SymbolicValueError, match="float"):
            _ = self.x * 0.5

    def test_mixed_exact_operands_accepted(self):
        assert isinstance(Fraction(1, 2) * self.x + 1, Real)
        assert isinstance(Fraction(1, 2) < self.x, Bool)

    def test_not_hashable(self):
        with pytest.raises(TypeError):
            hash(self.x)


class TestFreshContext:
    """Each proof builds its terms in a z3 context of its own (docs/writing-properties.md, Determinism)."""

    def test_every_constant_goes_to_the_block_context(self):
        o = SYMBOLIC
        with fresh_context() as ctx:
            values = (o.const(1), o.const_bool(True), o.and_(), o.or_(), o.find((o.const(2),), o.const(2))[1])
            assert all(unwrap(v).ctx is ctx for v in values)
            with fresh_context() as inner:
                assert inner is not ctx and unwrap(o.const(1)).ctx is inner
            assert unwrap(o.const(1)).ctx is ctx
        assert unwrap(o.const(1)).ctx is z3.main_ctx()

    def test_terms_of_two_contexts_do_not_mix(self):
        with fresh_context():
            x = Real(z3.Real("x", SYMBOLIC.const(0).term.ctx))
        with pytest.raises(z3.Z3Exception):
            unwrap(x + Real(z3.Real("y")))


class TestExactBackend:
    def test_refuses_non_bool_conditions(self):
        with pytest.raises(TypeError, match="bool"):
            EXACT.ite(Fraction(1), 1, 2)

    def test_fraction_arithmetic_is_exact(self):
        assert EXACT.const("0.1") * 3 == Fraction(3, 10)


class TestFloatBatch:
    def test_elementwise_on_arrays(self):
        a = np.array([1.0, 5.0, 3.0])
        b = np.array([2.0, 4.0, 3.0])
        assert FLOAT.min(a, b).tolist() == [1.0, 4.0, 3.0]
        assert FLOAT.max(a, 2.5).tolist() == [2.5, 5.0, 3.0]
        assert FLOAT.ite(a < b, a, b).tolist() == [1.0, 4.0, 3.0]
        assert FLOAT.and_(a < 4, b > 2).tolist() == [False, False, True]
        assert FLOAT.or_(a > 4, b < 3).tolist() == [True, True, False]
        assert FLOAT.not_(a > 2).tolist() == [True, False, False]
        assert FLOAT.eq(a, b).tolist() == [False, False, True]

    def test_scalars_stay_scalars(self):
        assert FLOAT.ite(True, 1.0, 2.0) == 1.0
        assert isinstance(FLOAT.and_(True, False), bool)
