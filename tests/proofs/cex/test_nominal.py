"""Near-nominal counterexamples (``--nominal``): measured inputs paired with their true values by name, z3's
optimizer on linear runs, bisection on nonlinear ones with its lower bound checked by a solver of the test's own,
every chosen run replayed exactly, and the command line's reports."""

import dataclasses
import json
from dataclasses import dataclass
from fractions import Fraction
from typing import Generic

import pytest
import z3

from atcs.model import closed_loop
from atcs.model.closed_loop import CLOSED_LOOP
from atcs.model.node import Node, as_dict, stateless_node
from atcs.model.ops import B, N
from atcs.model.ops.symbolic import fresh_context, unwrap
from atcs.model.supervision import supervise
from atcs.model.train_data import seed000_train, subset026_national
from atcs.proofs.cex.nominal import deviations, measurement_pairs, nominal_distance, nominalise
from atcs.proofs.cex.trace import reproduce
from atcs.proofs.cli import main
from atcs.proofs.engine.bmc import Bmc
from atcs.proofs.engine.prove import prove
from atcs.proofs.engine.system import Unrolling
from atcs.proofs.mutation.mutants import mutant_property, patched
from atcs.properties import PROPERTIES
from atcs.properties.closed_loop import closed_loop_properties, preset_data
from atcs.properties.property import Property

LATCH = "supervision.eb_latched_until_standstill"
# the closed loop's max safe front taken without the odometry error (tests/proofs/cex/test_counterexamples.py)
ODOMETRY_FAULT = (
    closed_loop.max_safe_front_m,
    "i.measured_front_m + p.position_error_m",
    "i.measured_front_m",
)


@dataclass(frozen=True)
class NoParams(Generic[N, B]):
    pass


@dataclass(frozen=True)
class Train(Generic[N, B]):
    speed_mps: N
    front_m: N


@dataclass(frozen=True)
class Readings(Generic[N, B]):
    speed_meas_mps: N
    front_measured_m: N
    accel_mps2: N
    fault: B


@dataclass(frozen=True)
class Shown(Generic[N, B]):
    shown_mps: N


def _odometer_step(o, p, s, i):
    return Train(speed_mps=s.speed_mps + i.accel_mps2, front_m=s.front_m + s.speed_mps), Shown(i.speed_meas_mps)


ODOMETER = Node(
    "odometer",
    NoParams,
    Train,
    Readings,
    Shown,
    init=lambda o, p, s: o.and_(o.eq(s.speed_mps, o.const(0)), o.eq(s.front_m, o.const(0))),
    step=_odometer_step,
)


def display_property(strict: bool) -> Property:
    """The display shows under 10 m/s (``strict``: at most 10): the train starts at rest, so a violation needs a
    speed reading at least (``strict``: above) 10 m/s off the true speed."""
    return Property(
        name=f"odometer.display_{'at_most' if strict else 'under'}_10",
        node=ODOMETER,
        requirement="TEST",
        seed="",
        text="the display shows under 10 m/s",
        holds=lambda o, p, s, i, out, nxt: out.shown_mps <= o.const(10) if strict else out.shown_mps < o.const(10),
        max_k=2,
    )


@pytest.fixture(scope="module")
def latch():
    mutant = mutant_property(
        PROPERTIES[LATCH], "eb_released = o.and_(standstill, eb_release)", "eb_released = eb_release", helper=supervise
    )
    return dataclasses.replace(mutant, name="mutant.eb_latch_without_standstill")


def coarse_no_overrun() -> Property:
    """The coarse closed loop's no-overrun property (tests/model/test_closed_loop.py), without its lemmas."""
    coarse = preset_data(
        dataclasses.replace(seed000_train(), t_be_s=Fraction(8, 5)), subset026_national(), cycle_s=Fraction(4, 5)
    )
    prop = next(p for p in closed_loop_properties("coarse", coarse) if p.name == "closed_loop.no_overrun_coarse")
    return dataclasses.replace(prop, lemmas=())


@pytest.fixture(scope="module")
def closed_loop_runs():
    """The odometry-error mutant's counterexample, from BMC and near nominal; (property, plain, nominal)."""
    prop = coarse_no_overrun()
    with patched(*ODOMETRY_FAULT):
        plain = prove(prop, timeout_s=120, max_k=12)
        nominal = prove(prop, timeout_s=120, max_k=12, nominal_cex=True)
    assert plain.status == nominal.status == "falsified" and plain.k == nominal.k, (plain.message, nominal.message)
    return prop, plain, nominal


class TestPairs:
    def test_measured_inputs_of_the_closed_loop(self):
        assert measurement_pairs(CLOSED_LOOP) == [
            ("measured_front_m", "state", "front_m"),
            ("measured_speed_mps", "state", "speed_mps"),
        ]

    def test_an_input_with_a_true_field_is_measured(self):
        assert measurement_pairs(PROPERTIES["curves.order_seed000"].node) == [("speed_mps", "inputs", "true_speed_mps")]

    def test_meas_inside_the_name(self):
        assert measurement_pairs(ODOMETER) == [
            ("speed_meas_mps", "state", "speed_mps"),
            ("front_measured_m", "state", "front_m"),
        ]

    def test_no_measured_input(self):
        assert measurement_pairs(PROPERTIES[LATCH].node) == []

    def test_a_counterpart_must_be_a_real_of_the_same_shape(self):
        @dataclass(frozen=True)
        class Inputs(Generic[N, B]):
            measured_level: N
            level: B

        node = stateless_node("levels", params=NoParams, inputs=Inputs, outputs=Shown, step=lambda o, p, s, i: None)
        assert measurement_pairs(node) == []

    def test_deviations_per_step_and_array_element(self):
        states = [{"speed_mps": Fraction(1), "front_m": Fraction(0)}, {"speed_mps": Fraction(2), "front_m": 1}]
        inputs = [
            {"speed_meas_mps": Fraction(3), "front_measured_m": Fraction(-1), "accel_mps2": Fraction(-4), "fault": True}
        ]
        errors, magnitudes = deviations(ODOMETER, states, inputs)  # one step: the inputs' count
        assert errors == [(3, 1), (-1, 0)] and magnitudes == [-4]


class TestLinear:
    def test_optimal_run_has_every_input_at_zero(self, latch):
        plain = prove(latch, timeout_s=120)
        result = prove(latch, timeout_s=120, nominal_cex=True)
        assert result.status == "falsified" and result.k == plain.k
        assert result.nominal.status == "optimal" and result.nominal.distance == (0, 0)
        assert nominal_distance(latch.node, result.trace) == (0, 0)
        assert all(v == 0 for inputs in result.trace.inputs for v in inputs.values() if not isinstance(v, bool))
        assert reproduce(latch, result.trace).first_violation == result.k
        assert (
            "; nominal: measurement error 0 -> 0, input magnitude" in result.message and "(optimal)" in result.message
        )

    def test_the_measurement_error_the_violation_needs_and_no_more(self):
        result = prove(display_property(strict=False), timeout_s=60, nominal_cex=True)
        nominal = result.nominal
        assert result.status == "falsified" and nominal.status == "optimal"
        assert nominal.distance == nominal.lower == (10, 0)
        step = result.trace.inputs[0]
        assert (step["speed_meas_mps"], step["front_measured_m"], step["accel_mps2"]) == (10, 0, 0)

    def test_a_minimum_not_attained_is_approached(self):
        """Above 10 m/s: the least error, 10, is an infimum. The run kept is a counterexample within 0.1% of the
        BMC run's error above it, and 10 is its proved lower bound."""
        prop = display_property(strict=True)
        result = prove(prop, timeout_s=60, nominal_cex=True)
        nominal = result.nominal
        assert result.status == "falsified" and nominal.status in ("optimal", "near optimal"), nominal
        error = nominal.distance[0]
        assert 10 < error <= 10 + nominal.original[0] / 1000 and nominal.lower[0] <= 10
        assert reproduce(prop, result.trace).first_violation == 0


def error_at_most(prop: Property, k: int, bound: Fraction) -> str:
    """A solver of the test's own (z3's default): is there a run violating ``prop`` first at step ``k`` whose
    measurement error is at most ``bound``?"""
    with fresh_context():
        u = Unrolling(prop)
        solver = z3.Solver(ctx=u.init().ctx)
        solver.add(u.init())
        for j in range(k + 1):
            f = u.frame(j)
            solver.add(f.trans, f.assumed, z3.Not(f.prop) if j == k else f.prop)
        errors, _ = deviations(
            prop.node, [as_dict(u.state(j)) for j in range(k + 1)], [as_dict(u.frame(j).inputs) for j in range(k + 1)]
        )
        solver.add(z3.Sum([z3.If(unwrap(m) >= unwrap(t), unwrap(m - t), unwrap(t - m)) for m, t in errors]) <= bound)
        solver.set(timeout=120_000)
        return str(solver.check())


class TestNonlinear:
    def test_the_measurement_error_drops_and_the_run_replays(self, closed_loop_runs):
        prop, plain, result = closed_loop_runs
        nominal = result.nominal
        assert nominal.original == nominal_distance(prop.node, plain.trace)
        assert nominal.distance == nominal_distance(prop.node, result.trace)
        assert nominal.status == "near optimal", nominal
        assert nominal.lower[0] < nominal.distance[0] < nominal.original[0]
        assert nominal.distance[0] - nominal.lower[0] <= nominal.original[0] / 1000
        with patched(*ODOMETRY_FAULT):
            assert reproduce(prop, result.trace).first_violation == result.k

    def test_the_lower_bound_by_a_direct_solver_check(self, closed_loop_runs):
        prop, _, result = closed_loop_runs
        with patched(*ODOMETRY_FAULT):
            assert error_at_most(prop, result.k, result.nominal.distance[0]) == "sat"
            assert error_at_most(prop, result.k, result.nominal.lower[0]) == "unsat"

    def test_no_time_left_keeps_the_bmc_run(self, closed_loop_runs):
        prop, plain, _ = closed_loop_runs
        with fresh_context(), patched(*ODOMETRY_FAULT):
            u = Unrolling(prop)
            bmc = Bmc(u)
            check = next(c for c in (bmc.check(k, 60) for k in range(plain.k + 1)) if c.result == "sat")
            model, nominal = nominalise(u, bmc.solver, plain.k, check.model, 0)
        assert model is check.model and nominal.status == "not optimal"
        assert nominal.distance == nominal.original and "the time ran out" in nominal.message


def test_smoothing_and_nominal_exclude_each_other(latch):
    with pytest.raises(ValueError, match="not both"):
        prove(latch, timeout_s=10, smooth_cex=True, nominal_cex=True)


class TestCommandLine:
    def test_reports_record_the_distances(self, latch, monkeypatch, tmp_path):
        monkeypatch.setitem(PROPERTIES, latch.name, latch)
        report, cex = tmp_path / "r.json", tmp_path / "cex"
        assert main(["prove", "--only", "mutant.*", "--nominal", "--json", str(report), "--cex-dir", str(cex)]) == 1
        (record,) = json.loads(report.read_text())["properties"]
        assert record["smoothing"] is None
        assert record["nominal"]["status"] == "optimal"
        assert record["nominal"]["measurement_error"] == record["nominal"]["input_magnitude"] == "0"
        doc = json.loads((cex / f"{latch.name}.json").read_text())
        assert doc["nominal"] == record["nominal"]
        assert main(["replay", str(cex / f"{latch.name}.json")]) == 0

    def test_with_smooth_is_a_usage_error(self, capsys):
        assert main(["prove", "--only", LATCH, "--smooth", "--nominal"]) == 2
        assert "--nominal: not allowed with argument --smooth" in capsys.readouterr().err
