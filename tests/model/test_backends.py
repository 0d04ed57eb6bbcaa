"""Every registered node runs under all three backends, and they agree (one source of truth).

Differential test: for random parameters, states and inputs, the float run (scalar
and numpy batch), the exact run and the symbolic run (one symbolic step,
evaluated by substituting the values) give the same next state and outputs.
Tolerance: exact and symbolic agree exactly. Numbers are drawn on a 1/8 grid
within +-10^4, so the float run starts from the same values and its sums,
differences and products of two are exact in binary: every comparison, hence
every boolean and every branch, agrees exactly. Numeric outputs may involve
squared speeds, longer products and divisions, and a small result may be the
difference of two large terms, so they agree within 1e-9 relative to the
larger of the result and the largest squared input (the size of a term such
as ``v^2``). A node whose outputs are braking-curve locations walks from
``FAR_M`` behind its target (the walk's bound), so positions of that size
enter its sums: its scale is at least ``FAR_M``.
"""

from fractions import Fraction

import numpy as np
import pytest
import z3
from hypothesis import given, settings
from hypothesis import strategies as st

from atcs.model import NODES
from atcs.model.curves import FAR_M, CurveLocations
from atcs.model.node import as_dict, flatten
from atcs.model.ops.exact import EXACT
from atcs.model.ops.floating import FLOAT
from atcs.model.ops.symbolic import SYMBOLIC, unwrap
from atcs.model.ops.traced import shape, trace, trace_first_false, trace_step_first_false
from atcs.proofs.engine.system import variables
from atcs.properties import PROPERTIES
from atcs.sim.monitor import _checked

REL_TOL = 1e-9
ROLES = ("params", "state", "inputs")

number = st.integers(min_value=-80_000, max_value=80_000).map(lambda k: k / 8)


def value(sort):
    scalar = number if sort.kind == "real" else st.booleans()
    return scalar if sort.size is None else st.tuples(*[scalar] * sort.size)


def record(node, role):
    """A strategy for one {field: value} record of a node dataclass (floats and bools, tuples for arrays)."""
    return st.fixed_dictionaries({n: value(s) for n, s in node.sorts(role).items()})


def example(node):
    return st.fixed_dictionaries({role: record(node, role) for role in ROLES})


def exact(v):
    if isinstance(v, tuple):
        return tuple(exact(x) for x in v)
    return Fraction(v) if isinstance(v, float) else v


def as_exact(values):
    return {n: exact(v) for n, v in values.items()}


def run(node, ops, values):
    p = node.params(**values["params"])
    s = node.state(**values["state"])
    i = node.inputs(**values["inputs"])
    nxt, out = node.step(ops, p, s, i)
    return as_dict(nxt), as_dict(out)


_symbolic_steps = {}


def symbolic_step(node):
    """One symbolic step of ``node`` over variables, built once per node."""
    if node.name not in _symbolic_steps:
        args = {role: variables(getattr(node, role), node, role, "t") for role in ROLES}
        nxt, out = node.step(SYMBOLIC, args["params"], args["state"], args["inputs"])
        _symbolic_steps[node.name] = (args, as_dict(nxt), as_dict(out))
    return _symbolic_steps[node.name]


def run_symbolic(node, values):
    args, nxt, out = symbolic_step(node)
    subst = []
    for role in ROLES:
        variables_ = flatten(as_dict(args[role]))
        for name, v in flatten(values[role]).items():
            term = z3.BoolVal(v) if isinstance(v, bool) else z3.Q(v.numerator, v.denominator)
            subst.append((unwrap(variables_[name]), term))

    def evaluate(value):
        if isinstance(value, tuple):
            return tuple(evaluate(v) for v in value)
        term = z3.simplify(z3.substitute(unwrap(value), *subst))
        if z3.is_true(term) or z3.is_false(term):
            return z3.is_true(term)
        assert z3.is_rational_value(term), f"not closed after substitution: {term}"
        return term.as_fraction()

    return {n: evaluate(v) for n, v in nxt.items()}, {n: evaluate(v) for n, v in out.items()}


def input_scale(values) -> float:
    """The largest squared magnitude among the numeric parameters, state and inputs (at least 1)."""
    numbers = [abs(float(v)) for role in ROLES for v in flatten(values[role]).values() if not isinstance(v, bool)]
    return max([1.0, *(x * x for x in numbers)])


def assert_float_close(float_values, exact_values, what, scale=1.0):
    for name, e in flatten(exact_values).items():
        f = flatten(float_values)[name]
        if isinstance(e, bool):
            assert bool(f) == e, f"{what}.{name}: float {f} vs exact {e}"
        else:
            tolerance = REL_TOL * max(scale, abs(float(e)))
            assert abs(float(f) - float(e)) <= tolerance, f"{what}.{name}: {f} vs {e}"


def outcome(compute, *args):
    """What ``compute(*args)`` returns, or the type of the exception it raises (a division by zero on drawn data)."""
    try:
        return compute(*args)
    except ArithmeticError as exc:
        return type(exc)


_programs: dict = {}


def _program(tracer, node, checks, ops, *args):
    """The program ``tracer`` makes of the node's step (or of its checks, or of both) for the shape of ``args``,
    made once per shape and run on every example of that shape (as the simulator does): the program must hold for
    every value of the shape, not only the one it was traced on."""
    key = (tracer, node.name, ops.name, shape(args))
    if key not in _programs:
        if tracer is trace_step_first_false:
            _programs[key] = tracer(node.step, checks, ops, *args)
        else:
            _programs[key] = tracer(node.step, ops, *args) if tracer is trace else tracer(checks, ops, *args)
    return _programs[key]


@pytest.mark.parametrize("node", NODES.values(), ids=list(NODES))
class TestEveryNodeUnderEveryBackend:
    def test_runs_under_all_three_backends(self, node):
        values = {
            role: {
                n: (1.5 if s.kind == "real" else True)
                if s.size is None
                else ((1.5,) * s.size if s.kind == "real" else (True,) * s.size)
                for n, s in node.sorts(role).items()
            }
            for role in ROLES
        }
        float_run = run(node, FLOAT, values)
        exact_run = run(node, EXACT, {r: as_exact(v) for r, v in values.items()})
        symbolic_run = run_symbolic(node, {r: as_exact(v) for r, v in values.items()})
        assert exact_run == symbolic_run
        for f, e, what in zip(float_run, exact_run, ("state", "outputs"), strict=True):
            assert_float_close(f, e, what)
        assert set(float_run[1]) == set(node.sorts("outputs"))

    @settings(max_examples=60)  # the symbolic side (substitute + simplify) is the slow part
    @given(data=st.data())
    def test_backends_agree(self, node, data):
        values = data.draw(example(node))
        exact_values = {r: as_exact(v) for r, v in values.items()}
        exact_nxt, exact_out = run(node, EXACT, exact_values)
        assert (exact_nxt, exact_out) == run_symbolic(node, exact_values)
        float_nxt, float_out = run(node, FLOAT, values)
        scale = input_scale(values)
        if issubclass(node.outputs, CurveLocations):
            scale = max(scale, float(FAR_M))
        assert_float_close(float_nxt, exact_nxt, "state", scale)
        assert_float_close(float_out, exact_out, "outputs", scale)

    @settings(max_examples=30)
    @given(data=st.data())
    def test_traced_program_equals_the_step(self, node, data):
        """The straight-line program traced from the step (from the checks of its properties, and from both in one
        program, as the simulator runs them) computes what the step and the checks compute, to the bit, on exact
        numbers and on floats."""
        values = data.draw(example(node))
        properties = [_checked(p) for p in PROPERTIES.values() if p.node is node]
        for ops, chosen in ((EXACT, {r: as_exact(v) for r, v in values.items()}), (FLOAT, values)):
            p, s, i = (getattr(node, role)(**chosen[role]) for role in ROLES)
            direct = outcome(node.step, ops, p, s, i)
            assert outcome(_program(trace, node, properties, ops, p, s, i), p, s, i) == direct, ops.name
            if isinstance(direct, tuple):
                nxt, out = direct
                checks = [outcome(c, ops, p, s, i, out, nxt) for c in properties]
                first = next((j for j, c in enumerate(checks) if c is not True), -1)
                program = _program(trace_first_false, node, properties, ops, p, s, i, out, nxt)
                combined = _program(trace_step_first_false, node, properties, ops, p, s, i)
                if first < 0 or checks[first] is False:
                    assert program(p, s, i, out, nxt) == first, ops.name
                    assert combined(p, s, i) == (nxt, out, first), ops.name
                else:  # the first check that is not true raised: so does the program
                    assert outcome(program, p, s, i, out, nxt) == checks[first], ops.name
                    assert outcome(combined, p, s, i) == checks[first], ops.name

    @settings(max_examples=40)  # each example steps up to 16 trains twice: 640 runs per node
    @given(data=st.data())
    def test_numpy_batch_equals_scalar_runs(self, node, data):
        """One call on arrays (an array per scalar field, a tuple of arrays per array field) steps a batch."""
        batch = data.draw(st.lists(example(node), min_size=1, max_size=16))

        def column(role, name, sort):
            if sort.size is None:
                return np.array([b[role][name] for b in batch])
            return tuple(np.array([b[role][name][j] for b in batch]) for j in range(sort.size))

        arrays = {role: {n: column(role, n, s) for n, s in node.sorts(role).items()} for role in ROLES}
        batch_nxt, batch_out = run(node, FLOAT, arrays)
        for t, values in enumerate(batch):
            nxt, out = run(node, FLOAT, values)
            for got, want in ((flatten(batch_nxt), flatten(nxt)), (flatten(batch_out), flatten(out))):
                for name, v in want.items():
                    assert np.shape(got[name]) == (len(batch),), f"{name} is not a batch"
                    assert got[name][t] == v, f"train {t} field {name}: batch {got[name][t]} vs scalar {v}"
