"""Straight-line programs traced from step functions (atcs.model.ops.traced) and the monitor that runs them.

That every node's program and every property's check compute what the functions compute is tested on random
data in tests/model/test_backends.py; here, what a trace refuses, the Fraction fast paths, and the simulator's
check of a step, traced and not, agreeing on every verdict.
"""

import dataclasses
from dataclasses import dataclass
from fractions import Fraction

import pytest
from hypothesis import given
from hypothesis import strategies as st

from atcs.model.ops.exact import EXACT
from atcs.model.ops.floating import FLOAT
from atcs.model.ops.traced import Term, Untraceable, shape, trace, trace_first_false
from atcs.sim import monitor
from atcs.sim.monitor import PropertyViolation, Traces, check_step


@dataclass(frozen=True)
class Pair:
    low: object
    high: object


fractions = st.fractions(min_value=-1000, max_value=1000, max_denominator=1 << 40)


class TestWhatATraceRefuses:
    def test_a_branch_on_a_value(self):
        def branches(o, x):
            return o.const(1) if x > 0 else o.const(2)

        with pytest.raises(Untraceable, match="truth value"):
            trace(branches, EXACT, Fraction(1))

    def test_python_equality(self):
        with pytest.raises(Untraceable, match=r"o\.eq"):
            trace(lambda o, x: x == o.const(1), EXACT, Fraction(1))

    def test_a_value_as_an_index(self):
        with pytest.raises(Untraceable, match="index"):
            trace(lambda o, x, t: t[x], EXACT, 0, (Fraction(1), Fraction(2)))

    def test_a_python_level_use_of_a_value(self):
        with pytest.raises(Untraceable, match="abs"):
            trace(lambda o, x: abs(x), EXACT, Fraction(-3))

    @pytest.mark.parametrize("leaf", [None, "text", [1], 1.5j])
    def test_a_leaf_that_is_not_a_number_or_a_boolean(self, leaf):
        with pytest.raises(Untraceable, match="cannot be traced"):
            shape(Pair(Fraction(1), leaf))

    def test_a_number_where_a_boolean_is_due(self):
        with pytest.raises(Untraceable, match="Fraction where a boolean is due"):
            trace(lambda o, x: o.and_(x, o.const_bool(True)), EXACT, Fraction(1))

    def test_a_term_has_no_hash(self):
        with pytest.raises(TypeError):
            hash(Term(None, "t0"))


class TestPrograms:
    @given(a=fractions, b=fractions)
    def test_fraction_comparisons_and_equality(self, a, b):
        def compare(o, x, y):
            return (x < y, x <= y, x > y, x >= y, o.eq(x, y), o.eq(x, x))

        assert trace(compare, EXACT, a, b)(a, b) == compare(EXACT, a, b)

    @given(a=fractions, b=fractions)
    def test_fraction_arithmetic_gives_fractions_own_results(self, a, b):
        def arithmetic(o, x, y):
            return x + y, x - y, x * y, -x, x + -x, x - x, x * (y - y), x / (y * y + 1), -x / -(y * y + 1)

        traced = trace(arithmetic, EXACT, a, b)(a, b)
        assert [(r.numerator, r.denominator) for r in traced] == [
            (r.numerator, r.denominator) for r in arithmetic(EXACT, a, b)
        ]
        assert all(type(r) is Fraction for r in traced)
        if b:
            quotient = trace(lambda o, x, y: x / y, EXACT, a, b)(a, b)
            assert (quotient.numerator, quotient.denominator) == ((a / b).numerator, (a / b).denominator)

    def test_a_fraction_divided_by_zero_raises_as_fraction_does(self):
        program = trace(lambda o, x, y: x / y, EXACT, Fraction(1), Fraction(1))
        with pytest.raises(ZeroDivisionError):
            program(Fraction(1), Fraction(0))

    @given(a=fractions, b=fractions)
    def test_arithmetic_mixed_with_constants(self, a, b):
        def arithmetic(o, x, y):
            z = o.const("0.1") * x - y / o.const(3) + 2 * x
            return o.ite(z >= -x, o.min(z, y), o.max(-z, x)), o.floor(z), o.first_above((o.const(0), y), x)

        assert trace(arithmetic, EXACT, a, b)(a, b) == arithmetic(EXACT, a, b)
        assert trace(arithmetic, FLOAT, float(a), float(b))(float(a), float(b)) == arithmetic(FLOAT, float(a), float(b))

    def test_a_dataclass_result_passes_arguments_through(self):
        def swap(o, pair):
            return Pair(pair.high, pair.low)

        program = trace(swap, EXACT, Pair(Fraction(1), True))
        assert program(Pair(Fraction(3), False)) == Pair(False, Fraction(3))

    def test_table_operations(self):
        def tables(o, keys, key):
            found, index = o.find(keys, key)
            return found, index, o.select(keys, index), o.sort_by_key(keys, tuple(-k for k in keys))

        keys = (Fraction(3), Fraction(1), Fraction(2))
        assert trace(tables, EXACT, keys, Fraction(2))(keys, Fraction(1)) == tables(EXACT, keys, Fraction(1))

    def test_the_first_false_predicate_and_one_that_cannot_be_traced(self):
        calls = []

        def untraceable(o, x):
            calls.append(x)
            return bool(x > 1)  # a Python branch: run as it is

        predicates = [lambda o, x: x > 0, untraceable, lambda o, x: x > 2]
        program = trace_first_false(predicates, EXACT, Fraction(5))
        assert [program(Fraction(v)) for v in (5, 2, 1, 0)] == [-1, 2, 1, 0]
        concrete = [x for x in calls if isinstance(x, Fraction)]  # the trial trace called it with a term first
        assert concrete == [5, 2, 1]  # a predicate is not evaluated once one before it is false


@pytest.fixture(scope="module")
def recorded():
    """The authority node's arguments, every seventh check of 120 cycles of the seed 002 timetable."""
    from atcs.sim.scenario import load_scenario, resolve
    from atcs.sim.simulator import AUTHORITY, AUTHORITY_PROPERTIES, Simulation

    steps = []
    real = monitor.check_step

    def record(node, params, state, inputs, properties, step, ops=FLOAT, traces=None):
        if node is AUTHORITY:
            steps.append((params, state, inputs))
        return real(node, params, state, inputs, properties, step, ops, traces)

    sim = Simulation(load_scenario(resolve("seed002_timetable")))
    import atcs.sim.simulator as simulator

    original, simulator.check_step = simulator.check_step, record
    try:
        for _ in range(120):
            sim.step()
    finally:
        simulator.check_step = original
    return AUTHORITY, AUTHORITY_PROPERTIES, steps[::7]


class TestCheckStep:
    """The simulator's check of a step, traced and not, on the authority node of the seed 002 timetable: the same
    next state, outputs and verdicts, and a violation names the same property."""

    def test_traced_and_direct_agree(self, recorded):
        node, properties, steps = recorded
        assert len(steps) > 20
        traces = Traces()
        for params, state, inputs in steps:
            traced = check_step(node, params, state, inputs, properties, 0, EXACT, traces)
            assert traced == check_step(node, params, state, inputs, properties, 0, EXACT)
        assert 0 < len(traces) < len(steps)  # a trace per window length, not per step

    def test_a_violation_names_the_same_property(self, recorded):
        node, properties, steps = recorded
        params, state, inputs = steps[-1]
        nxt, out = node.step(EXACT, params, state, inputs)
        beyond = dataclasses.replace(out, eoa_m=out.eoa_m + 10**6)  # an authority past every blocked resource
        broken = dataclasses.replace(node, step=lambda o, p, s, i: (nxt, beyond))
        verdicts = []
        for traces in (Traces(), None):
            with pytest.raises(PropertyViolation) as caught:
                check_step(broken, params, state, inputs, properties, 3, EXACT, traces)
            verdicts.append((caught.value.prop.name, caught.value.step))
        assert verdicts[0] == verdicts[1]


class TestMonitor:
    """A monitor given traces runs the node's step and its properties' predicates as their programs: the same
    outputs, states and applicable properties as without, cycle by cycle, and a violation names the same property
    at the same step."""

    @staticmethod
    def _runs(node, cycles: int):
        from tests.model.test_position import POSITION_PROPERTIES, _free_running, _motion, _params, _power_up

        p = _params()
        monitors = [
            monitor.Monitor(node, p, _power_up(Fraction(95)), tuple(POSITION_PROPERTIES), EXACT, traces)
            for traces in (Traces(), None)
        ]
        for k in range(cycles):
            steps = []
            for m in monitors:
                s = m.state
                v_next, distance = _motion(p, s.speed_mps, Fraction(1, 2))
                passed = [x for x in p.tag_positions_m if s.front_m < x <= s.front_m + distance]
                since = s.front_m + distance - passed[0] if passed else Fraction(0)
                tag = p.tag_ids[p.tag_positions_m.index(passed[0])] if passed else Fraction(0)
                tacho = distance * (1 + Fraction((-1) ** k, 100))
                inputs = _free_running(bool(passed), tag, since, tacho, distance, since, v_next)
                try:
                    steps.append((m.step(inputs), m.state, [m.applies(q.name) for q in m.properties]))
                except PropertyViolation as violation:
                    steps.append((violation.prop.name, violation.step))
            yield steps

    def test_traced_and_direct_agree_cycle_by_cycle(self):
        from atcs.model.position_loop import POSITION_LOOP

        for traced, direct in self._runs(POSITION_LOOP, 120):
            assert traced == direct

    def test_a_violation_names_the_same_property_at_the_same_step(self):
        from atcs.model.position_loop import POSITION_LOOP

        def lost_at_tags(o, p, s, i):
            nxt, out = POSITION_LOOP.step(o, p, s, i)
            return nxt, dataclasses.replace(out, front_max_m=o.ite(i.tag_read, out.front_min_m - 1, out.front_max_m))

        broken = dataclasses.replace(POSITION_LOOP, step=lost_at_tags)
        verdicts = [steps for steps in self._runs(broken, 120) if isinstance(steps[0][0], str)]
        assert verdicts, "the broken loop was never caught"
        assert verdicts[0][0] == verdicts[0][1]
