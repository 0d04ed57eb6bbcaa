"""No command prints a traceback: an internal error is one line and exit 70, an interruption exit 130, and the
reported crashes (certify into a new directory, vectors of a property that cannot be built, headway at a speed
it cannot run at) each give a proper answer. ``atcs --version`` and ``atcs bench --help``."""

import dataclasses
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from atcs.proofs.cli import main
from atcs.proofs.cli._common import EXIT_INTERNAL, EXIT_INTERRUPTED, EXIT_UNKNOWN, EXIT_USAGE
from atcs.properties import PROPERTIES


def _raising(exc: BaseException):
    def run(args, out, err):
        raise exc

    return run


def one_line(capsys, prefix: str) -> str:
    """The one error line on stderr (beside the progress lines a log gets, which never start ``atcs:``)."""
    err = capsys.readouterr().err
    assert "Traceback" not in err, err
    (line,) = [line for line in err.splitlines() if line.startswith("atcs:")]
    assert line.startswith(prefix), err
    return line


class TestInternalError:
    def test_is_one_line_and_exit_70(self, monkeypatch, capsys):
        monkeypatch.delenv("ATCS_TRACEBACK", raising=False)
        monkeypatch.setattr("atcs.proofs.cli.bench.run", _raising(RuntimeError("the cache is gone\nsecond line")))
        assert main(["bench", "supervision"]) == EXIT_INTERNAL == 70
        err = one_line(capsys, "atcs: internal error: ")
        assert err == "atcs: internal error: bench: RuntimeError: the cache is gone second line (please report this)"

    def test_names_the_subcommand(self, monkeypatch, capsys):
        monkeypatch.delenv("ATCS_TRACEBACK", raising=False)
        monkeypatch.setattr("atcs.proofs.cli.vectors.verify", _raising(KeyError("x")))
        assert main(["vectors", "verify", "somewhere"]) == 70
        assert one_line(capsys, "atcs: internal error: vectors verify: KeyError: 'x' (please report this)")

    def test_atcs_traceback_reraises(self, monkeypatch):
        monkeypatch.setenv("ATCS_TRACEBACK", "1")
        monkeypatch.setattr("atcs.proofs.cli.bench.run", _raising(RuntimeError("boom")))
        with pytest.raises(RuntimeError, match="boom"):
            main(["bench"])

    def test_input_errors_stay_exit_2(self, capsys):
        assert main(["bench", "nosuch"]) == EXIT_USAGE
        one_line(capsys, "atcs: error: bench: unknown benchmark 'nosuch'")


def test_interrupted_is_one_line_and_exit_130(monkeypatch, capsys):
    monkeypatch.delenv("ATCS_TRACEBACK", raising=False)
    monkeypatch.setattr("atcs.proofs.cli.bench.run", _raising(KeyboardInterrupt()))
    assert main(["bench"]) == EXIT_INTERRUPTED == 130
    assert one_line(capsys, "atcs: interrupted") == "atcs: interrupted"


def test_certify_creates_a_new_directory_when_nothing_is_proved(tmp_path, capsys):
    report = tmp_path / "prove.json"
    report.write_text(
        json.dumps({"properties": [{"name": "supervision.eb_above_ebi", "status": "unknown", "k": None}]})
    )
    directory = tmp_path / "not" / "yet"
    code = main(["certify", "--only", "supervision.eb_above_ebi", "--report", str(report), "--dir", str(directory)])
    assert code == EXIT_UNKNOWN
    assert "Traceback" not in capsys.readouterr().err
    (record,) = json.loads((directory / "certificates.json").read_text())["properties"]
    assert record["status"] == "not proved"


def _branching_holds(o, p, s, i, out, nxt):
    """The EB property written with a Python ``if`` on a model value: fine on floats, not on z3 terms."""
    return out.emergency_brake if i.speed_mps > i.ebi_mps else True


@pytest.fixture
def unbuildable_property(monkeypatch):
    prop = dataclasses.replace(
        PROPERTIES["supervision.eb_above_ebi"], name="supervision.eb_above_ebi_branching", holds=_branching_holds
    )
    monkeypatch.setitem(PROPERTIES, prop.name, prop)
    return prop


class TestVectorsOfWhatCannotBeBuilt:
    def test_a_property_is_an_unknown_goal_and_one_line(self, tmp_path, unbuildable_property, capsys):
        out = tmp_path / "vectors"
        assert main(["vectors", "generate", "--function", "supervision", "--out", str(out)]) == EXIT_UNKNOWN
        err = one_line(capsys, "atcs: vectors generate: supervision: supervision.eb_above_ebi_branching: ")
        assert "could not be built: SymbolicValueError" in err and "test_errors.py" in err
        goals = json.loads((out / "supervision.json").read_text())["goals"]
        (goal,) = [g for g in goals if "branching" in g["id"]]
        assert goal["id"] == "SUP-01 supervision.eb_above_ebi_branching (not built)"
        assert goal["status"] == "unknown" and "SymbolicValueError" in goal["reason"]
        others = [g for g in goals if g is not goal]
        assert others and all(g["status"] != "unknown" for g in others)  # the other properties' goals are settled

    def test_a_step_gives_no_file_and_one_line(self, tmp_path, monkeypatch, capsys):
        from atcs.model.ops.symbolic import SymbolicValueError

        def frame(node, props):
            raise SymbolicValueError("no truth value")

        monkeypatch.setattr("atcs.proofs.vectors.generate.StepFrame", frame)
        out = tmp_path / "vectors"
        assert main(["vectors", "generate", "--function", "ceiling_offset", "--out", str(out)]) == EXIT_UNKNOWN
        err = one_line(capsys, "atcs: vectors generate: ceiling_offset: the step could not be built on z3 terms: ")
        assert "SymbolicValueError: no truth value" in err
        assert not (out / "ceiling_offset.json").exists()


@pytest.mark.parametrize("speed", ["351", "350.5", "600", "64.9", "40", "0", "-80"])
def test_headway_refuses_a_speed_it_cannot_run_at(speed, capsys):
    assert main(["headway", "--speed", speed]) == EXIT_USAGE
    one_line(capsys, f"atcs: error: headway: --speed = '{speed}' is outside the supported range, 65 to 350 km/h")


def test_version_prints_one_line_per_tool():
    from atcs.proofs.vectors.files import model_sha256

    script = Path(sys.executable).parent / "atcs"
    done = subprocess.run([str(script), "--version"], capture_output=True, text=True, check=False)
    assert done.returncode == 0 and not done.stderr, done.stderr
    lines = done.stdout.splitlines()
    assert [line.split(" ")[0] for line in lines] == ["atcs", "Python", "z3", "cvc5", "model"]
    assert all(re.fullmatch(r"\S+ \d+\.\d+\S*", line) for line in lines[:4]), lines
    assert lines[4] == f"model sha256 {model_sha256()}"


def test_bench_help_lists_every_benchmark_with_its_summary(capsys):
    from atcs.proofs.bench import BENCHMARKS, summary

    with pytest.raises(SystemExit) as exit_:
        main(["bench", "--help"])
    assert exit_.value.code == 0
    out = capsys.readouterr().out
    assert list(BENCHMARKS) == ["supervision", "mrsp", "cycle", "sim", "sweep"]
    for name in BENCHMARKS:
        assert re.search(rf"^  {name} +{re.escape(summary(name))}$", out, re.MULTILINE), out
