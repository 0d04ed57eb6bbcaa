"""The `atcs` command line: prove, replay and bench; exit codes, reports, and bad input."""

import json
import os
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from atcs.model.supervision import supervise
from atcs.proofs.cli import main
from atcs.proofs.mutation.mutants import mutant_property
from atcs.properties import PROPERTIES

LATCH = "supervision.eb_latched_until_standstill"


@pytest.fixture
def latch_mutant_registered(monkeypatch):
    """Register a mutant of the EB latch (releases without standstill) under a name of its own."""
    mutant = mutant_property(
        PROPERTIES[LATCH], "eb_released = o.and_(standstill, eb_release)", "eb_released = eb_release", helper=supervise
    )
    import dataclasses

    mutant = dataclasses.replace(mutant, name="mutant.eb_latch_without_standstill")
    monkeypatch.setitem(PROPERTIES, mutant.name, mutant)
    return mutant


def one_line_error(capsys, *expected):
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0, err
    assert err.startswith("atcs: error:"), err
    for text in expected:
        assert text in err, err


class TestProve:
    def test_all_proved_exit_0_with_reports(self, proof_suite_run):
        run = proof_suite_run  # atcs prove --jobs 2 --json --junit --cex-dir, once per session (conftest.py)
        assert run.code == 0
        doc = run.doc
        names = [p["name"] for p in doc["properties"]]
        assert names == list(PROPERTIES)
        for p in doc["properties"]:
            assert {"name", "requirement", "status", "engine", "k", "seconds", "counterexample"} <= set(p)
            assert p["status"] == "proved" and p["engine"] == "k-induction" and p["counterexample"] is None
        cases = ET.parse(run.junit).getroot().findall("./testsuite/testcase")
        assert [c.get("name") for c in cases] == names
        assert not any(c.find("failure") is not None or c.find("error") is not None for c in cases)
        assert not run.cex.exists()
        assert "supervision.eb_latched_until_standstill" in run.stdout

    def test_only_selects_by_glob(self, tmp_path):
        report = tmp_path / "r.json"
        assert main(["prove", "--only", "supervision.eb_*", "--json", str(report)]) == 0
        names = [p["name"] for p in json.loads(report.read_text())["properties"]]
        assert names == [
            "supervision.eb_above_ebi",
            "supervision.eb_latched_until_standstill",
            "supervision.eb_without_position",
        ]
        umask = os.umask(0)
        os.umask(umask)
        assert report.stat().st_mode & 0o777 == 0o666 & ~umask  # an ordinary file, not a private temporary

    def test_only_repeated_selects_every_match_in_registry_order(self, tmp_path):
        report = tmp_path / "r.json"
        assert (
            main(
                [
                    "prove",
                    "--only",
                    "supervision.eb_without_position",
                    "--only",
                    "supervision.eb_above_ebi",
                    "--json",
                    str(report),
                ]
            )
            == 0
        )
        names = [p["name"] for p in json.loads(report.read_text())["properties"]]
        assert names == ["supervision.eb_above_ebi", "supervision.eb_without_position"]

    def test_one_job_gives_the_same_verdicts(self, tmp_path, proof_suite_run):
        """One process (lemma results shared in it) against the session's two workers, on the properties with
        lemmas that prove in seconds."""
        report = tmp_path / "r.json"
        assert main(["prove", "--jobs", "1", "--only", "resources.*", "--json", str(report)]) == 0
        records = json.loads(report.read_text())["properties"]
        assert [p["name"] for p in records] == [name for name in PROPERTIES if name.startswith("resources.")]
        assert {p["name"]: (p["status"], p["k"]) for p in records} == {
            p["name"]: (proof_suite_run.by_name[p["name"]]["status"], proof_suite_run.by_name[p["name"]]["k"])
            for p in records
        }

    def test_falsified_exit_1_writes_replayable_counterexample(self, tmp_path, latch_mutant_registered, capsys):
        report, junit, cex = tmp_path / "r.json", tmp_path / "r.xml", tmp_path / "cex"
        code = main(
            ["prove", "--only", "mutant.*", "--json", str(report), "--junit", str(junit), "--cex-dir", str(cex)]
        )
        assert code == 1
        (record,) = json.loads(report.read_text())["properties"]
        assert record["status"] == "falsified" and record["engine"] == "bmc"
        path = cex / "mutant.eb_latch_without_standstill.json"
        assert record["counterexample"] == str(path)
        assert (cex / "mutant.eb_latch_without_standstill.csv").read_text().startswith("step,param.")
        (case,) = ET.parse(junit).getroot().findall("./testsuite/testcase")
        assert case.find("failure").get("type") == "falsified"
        capsys.readouterr()
        # the counterexample replays through the command line
        assert main(["replay", str(path)]) == 0
        out = capsys.readouterr().out
        assert f"{record['k']} VIOLATED" in out and f"violated at step {record['k']}" in out

    def test_unknown_exit_3(self, tmp_path, monkeypatch):
        import dataclasses

        slow = dataclasses.replace(PROPERTIES["supervision.eb_above_ebi"], name="slow.needs_more_time")
        monkeypatch.setitem(PROPERTIES, slow.name, slow)
        monkeypatch.setattr("atcs.proofs.engine.prove._Deadline.remaining", _always_timeout)
        report = tmp_path / "r.json"
        assert main(["prove", "--only", "slow.*", "--json", str(report)]) == 3
        (record,) = json.loads(report.read_text())["properties"]
        assert record["status"] == "unknown" and "timeout" in record["message"]

    @pytest.mark.parametrize(
        ("argv", "expected"),
        [
            (["prove", "--only", "nosuch.*"], "matches no property"),
            (["prove", "--only", "supervision.*", "--only", "nosuch.*"], "--only 'nosuch.*' matches no property"),
            (["prove", "--json", "/nonexistent-dir/r.json"], "--json /nonexistent-dir/r.json: directory"),
            (["prove", "--junit", "/"], "--junit /: is a directory"),
            (["prove", "--cex-dir", "/etc/hostname/cex"], "--cex-dir"),
            (["prove", "--timeout", "0"], "--timeout: must be a positive number"),
            (["prove", "--timeout", "soon"], "--timeout: must be a number"),
            (["prove", "--jobs", "0"], "--jobs: must be at least 1"),
            (["prove", "--frobnicate"], "unrecognized arguments"),
            (["bench", "nosuch"], "unknown benchmark 'nosuch'"),
            (["headway", "--speed", "x"], "headway: --speed = 'x' is not a number"),
            (["headway", "--speed", "0"], "headway: --speed = '0' is outside the supported range, 65 to 350 km/h"),
            ([], "required"),
        ],
    )
    def test_bad_input_one_line_exit_2(self, argv, expected, capsys):
        assert main(argv) == 2
        one_line_error(capsys, expected)

    def test_bad_output_path_is_reported_before_proving(self, tmp_path, capsys, monkeypatch):
        monkeypatch.setattr("atcs.proofs.engine.suite.run", _must_not_run)
        assert main(["prove", "--json", str(tmp_path / "missing" / "r.json")]) == 2
        one_line_error(capsys, "does not exist")


def _always_timeout(self):
    from atcs.proofs.engine.prove import _Timeout

    raise _Timeout


def _must_not_run(*args, **kwargs):
    raise AssertionError("proofs ran although the output path is bad")


class TestReplay:
    def test_trace_of_a_changed_model_exit_1(self, tmp_path, latch_mutant_registered, monkeypatch, capsys):
        cex = tmp_path / "cex"
        assert main(["prove", "--only", "mutant.*", "--cex-dir", str(cex)]) == 1
        # the model is "fixed": the same name now refers to the real latch
        monkeypatch.setitem(PROPERTIES, latch_mutant_registered.name, PROPERTIES[LATCH])
        capsys.readouterr()
        assert main(["replay", str(cex / "mutant.eb_latch_without_standstill.json")]) == 1
        out = capsys.readouterr().out
        assert "not a run of the current model" in out

    @pytest.mark.parametrize(
        ("content", "expected"),
        [
            ("{not json", "not JSON"),
            ("[]", "top level must be an object"),
            ('{"format": "other"}', "field 'format'"),
            ('{"format": "atcs-trace/1", "property": "nosuch.prop"}', "'nosuch.prop'"),
        ],
    )
    def test_malformed_trace_file_exit_2(self, tmp_path, content, expected, capsys):
        path = tmp_path / "bad.json"
        path.write_text(content)
        assert main(["replay", str(path)]) == 2
        one_line_error(capsys, f"{path}: ", expected)

    def test_missing_trace_file_exit_2(self, tmp_path, capsys):
        assert main(["replay", str(tmp_path / "none.json")]) == 2
        one_line_error(capsys, "cannot read")


class TestCurves:
    def test_writes_png_and_svg_and_the_inverse_query(self, tmp_path, capsys):
        out_dir = tmp_path / "plots"
        assert main(["curves", "--train", "seed002", "--out", str(out_dir), "--speed", "50"]) == 0
        assert (out_dir / "curves.png").read_bytes().startswith(b"\x89PNG")
        assert b"<svg" in (out_dir / "curves.svg").read_bytes()
        assert sorted(p.name for p in out_dir.iterdir()) == ["curves.png", "curves.svg"]  # no temporary left
        out = capsys.readouterr().out
        assert "where each curve reaches 50 km/h" in out and "1500 @ 0" in out

    @pytest.mark.parametrize(
        ("argv", "expected"),
        [
            (["--mrsp", "0:80,600x60"], "--mrsp: '600x60' is not START:VALUE"),
            (["--mrsp", "0:80,600:fast"], "--mrsp"),
            (["--gradient", "0:0,500:-400"], "--gradient"),
            (["--eoa", "-5"], "--eoa = -5 is out of range"),
            (["--front", "2000"], "--front = 2000 is out of range"),
            (["--a-est", "-1"], "--a-est = -1 is out of range"),
            (["--speed", "0"], "--speed = 0 is out of range"),
            (["--gradient", "0:-100"], "the train cannot stop"),
            (["--train", "seed999"], "is neither a preset (seed000, seed002) nor a .toml file"),
            (["--train", "missing.toml"], "--train missing.toml: cannot read the train data"),
        ],
    )
    def test_bad_input_one_line_exit_2(self, tmp_path, argv, expected, capsys):
        assert main(["curves", "--out", str(tmp_path), *argv]) == 2
        one_line_error(capsys, expected)
        assert not any(tmp_path.iterdir())  # nothing written


class TestBench:
    def test_supervision_benchmark_prints_ratios(self, capsys):
        assert main(["bench", "supervision"]) == 0
        out = capsys.readouterr().out
        assert "numpy batch" in out and "x" in out

    def test_mrsp_benchmark_checks_agreement_and_prints_ratios(self, capsys):
        assert main(["bench", "mrsp"]) == 0  # the benchmark asserts the five methods agree at every metre
        out = capsys.readouterr().out
        assert "incremental window update" in out and "per-metre arrays" in out and "/ incremental" in out
        assert "window update" in out.split("per-metre arrays, numpy")[1]  # the arrays' own window update too


def test_cycle_benchmark_checks_agreement_and_prints_ratios():
    from rich.console import Console

    from atcs.proofs.bench.cycle import bench_cycle

    console = Console(record=True, width=200)
    reported = []
    results = bench_cycle(
        console, cycles=5, segment_counts=(5, 20), prove_closed_loop=False, progress=lambda *at: reported.append(at)
    )
    assert results["agree"] == results["compared"] == 20  # EBI and SBI of 10 cycles; preprocessed == direct too
    assert reported == [(done, 10) for done in range(10)]  # `atcs bench` shows the time left from these
    timed = ("prepared", "direct", "per_metre", "prepare", "envelopes")
    assert all(results[f"{n}_{k}_s"] > 0 for n in (5, 20) for k in timed)
    text = console.export_text()
    assert "direct / preprocessed" in text and "per-metre arrays" in text and "tables per MA" in text
    assert "envelopes (µs)" in text


def test_sim_benchmark_prints_the_cost_per_fleet():
    from rich.console import Console

    from atcs.proofs.bench.sim import MODES, bench_sim, fleet_scenario

    console = Console(record=True, width=200)
    reported = []
    results = bench_sim(console, fleets=(2, 4), warm_up=5, cycles=10, progress=lambda *at: reported.append(at))
    assert reported[-1] == (15 * 6 * 2, 15 * 6 * 2) and len(reported) == 60  # a report a cycle, in train-cycles
    kinds = ("cycle_s", "cpu_s", "real_time_factor")
    assert set(results) == {f"{n}_trains_{mode}_{kind}" for n in (2, 4) for mode in MODES for kind in kinds}
    assert all(v > 0 for v in results.values())
    text = console.export_text()
    assert "real-time factor" in text and "traced" in text and "direct" in text
    fleet = fleet_scenario(100)
    assert [t.front_m for t in fleet.trains[:2]] == [40000, 39600] and fleet.trains[-1].front_m == 400
    with pytest.raises(ValueError, match="trains must be from 1 to 285, got 500"):
        fleet_scenario(500)


def test_console_script_is_installed():
    script = Path(sys.executable).parent / "atcs"
    done = subprocess.run(
        [str(script), "prove", "--only", "supervision.eb_above_ebi"], capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, done.stderr
    assert "proved" in done.stdout


def test_a_long_line_into_a_pipe_is_not_broken(monkeypatch, capsys):
    """A log or pipe reader (CI, ``grep FAIL``) gets each message on one line, however long it is."""
    import argparse

    import atcs.proofs.cli as cli

    line = "FAIL " + "x" * 300 + " expected false, got true"

    def parser():
        p = argparse.ArgumentParser()
        p.set_defaults(run=lambda args, out, err: out.print(line) or 0)
        return p

    monkeypatch.setattr(cli, "build_parser", parser)
    assert main([]) == 0
    assert capsys.readouterr().out == line + "\n"
