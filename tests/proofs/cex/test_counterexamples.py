"""Counterexample debugging: the VCD waveform and the PNG plot (units, styles, axes around the train) beside the
JSON and CSV, `atcs replay`'s readable values and its float run against the exact one, and smoothing (the fewest
input changes) with its minimality checked by a solver of its own."""

import dataclasses
import io
import json
import struct
from fractions import Fraction

import pytest
import z3
from rich.console import Console
from vcd.reader import TokenKind, tokenize

from atcs.model import position
from atcs.model.closed_loop import CLOSED_LOOP
from atcs.model.node import as_dict, flatten
from atcs.model.ops.symbolic import fresh_context, unwrap
from atcs.model.supervision import supervise
from atcs.proofs.cex import smoothing as smoothing_module
from atcs.proofs.cex.float_replay import float_replay
from atcs.proofs.cex.plot import FAR, STYLES, axis_range, counterexample_figure, legend_label, line_style, plot_fields
from atcs.proofs.cex.trace import Trace, input_changes, replay, reproduce, to_json
from atcs.proofs.cex.vcd import cycle_s, timescale, to_vcd
from atcs.proofs.cli import main
from atcs.proofs.cli.replay import _print_exact
from atcs.proofs.engine.bmc import Bmc, Check
from atcs.proofs.engine.prove import prove
from atcs.proofs.engine.system import Unrolling
from atcs.proofs.mutation.mutants import mutant_property, patched
from atcs.proofs.report import write_counterexample
from atcs.properties import PROPERTIES, Property

LATCH = "supervision.eb_latched_until_standstill"
FALSE_ALARM = "position.no_false_alarm"
# the plausibility check without the tachometer error's slack (tests/model/test_position.py): a false alarm at step 1
SLACK_MUTANT = (position.implausible_increment, "slack = p.tacho_error * (tacho_m + last_m)", "slack = o.const(0)")


def latch_mutant():
    """The EB latch released without standstill (tests/proofs/cli/test_cli.py): violated at step 0."""
    mutant = mutant_property(
        PROPERTIES[LATCH], "eb_released = o.and_(standstill, eb_release)", "eb_released = eb_release", helper=supervise
    )
    return dataclasses.replace(mutant, name="mutant.eb_latch_without_standstill")


@pytest.fixture(scope="module")
def latch():
    mutant = latch_mutant()
    result = prove(mutant, timeout_s=120)
    assert result.status == "falsified"
    return mutant, result


@pytest.fixture(scope="module")
def false_alarm():
    """The slack mutant of POS-12, proved plainly and smoothed; (property, plain result, smoothed result)."""
    prop = dataclasses.replace(PROPERTIES[FALSE_ALARM], lemmas=())
    with patched(*SLACK_MUTANT):
        plain = prove(prop, timeout_s=120, max_k=6)
        smoothed = prove(prop, timeout_s=120, max_k=6, smooth_cex=True)
    assert plain.status == smoothed.status == "falsified", (plain.message, smoothed.message)
    return prop, plain, smoothed


@pytest.fixture
def registered(monkeypatch):
    """Register a property under its own name for the command line."""

    def register(prop):
        monkeypatch.setitem(PROPERTIES, prop.name, prop)
        return prop

    return register


def read_vcd(text: str):
    """The header tokens, ``{scope.name: id}`` and, per id, the value at each timestamp (values carried over)."""
    header, ids, scopes, changes, time = [], {}, [], {}, None
    for token in tokenize(io.BytesIO(text.encode())):
        if token.kind is TokenKind.SCOPE:
            scopes.append(token.data.ident)
        elif token.kind is TokenKind.UPSCOPE:
            scopes.pop()
        elif token.kind is TokenKind.VAR:
            var = token.data
            name = var.reference + ("" if var.bit_index is None else f"[{var.bit_index}]")
            ids[".".join([*scopes, name])] = var.id_code
        elif token.kind is TokenKind.CHANGE_TIME:
            time = token.data
        elif token.kind in (TokenKind.CHANGE_REAL, TokenKind.CHANGE_SCALAR):
            changes.setdefault(token.data.id_code, {})[time] = token.data.value
        if time is None:
            header.append(token.kind)
    return header, ids, changes


def value_at(changes: dict, code: str, time: int):
    """The value of a variable at ``time``: its last change at or before it."""
    return changes[code][max(t for t in changes[code] if t <= time)]


def expected(value):
    """What the VCD holds for an exact value: the nearest double at 16 significant digits, or a bit."""
    return ("1" if value else "0") if isinstance(value, bool) else float(f"{float(value):.16g}")


class TestWaveform:
    @pytest.mark.parametrize("which", ["latch", "false_alarm"])
    def test_every_value_reads_back(self, which, request):
        fixture = request.getfixturevalue(which)
        trace, replayed = fixture[1].trace, fixture[1].replay
        _, ids, changes = read_vcd(to_vcd(trace, replayed))
        node = trace.node
        steps = len(trace.inputs)
        ticks = timescale(cycle_s(trace))[1]  # VCD time units per cycle
        for k in range(steps + 1):
            t = k * ticks
            records = [("state", trace.states[k])]
            if k < steps:
                records += [("inputs", trace.inputs[k]), ("outputs", replayed.outputs[k])]
                assert value_at(changes, ids[f"{node}.holds"], t) == ("1" if replayed.holds[k] else "0")
                assert value_at(changes, ids[f"{node}.violation"], t) == ("1" if k == trace.violation_step else "0")
            for role, record in records:
                for name, value in flatten(record).items():
                    assert value_at(changes, ids[f"{node}.{role}.{name}"], t) == expected(value), (k, role, name)
        for name, value in flatten(trace.params).items():
            assert value_at(changes, ids[f"{node}.params.{name}"], steps * ticks) == expected(value)
        assert max(t for c in changes.values() for t in c) <= steps * ticks

    def test_one_variable_per_field_arrays_spread(self, false_alarm):
        prop, result, _ = false_alarm
        _, ids, _ = read_vcd(to_vcd(result.trace, result.replay))
        node = prop.node
        wanted = {
            f"position_loop.{role}.{name}"
            for role, record in (
                ("params", result.trace.params),
                ("state", result.trace.states[0]),
                ("inputs", result.trace.inputs[0]),
                ("outputs", result.replay.outputs[0]),
            )
            for name in flatten(record)
        }
        assert set(ids) == wanted | {"position_loop.holds", "position_loop.violation"}
        assert f"position_loop.params.tag_ids[{node.sizes['tag_ids'] - 1}]" in ids

    def test_gtkwave_header(self, latch):
        _, result = latch
        text = to_vcd(result.trace, result.replay, date="2026-01-01")
        header, _, _ = read_vcd(text)
        for kind in (
            TokenKind.DATE,
            TokenKind.VERSION,
            TokenKind.TIMESCALE,
            TokenKind.SCOPE,
            TokenKind.VAR,
            TokenKind.UPSCOPE,
            TokenKind.ENDDEFINITIONS,
        ):
            assert kind in header, kind
        assert "$timescale 100 ms $end" in text and "$dumpvars" in text
        assert text.index("$enddefinitions") < text.index("#0")

    def test_real_and_wire_types(self, latch):
        _, result = latch
        text = to_vcd(result.trace, result.replay)
        assert "$var real 64 " in text and " speed_mps $end" in text
        assert "$var wire 1 " in text and " eb_release $end" in text

    @pytest.mark.parametrize(
        ("cycle", "scale"),
        [
            (Fraction(1, 10), ("100 ms", 1, True)),  # seed 001
            (Fraction(4, 5), ("100 ms", 8, True)),  # the coarse closed-loop variant
            (Fraction(1), ("1 s", 1, True)),
            (Fraction(1, 4), ("10 ms", 25, True)),
            (Fraction(1, 3), ("100 ms", 1, False)),  # no unit divides it
        ],
    )
    def test_timescale_is_one_timestamp_per_cycle(self, cycle, scale):
        assert timescale(cycle) == scale

    def test_cycle_from_the_node_else_the_seed(self, latch, false_alarm):
        assert cycle_s(latch[1].trace) == Fraction(1, 10)
        assert cycle_s(false_alarm[1].trace) == false_alarm[1].trace.params["cycle_s"]


class TestPlot:
    def test_fields_of_supervision(self):
        fields = plot_fields(PROPERTIES[LATCH].node)
        assert fields.speeds == [
            ("inputs", n) for n in ("speed_mps", "permitted_mps", "warning_mps", "sbi_mps", "ebi_mps")
        ]
        assert fields.position is None and fields.locations == []
        assert fields.lanes == [
            ("state", "eb_latched"),
            ("state", "sb_latched"),
            ("inputs", "standstill"),
            ("inputs", "eb_release"),
            ("inputs", "position_valid"),
            ("outputs", "warning"),
            ("outputs", "service_brake"),
            ("outputs", "emergency_brake"),
            ("outputs", "traction_cut"),
        ]

    def test_fields_of_the_closed_loop(self):
        fields = plot_fields(CLOSED_LOOP)
        assert fields.position == ("state", "front_m")
        assert fields.speeds == [("state", "speed_mps"), ("inputs", "measured_speed_mps"), ("inputs", "next_speed_mps")]
        assert fields.locations == [
            ("state", "front_m"),
            ("inputs", "measured_front_m"),
            ("inputs", "distance_m"),
            ("outputs", "ebi_m"),
        ]
        assert ("state", "eb_latched") in fields.lanes and ("outputs", "emergency_brake") in fields.lanes
        assert not any(role == "params" for role, _ in fields.speeds + fields.locations + fields.lanes)

    def test_position_falls_back_to_a_front_field(self):
        assert plot_fields(PROPERTIES["authority.behind_leader"].node).position == ("inputs", "front_max_m")
        # not probe_front_m, which comes later among the inputs
        assert plot_fields(PROPERTIES["doors.enable_left_only_at_platform_stop"].node).position == (
            "inputs",
            "front_min_m",
        )

    def test_arrays_spread_as_lanes(self):
        fields = plot_fields(PROPERTIES["resources.mutual_exclusion"].node)
        node = PROPERTIES["resources.mutual_exclusion"].node
        assert ("inputs", f"send[{node.sizes['send'] - 1}]") in fields.lanes

    @pytest.mark.parametrize(
        ("field", "label"),
        [
            (("inputs", "measured_speed_mps"), "inputs.measured_speed"),
            (("state", "front_m"), "state.front"),
            (("state", "cells_m[2]"), "state.cells[2]"),
            (("outputs", "eb_latched"), "outputs.eb_latched"),
            (("inputs", "gradient_permille"), "inputs.gradient_permille"),
        ],
    )
    def test_legends_name_fields_without_their_unit(self, field, label):
        assert legend_label(field) == label

    def test_every_trace_has_its_own_style_the_first_drawn_thickest(self):
        styles = [line_style(j, len(STYLES)) for j in range(len(STYLES))]
        assert len({(str(s["linestyle"]), s["marker"]) for s in styles}) == len(STYLES)
        widths = [s["linewidth"] for s in styles]
        assert widths == sorted(widths, reverse=True) and widths[0] > widths[-1]

    def test_axis_around_the_reference_far_values_left_out(self):
        low, high = axis_range([0.0, 10.0], [0.0, 5.0, -17.5, 1e6, -1e6])
        assert low < -17.5 and 10 < high < FAR + 10
        assert axis_range([], [1.0, 1e6])[1] > 1e6  # no reference: every value
        assert axis_range([5.0], [5.0]) == (4.0, 6.0)  # one value: a margin all the same

    def test_plot_scaled_around_the_train_with_units_on_the_axes(self, false_alarm):
        """The POS-12 mutant's counterexample with a tachometer reading of a million metres: the location axis
        stays around the train, the reading is drawn at its top edge with its value."""
        prop, result, _ = false_alarm
        trace = result.trace
        inputs = [dict(trace.inputs[0], tacho_m=Fraction(10**6)), *trace.inputs[1:]]
        edited = dataclasses.replace(trace, inputs=inputs)
        fig = counterexample_figure(prop.node, edited, replay(prop, edited))
        axes = {ax.get_ylabel(): ax for ax in fig.axes}
        locations = axes["location (m)"]
        front = [float(s["front_m"]) for s in trace.states]
        low, high = locations.get_ylim()
        assert low <= min(front) and max(front) <= high < FAR
        assert "1e+06" in [t.get_text() for t in locations.texts]
        legend = locations.get_legend()
        assert legend.get_title().get_text() == "location (m)"
        labels = [t.get_text() for t in legend.get_texts()]
        assert "inputs.tacho" in labels and not any(label.endswith(("_m", "_mps")) for label in labels)
        speeds = [t.get_text() for t in axes["speed (km/h)"].get_legend().get_texts()]
        assert "state.speed" in speeds and not any("_mps" in label for label in speeds)

    def test_counterexample_files(self, false_alarm, tmp_path):
        prop, result, _ = false_alarm
        path = write_counterexample(tmp_path, prop, result)
        assert path == tmp_path / f"{prop.name}.json"
        for suffix in (".json", ".csv", ".vcd", ".png"):
            assert (tmp_path / f"{prop.name}{suffix}").stat().st_size > 0
        png = (tmp_path / f"{prop.name}.png").read_bytes()
        assert png[:8] == b"\x89PNG\r\n\x1a\n" and png[12:16] == b"IHDR"
        width, height = struct.unpack(">II", png[16:24])
        assert width == 1100 and height > 800  # 11 in at 100 dpi; four panels
        assert not list(tmp_path.glob(".*.tmp"))  # written atomically: no temporary left


def _boundary_trace(mutant, result) -> Trace:
    """The latch mutant's counterexample with the warning limit 1e-30 under the speed: exactly the train is over
    it, in doubles the two are equal. The states are the model's own, so it is still a counterexample."""
    trace = result.trace
    inputs = dict(
        trace.inputs[0],
        speed_mps=Fraction(1, 10),
        permitted_mps=Fraction(1, 10) - Fraction(1, 10**30),
        warning_mps=Fraction(1, 10) - Fraction(1, 10**30),
        sbi_mps=Fraction(1),
        ebi_mps=Fraction(1),
    )
    edited = Trace(trace.property, trace.node, 0, trace.params, [trace.states[0], trace.states[0]], [inputs])
    run = replay(mutant, edited)
    boundary = dataclasses.replace(edited, states=run.states)
    reproduce(mutant, boundary)  # a genuine counterexample of the mutant
    return boundary


def _non_dyadic(prop, result):
    """The slack mutant's counterexample with a tachometer error of 0.7, not a double (the solver's values are
    dyadic): the false alarm does not depend on it, the interval's ends do. ``(prop, trace, its replay)``."""
    trace = dataclasses.replace(result.trace, params={**result.trace.params, "tacho_error": Fraction(7, 10)})
    with patched(*SLACK_MUTANT):
        trace = dataclasses.replace(trace, states=replay(prop, trace).states)
        return prop, trace, reproduce(prop, trace)  # still a counterexample of the mutant


class TestFloatReplay:
    def test_dyadic_trace_agrees_everywhere(self, latch):
        mutant, result = latch
        floats = float_replay(mutant, result.trace, result.replay)
        assert not floats.diverged and floats.largest == {} and floats.steps == len(result.trace.inputs)
        assert floats.float_first_violation == result.k

    def test_boundary_trace_diverges_on_a_boolean(self, latch):
        mutant, result = latch
        trace = _boundary_trace(mutant, result)
        floats = float_replay(mutant, trace, replay(mutant, trace))
        assert floats.diverged
        d = floats.first_boolean
        assert (d.step, d.field, d.exact, d.float) == (0, "outputs.warning", True, False)

    def test_smoothed_closed_loop_counterexample_on_a_boundary(self):
        """A real trace: the coarse closed loop (tests/model/test_closed_loop.py) with the max safe front taken without
        the odometry error. Its smoothed counterexample has the max safe front exactly on the EBI at step 0: no
        EB exactly, EB in doubles. The exact replay reproduces the violation; the float run diverges there."""
        from atcs.model import closed_loop
        from atcs.model.train_data import seed000_train, subset026_national
        from atcs.properties.closed_loop import closed_loop_properties, preset_data

        coarse = preset_data(
            dataclasses.replace(seed000_train(), t_be_s=Fraction(8, 5)), subset026_national(), cycle_s=Fraction(4, 5)
        )
        prop = next(p for p in closed_loop_properties("coarse", coarse) if p.name == "closed_loop.no_overrun_coarse")
        prop = dataclasses.replace(prop, lemmas=())
        fault = (closed_loop.max_safe_front_m, "i.measured_front_m + p.position_error_m", "i.measured_front_m")
        with patched(*fault):
            result = prove(prop, timeout_s=300, max_k=12, smooth_cex=True)
            assert result.status == "falsified" and result.smoothing.status == "minimal"
            exact = reproduce(prop, result.trace)
            floats = float_replay(prop, result.trace, exact)
        d = floats.first_boolean
        assert (d.step, d.field, d.exact, d.float) == (0, "next_state.eb_latched", False, True)
        assert not exact.states[1]["eb_latched"]

    def test_largest_difference_per_field(self, false_alarm):
        prop, trace, run = _non_dyadic(*false_alarm[:2])
        with patched(*SLACK_MUTANT):
            floats = float_replay(prop, trace, run)
        assert floats.largest
        for name, d in floats.largest.items():
            assert floats.gap(name) == abs(Fraction(d.float) - d.exact) > 0
            role, field = name.split(".", 1)
            records = [flatten(r) for r in (run.states[1:] if role == "next_state" else run.outputs)]
            assert records[d.step][field] == d.exact

    def test_cli_exit_0_when_floats_agree(self, latch, registered, tmp_path, capsys):
        mutant, result = latch
        registered(mutant)
        path = tmp_path / "cex.json"
        path.write_text(json.dumps(to_json(result.trace, result.replay)))
        assert main(["replay", str(path)]) == 0
        assert "the float run agrees with the exact run on every boolean" in capsys.readouterr().out

    def test_cli_exit_4_when_floats_diverge(self, latch, registered, tmp_path, capsys):
        mutant, result = latch
        registered(mutant)
        trace = _boundary_trace(mutant, result)
        path = tmp_path / "cex.json"
        path.write_text(json.dumps(to_json(trace, replay(mutant, trace))))
        assert main(["replay", str(path)]) == 4
        out = " ".join(capsys.readouterr().out.split())
        assert "violated at step 0" in out
        assert (
            "the float run diverges: a boolean differs first at step 0, outputs.warning: exact True, float False" in out
        )

    def test_cli_shows_decimals_beside_the_exact_values(self, latch, registered, tmp_path, capsys):
        mutant, result = latch
        registered(mutant)
        trace = _boundary_trace(mutant, result)
        path = tmp_path / "cex.json"
        path.write_text(json.dumps(to_json(trace, replay(mutant, trace))))
        main(["replay", str(path)])
        out = capsys.readouterr().out
        assert "0.1 (0.099999999999999999999999999999)" in out  # 0.1 - 1e-30: rounded, then exact
        assert " 0.1 │" in out  # exactly 0.1: no exact value beside it

    def test_a_narrow_table_folds_long_values_never_cuts_them(self, latch):
        mutant, result = latch
        trace = _boundary_trace(mutant, result)
        console = Console(file=io.StringIO(), width=40)
        _print_exact(console, mutant, trace, replay(mutant, trace), "cex.json")
        out = console.file.getvalue()
        assert "…" not in out
        column = "".join(line.split("│")[2].strip() for line in out.splitlines() if line.startswith("│"))
        assert "0.1(0.099999999999999999999999999999)" in column  # the step's column, its lines joined

    def test_cli_shows_the_largest_differences(self, false_alarm, registered, tmp_path, capsys):
        prop, trace, run = _non_dyadic(*false_alarm[:2])
        registered(dataclasses.replace(prop, name="mutant.no_false_alarm"))
        with patched(*SLACK_MUTANT):
            floats = float_replay(prop, trace, run)
            path = tmp_path / "cex.json"
            path.write_text(json.dumps(dict(to_json(trace, run), property="mutant.no_false_alarm")))
            assert main(["replay", str(path)]) == 0
        out = capsys.readouterr().out
        assert floats.largest and not floats.diverged
        assert "the largest difference per field" in out
        for name in floats.largest:
            assert name in out
        assert "the float run agrees with the exact run on every boolean over 2 steps" in out


def fewer_changes_exist(prop: Property, k: int, bound: int) -> str:
    """A solver of the test's own, not smoothing's: is there a run violating ``prop`` first at step ``k`` with at
    most ``bound`` input changes? (z3's default solver; the changes a sum of 0/1 terms.)"""
    with fresh_context():
        u = Unrolling(prop)
        solver = z3.Solver(ctx=u.init().ctx)
        solver.add(u.init())
        changes = []
        for j in range(k + 1):
            f = u.frame(j)
            solver.add(f.trans, f.assumed, z3.Not(f.prop) if j == k else f.prop)
            if j:
                before, now = flatten(as_dict(u.frame(j - 1).inputs)), flatten(as_dict(f.inputs))
                changes += [z3.If(unwrap(now[n]) == unwrap(before[n]), 0, 1) for n in now]
        solver.add(z3.Sum(changes) <= bound)
        return str(solver.check())


class TestSmoothing:
    def test_no_more_changes_and_replays_exactly(self, false_alarm):
        prop, plain, smoothed = false_alarm
        assert smoothed.k == plain.k
        s = smoothed.smoothing
        # BMC's own run changes more inputs (how many depends on z3's model); the least is 2 (the next test)
        assert s.original_changes == input_changes(plain.trace) > 2
        assert s.changes == input_changes(smoothed.trace) == 2
        assert s.status == "minimal"
        assert f"smoothed: {s.original_changes} -> 2 input changes (minimal)" in smoothed.message
        with patched(*SLACK_MUTANT):
            assert reproduce(prop, smoothed.trace).first_violation == smoothed.k
        assert plain.smoothing is None

    def test_minimal_by_a_direct_solver_check(self, false_alarm):
        prop, _, smoothed = false_alarm
        with patched(*SLACK_MUTANT):
            assert fewer_changes_exist(prop, smoothed.k, smoothed.smoothing.changes) == "sat"
            assert fewer_changes_exist(prop, smoothed.k, smoothed.smoothing.changes - 1) == "unsat"

    def test_many_changes_smoothed_away(self):
        """The resource manager that forgets the holder: BMC's run changes its inputs at every step; a run with
        constant inputs violates the property as well."""
        prop = PROPERTIES["resources.manager_records_holder"]
        fault = ("o.ite(releases, code(RELEASING), after_reply)", "o.ite(releases, code(HELD), after_reply)")
        mutant = dataclasses.replace(mutant_property(prop, *fault), lemmas=())
        plain = prove(mutant, timeout_s=120, max_k=8)
        smoothed = prove(mutant, timeout_s=120, max_k=8, smooth_cex=True)
        assert plain.status == smoothed.status == "falsified" and plain.k == smoothed.k
        assert smoothed.smoothing.changes <= smoothed.smoothing.original_changes == input_changes(plain.trace)
        assert input_changes(smoothed.trace) == smoothed.smoothing.changes
        assert smoothed.smoothing.status == "minimal"

    def test_unknown_keeps_the_original_and_says_so(self, false_alarm, monkeypatch):
        prop, _, _ = false_alarm
        monkeypatch.setattr(smoothing_module, "solve", lambda *a, **k: Check("unknown", reason="timeout"))
        with patched(*SLACK_MUTANT):
            result = prove(prop, timeout_s=120, max_k=6, smooth_cex=True)
        assert result.status == "falsified"
        assert result.smoothing.status == "not minimal"
        assert result.smoothing.changes == result.smoothing.original_changes == input_changes(result.trace)
        assert "the solver said timeout" in result.smoothing.message and "not minimal" in result.message

    def test_no_time_left_keeps_the_original(self, false_alarm):
        prop, plain, _ = false_alarm
        with fresh_context():
            u = Unrolling(prop)
            with patched(*SLACK_MUTANT):
                bmc = Bmc(u)
                check = next(c for c in (bmc.check(k, 60) for k in range(plain.k + 1)) if c.result == "sat")
                model, s = smoothing_module.smooth(u, bmc.solver, plain.k, check.model, 0)
        assert model is check.model and s.status == "not minimal" and "time ran out" in s.message

    def test_cli_records_the_changes(self, false_alarm, registered, tmp_path):
        prop, plain, _ = false_alarm
        registered(dataclasses.replace(prop, name="mutant.no_false_alarm"))
        report, cex = tmp_path / "r.json", tmp_path / "cex"
        with patched(*SLACK_MUTANT):
            assert main(["prove", "--only", "mutant.*", "--smooth", "--json", str(report), "--cex-dir", str(cex)]) == 1
        (record,) = json.loads(report.read_text())["properties"]
        assert record["input_changes"] == 2
        assert record["smoothing"] == {
            "status": "minimal",
            "original_input_changes": input_changes(plain.trace),
            "input_changes": 2,
            "message": "",
        }
        doc = json.loads((cex / "mutant.no_false_alarm.json").read_text())
        assert doc["input_changes"] == 2 and doc["smoothing"]["status"] == "minimal"
        for suffix in (".csv", ".vcd", ".png"):
            assert (cex / f"mutant.no_false_alarm{suffix}").exists()

    def test_without_smooth_the_changes_are_still_recorded(self, latch, registered, tmp_path):
        mutant, result = latch
        registered(mutant)
        report = tmp_path / "r.json"
        assert main(["prove", "--only", "mutant.*", "--json", str(report), "--cex-dir", str(tmp_path / "c")]) == 1
        (record,) = json.loads(report.read_text())["properties"]
        assert record["input_changes"] == input_changes(result.trace) and record["smoothing"] is None
