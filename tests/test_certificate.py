"""Proof certificates (issue 9): z3 and cvc5 confirm every proved property's certificate; a broken model's
certificate, or one at too shallow a depth, is refuted by both; the scripts are standalone SMT-LIB; a bad prove
report is refused with the file, the field and the value."""

import dataclasses
import hashlib
import json

import pytest
import z3

from atcs.proofs.certificate import SOLVERS, check_obligation, obligations
from atcs.proofs.certify import Certified, certify_one, depths_from_report, run, settle
from atcs.proofs.cli import main
from atcs.proofs.engine import prove
from atcs.proofs.mutants import mutant_property
from atcs.properties import PROPERTIES

GRANTS_TAKEN = ("o.ite(free, code(GRANT), code(REFUSE))", "code(GRANT)")
"""The resource manager grants a resource another train owns (the mutant of tests/test_resources.py)."""


CERTIFIED_IN_CI = ("supervision", "authority", "deceleration", "doors")
"""The modules whose certificates both solvers confirm in seconds; README gives the figures for the rest."""


class TestProvedProperties:
    def test_both_solvers_confirm_every_certificate_of_these_modules(self, proof_suite_run):
        depths = depths_from_report(proof_suite_run.json)  # the session's atcs prove run (conftest.py)
        props = [p for p in PROPERTIES.values() if p.module in CERTIFIED_IN_CI]
        assert len(props) == 35 and all(p.name in depths for p in props)
        results = {c.name: c for c in run(props, depths, timeout_s=120)}
        settle(results, depths)
        refused = {n: c.message for n, c in results.items() if c.status != "certified"}
        assert not refused, refused
        assert all(c.confirmed_by == SOLVERS and c.k == depths[n] for n, c in results.items())


class TestRefuted:
    def test_a_broken_models_certificate_is_refuted_by_both_solvers(self):
        prop = PROPERTIES["resources.mutual_exclusion"]
        real = prove(prop, timeout_s=120, lemmas=PROPERTIES)
        assert real.status == "proved"
        broken = mutant_property(dataclasses.replace(prop, lemmas=()), *GRANTS_TAKEN)
        obs = obligations(broken, real.k, PROPERTIES)
        checks = [check_obligation(solver, ob, 120) for ob in obs for solver in SOLVERS]
        refuted = {c.check for c in checks if c.verdict == "sat"}
        assert refuted and all({c.solver for c in checks if c.check == r and c.verdict == "sat"} == set(SOLVERS)
                               for r in refuted)
        c = Certified(prop.name, prop.requirement, real.k, (), obs, tuple(checks))
        assert c.own_status() == "disagreement" and c.confirmed_by == ()

    def test_too_shallow_a_depth_is_refuted(self):
        name, k = _deeper_than_zero()
        c = certify_one(name, k - 1, 120)
        step = [ch for ch in c.checks if ch.check.startswith("step")]
        assert any(ch.verdict == "sat" for ch in step) and c.own_status() == "disagreement"
        assert certify_one(name, k, 120).own_status() == "certified"


def _deeper_than_zero() -> tuple[str, int]:
    """A quickly proved property whose induction needs k >= 1."""
    for name in ("supervision.sb_held_above_permitted", "authority.rear_bound_behind_stop_bound"):
        result = prove(PROPERTIES[name], timeout_s=120, lemmas=PROPERTIES)
        if result.status == "proved" and result.k >= 1:
            return name, result.k
    raise AssertionError("no quickly proved property needs k >= 1")


class TestScripts:
    def test_certify_proves_first_and_writes_standalone_scripts(self, tmp_path, capsys):
        assert main(["certify", "--only", "position.rear_in_interval", "--dir", str(tmp_path)]) == 0
        doc = json.loads((tmp_path / "certificates.json").read_text())
        (entry,) = doc["properties"]  # the lemma is certified, but only what --only names is reported
        assert entry["status"] == "certified" and entry["lemmas"] == ["position.front_in_interval"]
        assert set(doc["solver_versions"]) == set(SOLVERS)
        assert [c["check"] for c in entry["checks"]] == ["base", "step", "invariant"]
        for check in entry["checks"]:
            text = (tmp_path / check["file"]).read_text()
            assert hashlib.sha256(text.encode()).hexdigest() == check["sha256"]
            assert text.startswith("; atcs proof certificate: position.rear_in_interval")
            assert "(set-logic ALL)" in text and text.rstrip().endswith("(check-sat)")
            solver = z3.Solver()  # any SMT solver can read it: here plain z3, without the engine's tactics
            solver.add(z3.parse_smt2_string(text))
            assert solver.check() == z3.unsat
            assert all(check[s]["verdict"] == "unsat" for s in SOLVERS)
        assert "certified" in capsys.readouterr().out

    def test_a_lemma_without_a_certificate_leaves_the_property_unconfirmed(self):
        results = {"position.rear_in_interval": certify_one("position.rear_in_interval", 0, 60)}
        settle(results, {"position.rear_in_interval": 0})
        c = results["position.rear_in_interval"]
        assert c.own_status() == "certified"
        assert c.status == "unconfirmed" and "lemma position.front_in_interval" in c.message

    def test_an_unknown_is_not_a_confirmation(self):
        c = certify_one("supervision.eb_above_ebi", 0, 60)
        unknown = dataclasses.replace(c, checks=(dataclasses.replace(c.checks[0], verdict="unknown"), *c.checks[1:]))
        others = tuple(s for s in SOLVERS if s != c.checks[0].solver)
        assert unknown.own_status() == "unconfirmed" and unknown.confirmed_by == others


class TestBadInput:
    @pytest.mark.parametrize(("content", "message"), [
        (None, "cannot read the prove report"),
        ("{", "not a JSON prove report"),
        ('{"runs": []}', "properties is missing or not a list"),
        ('{"properties": [{"name": "nosuch.property", "status": "proved", "k": 0}]}',
         "properties[0].name = 'nosuch.property' is not a registered property"),
        ('{"properties": [{"name": "supervision.eb_above_ebi", "status": "proved", "k": -1}]}',
         "properties[0].k = -1 (of supervision.eb_above_ebi) is not a depth"),
    ])
    def test_a_bad_report_names_the_file_the_field_and_the_value(self, tmp_path, capsys, content, message):
        path = tmp_path / "r.json"
        if content is not None:
            path.write_text(content)
        code = main(["certify", "--only", "supervision.eb_above_ebi", "--report", str(path), "--dir", str(tmp_path)])
        err = capsys.readouterr().err
        assert code == 2 and str(path) in err and message in err, err
        assert not (tmp_path / "certificates.json").exists()

    def test_no_matching_property(self, tmp_path, capsys):
        assert main(["certify", "--only", "nosuch.*", "--dir", str(tmp_path)]) == 2
        assert "matches no property" in capsys.readouterr().err

    def test_obligations_need_a_depth(self):
        with pytest.raises(ValueError, match="k must be a non-negative whole number, got -1"):
            obligations(PROPERTIES["supervision.eb_above_ebi"], -1, PROPERTIES)
        with pytest.raises(ValueError, match="solver must be one of z3, cvc5, got 'yices'"):
            check_obligation("yices", obligations(PROPERTIES["supervision.eb_above_ebi"], 0, PROPERTIES)[0], 1)
