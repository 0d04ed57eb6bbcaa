"""Certified test vectors: coverage goals, generation, verification, checking an implementation."""

import json
import shutil
import sys
from pathlib import Path

import pytest
import z3

from atcs.model import NODES
from atcs.model.doors import DOOR_ENABLE
from atcs.model.supervision import SUPERVISION
from atcs.proofs.cli import main
from atcs.proofs.mutation.mutants import mutant_node
from atcs.proofs.vectors import files as vector_files
from atcs.proofs.vectors import verify as vector_verify
from atcs.proofs.vectors.files import read
from atcs.proofs.vectors.generate import Vector, expected, generate
from atcs.proofs.vectors.goals import StepFrame, boundaries, conditions, decisions
from atcs.properties import PROPERTIES

IMPL = Path(__file__).parent / "impl" / "supervision_impl.py"


def _props(node):
    return tuple(p for p in PROPERTIES.values() if p.node is node)


@pytest.fixture(scope="module")
def supervision_vectors():
    return generate(SUPERVISION, _props(SUPERVISION), timeout_s=30)


@pytest.fixture(scope="module")
def vector_dir(tmp_path_factory, supervision_vectors):
    """``atcs vectors generate --function supervision --function dcu``, written once for the module."""
    out = tmp_path_factory.mktemp("vectors")
    assert main(["vectors", "generate", "--function", "supervision", "--function", "dcu", "--out", str(out)]) == 0
    return out


@pytest.fixture
def fresh_dir(vector_dir, tmp_path):
    """A copy of the generated files a test may edit."""
    return Path(shutil.copytree(vector_dir, tmp_path / "v"))


class TestGoals:
    """Decisions, conditions and boundaries are read off the step's own z3 terms."""

    def test_conditions_are_the_atoms_under_and_or_not(self):
        x, y = z3.Reals("x y")
        b = z3.Bool("b")
        found = conditions(z3.Or(z3.And(x < y, b), z3.Not(x < y), y >= 2))
        assert [str(c) for c in found] == ["x < y", "b", "y >= 2"]

    def test_supervision_decisions(self):
        found = decisions(StepFrame(SUPERVISION))
        where = [d.where for d in found]
        assert where[0] == "next_state.eb_latched" and "next_state.sb_latched" in where
        eb = found[0]
        assert {str(c) for c in eb.conditions} >= {"speed_mps@v > ebi_mps@v", "eb_latched@v", "position_valid@v"}
        comparisons = [str(c) for c, _ in boundaries(found)]
        assert sorted(comparisons) == sorted(f"speed_mps@v > {n}_mps@v" for n in ("ebi", "sbi", "permitted", "warning"))

    def test_every_node_has_decisions(self):
        branch_free = {"adhesion", "t2t_codec"}  # K is one product; the codec is bits: requirement goals alone
        for name, node in NODES.items():
            assert bool(decisions(StepFrame(node, _props(node)))) == (name not in branch_free), name


class TestGenerate:
    """What generate finds, and that its expected outputs are the exact model's."""

    def test_supervision_fully_covered(self, supervision_vectors):
        fv = supervision_vectors
        cov = fv.coverage()
        assert fv.requirements_covered() == fv.requirements and len(fv.requirements) == len(_props(SUPERVISION))
        for kind in ("requirement", "boundary", "mcdc"):
            assert cov[kind]["goals"] > 0 and cov[kind]["covered"] == cov[kind]["goals"], (kind, cov)
        assert cov["mcdc"]["goals"] == sum(len(d.conditions) for d in decisions(StepFrame(SUPERVISION)))

    def test_expected_outputs_are_the_exact_model(self, supervision_vectors):
        for v in supervision_vectors.vectors:
            again = Vector(v.id, v.context, v.params, v.state, v.inputs)
            expected(SUPERVISION, again)
            assert (again.next_state, again.outputs) == (v.next_state, v.outputs)

    def test_boundary_vectors_sit_on_the_threshold(self, supervision_vectors):
        at = [v for v in supervision_vectors.vectors if "B1 at" in v.covers]
        assert at and at[0].inputs["speed_mps"] == at[0].inputs["ebi_mps"]
        below = next(v for v in supervision_vectors.vectors if "B1 below" in v.covers)
        assert below.inputs["ebi_mps"] - below.inputs["speed_mps"] == pytest.approx(0.001)

    def test_unreachable_boundary_is_infeasible_not_covered(self):
        fv = generate(DOOR_ENABLE, _props(DOOR_ENABLE), timeout_s=30)
        infeasible = [g for g in fv.goals if g.status == "infeasible"]
        assert infeasible and all(g.kind == "boundary" for g in infeasible)
        assert fv.coverage()["boundary"]["covered"] == fv.coverage()["boundary"]["goals"] - len(infeasible)


class TestVerify:
    """verify re-checks hashes, the symbolic and the exact model, and every coverage claim."""

    def test_generated_files_verify(self, vector_dir, capsys):
        assert main(["vectors", "verify", str(vector_dir)]) == 0
        assert capsys.readouterr().out.count("verified") == 2

    def test_files_carry_their_manifest(self, vector_dir):
        doc = json.loads((vector_dir / "supervision.json").read_text())
        m = doc["manifest"]
        assert m["function"] == "supervision" and m["requirements_covered"] == m["requirements"]
        assert m["model_sha256"] == vector_files.model_sha256() and set(m["tools"]) == {"python", "z3", "atcs"}
        assert m["content_sha256"] == vector_files.content_sha256(doc["goals"], doc["vectors"])
        header = (vector_dir / "supervision.csv").read_text().splitlines()[0].split(",")
        assert header[:3] == ["id", "context", "covers"] and "expected.out.emergency_brake" in header

    def test_tampered_expected_output_fails(self, fresh_dir, capsys):
        path = fresh_dir / "supervision.json"
        doc = json.loads(path.read_text())
        v = doc["vectors"][3]
        v["expected"]["outputs"]["emergency_brake"] = not v["expected"]["outputs"]["emergency_brake"]
        path.write_text(json.dumps(doc))
        assert main(["vectors", "verify", str(fresh_dir)]) == 1
        out = capsys.readouterr().out
        assert "edited: the goals and vectors hash to" in out
        assert f"vector {v['id']}: outputs.emergency_brake is" in out and "the symbolic model gives" in out

    def test_tampered_input_with_its_hash_redone_still_fails(self, fresh_dir):
        """An edit that also fixes the manifest's hash is caught by the model itself."""
        path = fresh_dir / "supervision.json"
        doc = json.loads(path.read_text())
        doc["vectors"][0]["inputs"]["speed_mps"] = "1000"
        doc["manifest"]["content_sha256"] = vector_files.content_sha256(doc["goals"], doc["vectors"])
        path.write_text(json.dumps(doc))
        problems = vector_verify.verify_file(path).problems
        assert not any(p.startswith("edited: the goals") for p in problems)
        assert any("the symbolic model gives" in p for p in problems)

    def test_edited_csv_fails(self, fresh_dir):
        path = fresh_dir / "dcu.csv"
        path.write_text(path.read_text().replace("True", "False", 1))
        assert any("dcu.csv does not match" in p for p in vector_verify.verify_file(fresh_dir / "dcu.json").problems)

    def test_changed_model_fails(self, vector_dir, monkeypatch):
        """A mutant of the step (EB at the EBI, not above it) contradicts the vectors at the boundary."""
        mutant = mutant_node(SUPERVISION, "over_ebi=i.speed_mps > i.ebi_mps", "over_ebi=i.speed_mps >= i.ebi_mps")
        monkeypatch.setitem(NODES, "supervision", mutant)
        monkeypatch.setattr(vector_verify, "model_sha256", lambda: "0" * 64)
        problems = vector_verify.verify_file(vector_dir / "supervision.json").problems
        assert any(p.startswith("the model changed since the vectors were generated") for p in problems)
        assert any("is false in the file, the symbolic model gives true" in p for p in problems)

    def test_wrong_coverage_claim_fails(self, fresh_dir):
        path = fresh_dir / "supervision.json"
        doc = json.loads(path.read_text())
        v = next(
            v
            for v in doc["vectors"]
            if "B1 at" not in v["covers"] and v["inputs"]["speed_mps"] != v["inputs"]["ebi_mps"]
        )
        v["covers"].append("B1 at")
        doc["manifest"]["content_sha256"] = vector_files.content_sha256(doc["goals"], doc["vectors"])
        path.write_text(json.dumps(doc))
        (fresh_dir / "supervision.csv").unlink()
        problems = vector_verify.verify_file(path).problems
        assert f"vector {v['id']}: it is not at boundary B1 at" in problems

    @pytest.mark.parametrize(
        "edit, message",
        [
            (lambda d: d.update(format="x"), "field 'format' must be 'atcs-vectors/1', got 'x'"),
            (
                lambda d: d["manifest"].update(function="nope"),
                "manifest.function names no function of the model: 'nope'",
            ),
            (
                lambda d: d["vectors"][0]["inputs"].update(speed_mps="fast"),
                "vectors[0].inputs.speed_mps = 'fast' is not a number",
            ),
            (
                lambda d: d["vectors"][0]["state"].pop("eb_latched"),
                "vectors[0].state has missing fields ['eb_latched']",
            ),
        ],
    )
    def test_malformed_file_is_one_line(self, fresh_dir, capsys, edit, message):
        path = fresh_dir / "supervision.json"
        doc = json.loads(path.read_text())
        edit(doc)
        path.write_text(json.dumps(doc))
        assert main(["vectors", "verify", str(fresh_dir)]) == 2
        err = capsys.readouterr().err
        assert str(path) in err and message in err and "Traceback" not in err


class TestCheck:
    """check runs an external implementation over JSON lines and shows the first mismatch."""

    def _impl(self, *flags):
        return " ".join([sys.executable, str(IMPL), *flags])

    def test_correct_implementation_passes(self, vector_dir, capsys):
        assert main(["vectors", "check", str(vector_dir), "--function", "supervision", "--impl", self._impl()]) == 0
        n = len(read(vector_dir / "supervision.json").vectors)
        assert f"{n} of {n} vectors passed" in capsys.readouterr().out

    def test_wrong_implementation_fails_with_the_mismatch(self, vector_dir, capsys):
        code = main(
            ["vectors", "check", str(vector_dir), "--function", "supervision", "--impl", self._impl("--wrong-ebi")]
        )
        out = capsys.readouterr().out
        assert code == 1
        fail = next(line for line in out.splitlines() if line.startswith("FAIL") and "B1 at" in line)
        assert "emergency_brake: expected false, got true" in fail or "eb_latched: expected false, got true" in fail

    def test_implementation_that_stops(self, vector_dir, capsys):
        code = main(
            [
                "vectors",
                "check",
                str(vector_dir),
                "--function",
                "supervision",
                "--impl",
                self._impl("--crash-after", "2"),
            ]
        )
        assert code == 1 and "stopped answering (exit code 7)" in capsys.readouterr().err

    def test_command_that_cannot_start_is_a_usage_error(self, vector_dir, capsys):
        assert main(["vectors", "check", str(vector_dir), "--impl", "/nonexistent/impl"]) == 2
        assert "cannot be started" in capsys.readouterr().err

    @pytest.mark.parametrize(
        "argv, message",
        [
            (["vectors", "generate", "--function", "nope"], "--function 'nope' is not a function of the model"),
            (["vectors", "check", "/nonexistent", "--impl", "x"], "/nonexistent is not a directory"),
            (["vectors", "check", ".", "--impl", "x", "--rel-tol", "-1"], "must be a finite number >= 0"),
        ],
    )
    def test_bad_arguments(self, argv, message, capsys):
        assert main(argv) == 2
        assert message in capsys.readouterr().err
