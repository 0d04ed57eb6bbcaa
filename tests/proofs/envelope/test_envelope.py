"""Ranges of train data (docs/configuration.md "Ranges of train data"): the cells and their split, the ranges read
and refused naming the field and the value, the proofs made for a cell, the refinement into a map (a property
falsified by a mutant in every cell, each counterexample replayed exactly), and ``atcs prove --config --map``."""

import json
import textwrap
from fractions import Fraction
from pathlib import Path

import pytest

from atcs.model import curves
from atcs.model.configuration import ConfigurationError, DataRange, load_configuration
from atcs.model.train_files import shipped_trains
from atcs.proofs.cex.trace import reproduce
from atcs.proofs.cli import main
from atcs.proofs.cli._common import EXIT_FALSIFIED, EXIT_OK, EXIT_USAGE
from atcs.proofs.envelope import split, sweep, whole_range
from atcs.proofs.envelope.executors import local_executor
from atcs.proofs.envelope.sweep import cell_proofs, envelope_properties
from atcs.proofs.mutation.mutants import patched
from atcs.properties.envelope import Cell, cell_families

RANGES = """
emergency_deceleration_scale = { min = 0.8, max = 1.2, resolution = 0.2 }
t_be_s = { min = 2, max = 3, resolution = 0.5 }
"""

CONFIG = """
name = "envelope"

[[trains]]
file = "{train}"

[trains.ranges]
{ranges}

[[lines]]
name = "design"
length_m = 2000
speed_limits = [{{ start_m = 0, kmh = 160 }}]
gradients = [{{ start_m = 0, permille = -40 }}, {{ start_m = 1000, permille = 40 }}]
"""

SPACING = "curves.spacing_gamma_passenger_p_design_0"


def _write(tmp_path, ranges=RANGES):
    path = tmp_path / "c.toml"
    path.write_text(CONFIG.format(train=shipped_trains()["gamma_passenger_P"], ranges=ranges), encoding="utf-8")
    return path


def _range(field, low, high, resolution):
    return DataRange(field, Fraction(low), Fraction(high), Fraction(resolution))


class TestCells:
    def test_the_whole_range_is_one_cell(self):
        ranges = (_range("t_be_s", 1, 3, "0.5"),)
        assert whole_range(ranges) == Cell((("t_be_s", 1, 3),))

    def test_a_cell_splits_along_its_field_of_most_steps_on_the_grid(self):
        ranges = (_range("t_be_s", 1, 3, "0.5"), _range("v_ura_mps", 0, 1, "0.5"))
        first, second = split(whole_range(ranges), ranges)
        assert first.bounds[0] == ("t_be_s", 1, 2) and second.bounds[0] == ("t_be_s", 2, 3)
        assert first.bounds[1] == second.bounds[1] == ("v_ura_mps", 0, 1)

    def test_a_range_not_a_multiple_of_its_resolution_keeps_the_grid_and_its_end(self):
        ranges = (_range("t_be_s", 0, "1.25", "0.5"),)
        first, second = split(whole_range(ranges), ranges)
        assert (first.bounds[0][1:], second.bounds[0][1:]) == ((0, Fraction(1, 2)), (Fraction(1, 2), Fraction(5, 4)))
        low, high = split(second, ranges)
        assert (low.bounds[0][1:], high.bounds[0][1:]) == ((Fraction(1, 2), 1), (1, Fraction(5, 4)))
        assert split(high, ranges) is None  # 1 to 1.25 is within one step

    def test_no_split_at_the_resolution(self):
        ranges = (_range("t_be_s", 1, "1.5", "0.5"),)
        assert split(whole_range(ranges), ranges) is None


class TestReading:
    def test_ranges_are_read_in_order(self, tmp_path):
        (t,) = load_configuration(_write(tmp_path)).trains
        assert [r.field for r in t.ranges] == ["emergency_deceleration_scale", "t_be_s"]
        assert t.ranges[1] == _range("t_be_s", 2, 3, "0.5")

    @pytest.mark.parametrize(
        ("ranges", "message"),
        [
            ("t_ba_s = { min = 1, max = 2, resolution = 1 }", "trains[0].ranges.t_ba_s: unknown field"),
            ("t_be_s = { min = 2, max = 2, resolution = 1 }", "trains[0].ranges.t_be_s.max = 2 must be above min"),
            ("t_be_s = { min = 2, max = 3, resolution = 2 }", "ranges.t_be_s.resolution = 2 must be at most max - min"),
            ("t_be_s = { min = 2, max = 3, resolution = 0.001 }", "resolution = 0.001 splits the range into more than"),
            ("t_be_s = { min = -1, max = 3, resolution = 1 }", "trains[0].ranges.t_be_s.min = -1 must be at least 0"),
            ("t_be_s = { min = 1, max = 300, resolution = 5 }", "trains[0].ranges.t_be_s.max = 300 makes the train"),
            ("t_be_s = { min = 1, max = 3 }", "trains[0].ranges.t_be_s.resolution is missing"),
            ("t_be_s = 2", "trains[0].ranges.t_be_s must be a table, got 2"),
            ("t_be_s = { min = 1, max = 3, resolution = 1, step = 1 }", "ranges.t_be_s.step: unknown field"),
        ],
    )
    def test_a_bad_range_is_refused_naming_the_field_and_value(self, tmp_path, ranges, message):
        with pytest.raises(ConfigurationError, match=None) as caught:
            load_configuration(_write(tmp_path, ranges))
        assert message in str(caught.value) and str(tmp_path / "c.toml") in str(caught.value)


class TestCellProofs:
    def test_the_cells_fields_are_symbolic_within_their_intervals(self, tmp_path):
        config = load_configuration(_write(tmp_path))
        t, line = config.trains[0], config.lines[0]
        cell = whole_range(t.ranges)
        ((prop, registry),) = cell_proofs(config, SPACING, cell)
        assert "t_be_s" not in prop.fixed_params and "emergency_decelerations_mps2" not in prop.fixed_params
        assert {a.name for a in prop.assumptions} >= {"range_t_be_s", "range_emergency_deceleration_scale"}
        assert prop.name.endswith(f"_c{cell.id}_0") and prop.name in registry
        curves_family, _ = cell_families(config, t, line, cell)
        assert all("t_be_s" not in p.fixed_params for p in curves_family)

    def test_the_closed_loop_is_made_for_each_whole_cycle_rounding(self, tmp_path):
        config = load_configuration(_write(tmp_path))
        t, line = config.trains[0], config.lines[0]
        cell = Cell((("emergency_deceleration_scale", 1, Fraction(6, 5)), ("t_be_s", Fraction(2), Fraction(21, 10))))
        _, loops = cell_families(config, t, line, cell)
        assert [family[0].fixed_params["t_be_s"] for family in loops] == [2, Fraction(21, 10)]
        assert [family[0].fixed_params["brake_build_up_cycles"] for family in loops] == [19, 20]
        name = next(n for n in envelope_properties(config) if n.startswith("closed_loop.no_overrun"))
        proofs = cell_proofs(config, name, cell)
        assert len(proofs) == 2
        assert all(p.lemmas and set(p.lemmas) <= set(registry) for p, registry in proofs)

    def test_a_windows_reach_is_proved_for_every_value_of_the_cell(self, tmp_path):
        """CL-07's speed cap is computed from the node's parameters, so a range of V_ura moves it in the proof."""
        text = CONFIG.format(train=shipped_trains()["gamma_passenger_P"], ranges=RANGES)
        text = text.replace("length_m = 2000", "length_m = 8000").replace("start_m = 1000", "start_m = 4000")
        text = text.replace(
            "t_be_s = { min = 2, max = 3, resolution = 0.5 }", "v_ura_mps = { min = 0, max = 2, resolution = 1 }"
        )
        path = tmp_path / "long.toml"
        path.write_text(text, encoding="utf-8")
        config = load_configuration(path)
        name = next(n for n in envelope_properties(config) if n.startswith("closed_loop.window_reach"))
        ((prop, _),) = cell_proofs(config, name, whole_range(config.trains[0].ranges))
        assert {"range_v_ura_mps", "range_emergency_deceleration_scale"} <= {a.name for a in prop.assumptions}
        with local_executor(1) as tasks:
            maps = sweep(str(path), [name], timeout_s=300, executor=tasks)
        assert maps[name].status == "proved", maps[name].describe()


class TestSweep:
    def test_a_property_proved_over_the_whole_range_is_one_cell(self, tmp_path):
        path = str(_write(tmp_path))
        with local_executor(1) as tasks:
            maps = sweep(path, [SPACING], timeout_s=120, executor=tasks)
        assert maps[SPACING].status == "proved"
        assert [c.cell for c in maps[SPACING].cells] == [whole_range(load_configuration(path).trains[0].ranges)]

    def test_a_mutant_falsifies_every_cell_down_to_the_resolution_each_replayed(self, tmp_path):
        path = str(_write(tmp_path))
        with patched(curves.curves_from_ebd_and_ebi, "permitted - speed_mps * n.t_indication_s", "permitted"):
            with local_executor(1) as tasks:
                maps = sweep(path, [SPACING], timeout_s=120, executor=tasks)
            cells = maps[SPACING].cells
            assert maps[SPACING].status == "falsified"
            assert len(cells) == 4 and {c.status for c in cells} == {"falsified"}  # 2 x 2 at the resolution
            config = load_configuration(path)
            for c in cells:
                failing = c.failing
                prop = next(p for p, _ in cell_proofs(config, SPACING, c.cell) if p.name == failing.name)
                assert reproduce(prop, failing.trace).first_violation == failing.k
                for field, low, high in c.cell.bounds:  # the counterexample lies in its cell
                    if field == "t_be_s":
                        assert low <= failing.trace.params["t_be_s"] <= high


class TestCommand:
    def test_prove_with_a_map_writes_the_json_and_the_slice(self, tmp_path, capsys):
        path = _write(tmp_path)
        argv = ["prove", "--config", str(path), "--only", SPACING, "--map", str(tmp_path / "map")]
        assert main([*argv, "--json", str(tmp_path / "r.json"), "--jobs", "2"]) == EXIT_OK
        doc = json.loads((tmp_path / "map" / "map.json").read_text())
        (entry,) = doc["envelopes"]
        assert entry["name"] == SPACING and entry["status"] == "proved" and len(entry["cells"]) == 1
        expected = {"min": "2", "max": "3", "min_float": 2.0, "max_float": 3.0, "resolution": "1/2"}
        assert entry["ranges"]["t_be_s"] == expected
        assert json.loads((tmp_path / "r.json").read_text())["envelopes"] == doc["envelopes"]
        assert (tmp_path / "map" / "gamma_passenger_P.emergency_deceleration_scale.t_be_s.png").stat().st_size > 0
        assert f"envelope {SPACING}: proved (1 cells: 1 proved)" in capsys.readouterr().out

    def test_a_falsified_cell_makes_the_run_falsified_with_its_counterexample(self, tmp_path, capsys):
        path = _write(tmp_path, "t_be_s = { min = 2, max = 3, resolution = 1 }")
        argv = ["prove", "--config", str(path), "--only", SPACING, "--cex-dir", str(tmp_path / "cex")]
        with patched(curves.curves_from_ebd_and_ebi, "permitted - speed_mps * n.t_indication_s", "permitted"):
            assert main([*argv, "--json", str(tmp_path / "r.json")]) == EXIT_FALSIFIED
        (entry,) = json.loads((tmp_path / "r.json").read_text())["envelopes"]
        (cell,) = entry["cells"]
        assert cell["status"] == "falsified" and cell["counterexample"].endswith(".json")
        assert json.loads(Path(cell["counterexample"]).read_text())["requirement"] == "CRV-06"

    @pytest.mark.parametrize("option", [["--map", "m"], ["--ray", "auto"]])
    def test_map_and_ray_need_a_configuration_with_ranges(self, tmp_path, capsys, option):
        assert main(["prove", "--only", "curves.spacing_seed000", *option]) == EXIT_USAGE
        assert "needs --config" in capsys.readouterr().err
        path = tmp_path / "s.toml"
        path.write_text(textwrap.dedent(CONFIG.format(train=shipped_trains()["gamma_passenger_P"], ranges="")))
        assert main(["prove", "--config", str(path), "--only", SPACING, *option]) == EXIT_USAGE
        assert "gives no train a range of train data" in capsys.readouterr().err


def test_a_second_run_reuses_the_cells_proofs_from_the_cache(tmp_path, capsys):
    path = _write(tmp_path)
    argv = ["prove", "--config", str(path), "--only", SPACING, "--cache", str(tmp_path / "cache")]
    assert main([*argv, "--json", str(tmp_path / "a.json")]) == EXIT_OK
    assert "reused" not in capsys.readouterr().out
    assert main([*argv, "--json", str(tmp_path / "b.json")]) == EXIT_OK
    assert f"reused proved cell proofs from {tmp_path / 'cache'}: {SPACING} [" in capsys.readouterr().out
    (entry,) = json.loads((tmp_path / "b.json").read_text())["envelopes"]
    assert [c["reused"] for c in entry["cells"]] == [1]
