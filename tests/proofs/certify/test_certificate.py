"""Proof certificates: z3 and cvc5 confirm every proved property's certificate; a broken model's
certificate, or one at too shallow a depth, is refuted by both; the scripts are standalone SMT-LIB; a bad prove
report is refused with the file, the field and the value."""

import dataclasses
import hashlib
import json

import pytest
import z3

from atcs.proofs.certify.campaign import Certified, certify_one, depths_from_report, settle, solver_timeouts
from atcs.proofs.certify.obligations import SOLVERS, SolverCheck, check_obligation, obligations
from atcs.proofs.cli import main
from atcs.proofs.engine.prove import prove
from atcs.proofs.mutation.mutants import mutant_property
from atcs.properties import PROPERTIES
from atcs.properties.closed_loop import CERTIFICATE_SPEED_BOUND_MPS

GRANTS_TAKEN = ("o.ite(free, code(GRANT), code(REFUSE))", "code(GRANT)")
"""The resource manager grants a resource another train owns (the mutant of tests/model/test_resources.py)."""


class TestProvedProperties:
    def test_every_proved_property_is_certified_by_both_solvers(self, certify_suite_run, proof_suite_run):
        """Both solvers confirm every certificate but the few the suite gives z3 alone (conftest.py): z3 confirms
        those, and they, and the properties resting on them as lemmas, are unconfirmed only because cvc5 was not
        asked."""
        # the session's atcs certify --report on the session's atcs prove report (conftest.py)
        depths = depths_from_report(proof_suite_run.json)
        assert len(depths) == len(PROPERTIES)
        doc = certify_suite_run.doc
        assert doc["solver_timeout_s"] == certify_suite_run.timeouts_s and set(doc["solver_versions"]) == set(SOLVERS)
        assert doc["z3_only"] == sorted(certify_suite_run.z3_only) and set(certify_suite_run.by_name) == set(depths)
        z3_only = set(certify_suite_run.z3_only)
        wrong = {}
        for name, r in certify_suite_run.by_name.items():
            assert r["k"] == depths[name] and r["checks"]
            for c in r["checks"]:
                text = (certify_suite_run.dir / c["file"]).read_text()
                assert hashlib.sha256(text.encode()).hexdigest() == c["sha256"]
            solvers = ("z3",) if name in z3_only else SOLVERS
            verdicts = {(solver, c[solver]["verdict"]) for c in r["checks"] for solver in solvers}
            status = "unconfirmed" if _rests_on(name, z3_only) else "certified"
            if (
                r["status"] != status
                or r["confirmed_by"] != list(solvers)
                or verdicts != {(solver, "unsat") for solver in solvers}
            ):
                wrong[name] = (r["status"], r["message"], sorted(verdicts))
        assert not wrong, wrong
        for name in z3_only:
            reasons = {c["cvc5"]["reason"] for c in certify_suite_run.by_name[name]["checks"]}
            assert reasons == {"not checked: cvc5 was not asked (--z3-only)"}, (name, reasons)
        unconfirmed = sum(_rests_on(name, z3_only) for name in depths)
        assert doc["summary"]["certified"] == len(depths) - unconfirmed and doc["summary"]["unconfirmed"] == unconfirmed
        assert certify_suite_run.code == 3  # some property unconfirmed, none disagreeing


def _rests_on(name: str, names: set[str]) -> bool:
    """``name`` is one of ``names`` or assumes one of them as a lemma, directly or through other lemmas."""
    return name in names or any(_rests_on(lemma, names) for lemma in PROPERTIES[name].lemmas)


class TestRefuted:
    def test_a_broken_models_certificate_is_refuted_by_both_solvers(self):
        prop = PROPERTIES["resources.mutual_exclusion"]
        real = prove(prop, timeout_s=120, lemmas=PROPERTIES)
        assert real.status == "proved"
        broken = mutant_property(dataclasses.replace(prop, lemmas=()), *GRANTS_TAKEN)
        obs = obligations(broken, real.k, PROPERTIES)
        checks = [check_obligation(solver, ob, 120) for ob in obs for solver in SOLVERS]
        refuted = {c.check for c in checks if c.verdict == "sat"}
        assert refuted and all(
            {c.solver for c in checks if c.check == r and c.verdict == "sat"} == set(SOLVERS) for r in refuted
        )
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
        assert (
            main(["certify", "--only", "position.rear_in_interval", "--dir", str(tmp_path), "--cvc5-timeout", "90"])
            == 0
        )
        doc = json.loads((tmp_path / "certificates.json").read_text())
        assert doc["solver_timeout_s"] == {"z3": 600.0, "cvc5": 90.0}  # z3's is --timeout's default
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

    def test_the_step_is_split_by_the_certificate_cases_and_the_rest(self):
        # closed-loop properties: the engine splits its step by the EB-command counter, the certificate also
        # bounds the speed in each case (properties/closed_loop.py); the rest case keeps every state covered
        prop = PROPERTIES["closed_loop.braking_invariant_seed000"]
        n_cases = int(prop.fixed_params["brake_build_up_cycles"]) + 1
        bound = f"(>= {z3.RealVal(CERTIFICATE_SPEED_BOUND_MPS).sexpr()} speed_mps@0)"
        steps = [ob for ob in obligations(prop, 1, PROPERTIES) if ob.check.startswith("step")]
        assert [ob.check for ob in steps] == [f"step_case_{j}" for j in range(1, n_cases + 2)]
        assert all(bound in ob.script for ob in steps) and "(the states in no other case)" in steps[-1].claim
        assert prop.cases is not prop.certificate_cases
        assert all(check_obligation("z3", ob, 120).verdict == "unsat" for ob in (steps[0], steps[-1]))

    def test_a_lemma_without_a_certificate_leaves_the_property_unconfirmed(self):
        results = {"position.rear_in_interval": certify_one("position.rear_in_interval", 0, 60)}
        settle(results, {"position.rear_in_interval": 0})
        c = results["position.rear_in_interval"]
        assert c.own_status() == "certified"
        assert c.status == "unconfirmed" and "lemma position.front_in_interval" in c.message

    def test_a_solver_that_gave_up_is_not_asked_again_and_says_so(self, monkeypatch):
        import atcs.proofs.certify.campaign as certify

        real = certify.check_obligation
        asked = []

        def first_cvc5_check_times_out(solver, ob, timeout_s, resource_limit):
            asked.append((solver, ob.check, timeout_s))
            if solver == "cvc5" and ob.check == "base":
                return SolverCheck(solver, ob.check, "unknown", timeout_s, "timeout")
            return real(solver, ob, timeout_s, resource_limit)

        monkeypatch.setattr(certify, "check_obligation", first_cvc5_check_times_out)
        c = certify_one("supervision.sb_held_above_permitted", 1, {"z3": 60, "cvc5": 7})
        assert [(s, t) for s, _, t in asked] == [("z3", 60), ("cvc5", 7), ("z3", 60), ("z3", 60)]
        later = [ch for ch in c.checks if ch.solver == "cvc5" and ch.check != "base"]
        assert [ch.check for ch in later] == ["step", "invariant"]
        assert all(ch.verdict == "unknown" and ch.reason == "not checked: cvc5 said unknown on base" for ch in later)
        assert c.own_status() == "unconfirmed" and c.confirmed_by == ("z3",)
        settle({c.name: c}, {c.name: 1})
        assert c.message == "cvc5 says unknown on base (timeout); 2 checks not checked: cvc5 said unknown on base"

    def test_z3_only_leaves_the_property_unconfirmed_and_says_why(self, tmp_path):
        report = tmp_path / "r.json"
        report.write_text('{"properties": [{"name": "supervision.eb_above_ebi", "status": "proved", "k": 0}]}')
        argv = ["certify", "--only", "supervision.eb_above_ebi", "--report", str(report), "--dir", str(tmp_path)]
        assert main([*argv, "--z3-only", "supervision.eb_*"]) == 3
        doc = json.loads((tmp_path / "certificates.json").read_text())
        (entry,) = doc["properties"]
        assert doc["z3_only"] == ["supervision.eb_above_ebi"] and entry["status"] == "unconfirmed"
        assert entry["confirmed_by"] == ["z3"] and all(c["cvc5"]["seconds"] == 0 for c in entry["checks"])
        assert all(c["cvc5"]["reason"] == "not checked: cvc5 was not asked (--z3-only)" for c in entry["checks"])

    def test_cvc5s_resource_limit_gives_unknown_and_every_check_counts_its_units(self, tmp_path):
        obs = obligations(PROPERTIES["closed_loop.braking_invariant_seed000"], 1, PROPERTIES)
        step = next(ob for ob in obs if ob.check == "step_case_2")
        check = check_obligation("cvc5", step, 120, resource_limit=20_000)
        assert (check.verdict, check.reason) == ("unknown", "resourceout") and check.resource_units >= 20_000
        easy = obligations(PROPERTIES["supervision.eb_above_ebi"], 0, PROPERTIES)[0]
        assert check_obligation("cvc5", easy, 60).resource_units > 0
        assert check_obligation("z3", easy, 60).resource_units is None
        with pytest.raises(ValueError, match=r"resource_limit must be a positive whole number .* got 0 for cvc5"):
            check_obligation("cvc5", easy, 60, resource_limit=0)
        with pytest.raises(ValueError, match=r"resource_limit .* got 5 for z3"):
            check_obligation("z3", easy, 60, resource_limit=5)

    def test_an_unknown_is_not_a_confirmation(self):
        c = certify_one("supervision.eb_above_ebi", 0, 60)
        unknown = dataclasses.replace(c, checks=(dataclasses.replace(c.checks[0], verdict="unknown"), *c.checks[1:]))
        others = tuple(s for s in SOLVERS if s != c.checks[0].solver)
        assert unknown.own_status() == "unconfirmed" and unknown.confirmed_by == others

    def test_a_formula_is_checked_once_by_each_solver(self, monkeypatch):
        """k = 0 on a stateless node: the base (every state initial) and the step are one formula."""
        import atcs.proofs.certify.campaign as certify

        real, asked = certify.check_obligation, []

        def counted(solver, ob, timeout_s, resource_limit):
            asked.append((solver, ob.check))
            return real(solver, ob, timeout_s, resource_limit)

        monkeypatch.setattr(certify, "check_obligation", counted)
        c = certify_one("mrsp.below_every_profile", 0, 60)
        base, step = c.obligations[:2]
        assert (
            base.script != step.script
            and base.formula == step.formula
            and "true" not in base.formula.split("(check-sat)")[0].split("(assert\n")[1][:10]
        )
        assert asked == [(s, check) for check in ("base", "invariant") for s in SOLVERS]
        reused = [ch for ch in c.checks if ch.check == "step"]
        assert [(ch.verdict, ch.reason, ch.seconds) for ch in reused] == [("unsat", "the formula of base", 0.0)] * 2
        assert c.own_status() == "certified"


class TestReuse:
    """``--reuse``: cvc5's verdict on a script byte for byte the same as one an earlier listing records unsat (same
    cvc5 version) is taken from it; any other script is given to cvc5; z3 checks every script."""

    def test_a_listed_script_is_not_given_to_cvc5_again_and_every_other_is(self, tmp_path, monkeypatch):
        import atcs.proofs.certify.campaign as certify

        report = tmp_path / "r.json"
        name = "supervision.sb_held_above_permitted"
        report.write_text(json.dumps({"properties": [{"name": name, "status": "proved", "k": 1}]}))
        argv = ["certify", "--only", name, "--report", str(report)]
        assert main([*argv, "--dir", str(tmp_path / "first")]) == 0
        listing = tmp_path / "first" / "certificates.json"
        doc = json.loads(listing.read_text())
        changed = doc["properties"][0]["checks"][0]  # as if the base's script had changed since
        changed["sha256"] = "0" * 64
        listing.write_text(json.dumps(doc))
        real, asked = certify.check_obligation, []

        def counted(solver, ob, timeout_s, resource_limit):
            asked.append((solver, ob.check))
            return real(solver, ob, timeout_s, resource_limit)

        monkeypatch.setattr(certify, "check_obligation", counted)
        assert main([*argv, "--dir", str(tmp_path / "again"), "--reuse", str(listing)]) == 0
        again = json.loads((tmp_path / "again" / "certificates.json").read_text())
        checks = {c["check"]: c for c in again["properties"][0]["checks"]}
        assert again["reused"] == str(listing) and set(checks) == {"base", "step", "invariant"}
        assert sorted(asked) == sorted([("z3", c) for c in checks] + [("cvc5", "base")])
        reused = f"reused: cvc5 found this very script unsat in {listing}"
        assert [checks[c]["cvc5"]["reason"] for c in ("step", "invariant")] == [reused] * 2
        assert all(
            checks[c]["cvc5"]["seconds"] == 0 < checks[c]["cvc5"]["resource_units"] for c in ("step", "invariant")
        )
        assert checks["base"]["cvc5"]["reason"] == "" and again["properties"][0]["status"] == "certified"

    def test_another_cvc5_versions_listing_reuses_nothing_and_says_so(self, tmp_path):
        import atcs.proofs.certify.campaign as certify

        listing = tmp_path / "certificates.json"
        check = {"sha256": "a" * 64, "cvc5": {"verdict": "unsat", "resource_units": 5}}
        doc = {"solver_versions": {"cvc5": "0.0.1"}, "properties": [{"checks": [check]}]}
        listing.write_text(json.dumps(doc))
        scripts, said = certify.cvc5_unsat_scripts(listing)
        assert scripts == {} and said.startswith("none of its verdicts reused: they are cvc5 0.0.1's, this is cvc5 ")
        doc["solver_versions"]["cvc5"] = certify.solver_versions()["cvc5"]
        listing.write_text(json.dumps(doc))
        assert certify.cvc5_unsat_scripts(listing)[0] == {"a" * 64: 5}

    def test_the_suites_listing_is_readable(self):
        import atcs.proofs.certify.campaign as certify
        from tests.conftest import CERTIFIED_BEFORE

        scripts, _ = certify.cvc5_unsat_scripts(CERTIFIED_BEFORE)
        doc = json.loads(CERTIFIED_BEFORE.read_text())
        assert doc["tool"] == "atcs certify" and doc.get("reused") is None  # made by cvc5 itself, not by a reuse
        assert scripts or doc["solver_versions"]["cvc5"] != certify.solver_versions()["cvc5"]


class TestBadInput:
    @pytest.mark.parametrize(
        ("content", "message"),
        [
            (None, "cannot read the prove report"),
            ("{", "the prove report is not JSON"),
            ('{"runs": []}', "properties is missing or not a list"),
            (
                '{"properties": [{"name": "nosuch.property", "status": "proved", "k": 0}]}',
                "properties[0].name = 'nosuch.property' is not a registered property",
            ),
            (
                '{"properties": [{"name": "supervision.eb_above_ebi", "status": "proved", "k": -1}]}',
                "properties[0].k = -1 (of supervision.eb_above_ebi) is not a depth",
            ),
        ],
    )
    def test_a_bad_report_names_the_file_the_field_and_the_value(self, tmp_path, capsys, content, message):
        path = tmp_path / "r.json"
        if content is not None:
            path.write_text(content)
        code = main(["certify", "--only", "supervision.eb_above_ebi", "--report", str(path), "--dir", str(tmp_path)])
        err = capsys.readouterr().err
        assert code == 2 and str(path) in err and message in err, err
        assert not (tmp_path / "certificates.json").exists()

    @pytest.mark.parametrize("option", ["--z3-timeout", "--cvc5-timeout"])
    def test_a_bad_solver_time_limit_names_the_option_and_the_value(self, tmp_path, capsys, option):
        assert main(["certify", "--only", "supervision.eb_above_ebi", option, "0", "--dir", str(tmp_path)]) == 2
        err = capsys.readouterr().err
        assert option in err and "'0'" in err and len(err.strip().splitlines()) == 1, err

    def test_per_solver_limits_must_name_every_solver_with_a_positive_number(self):
        assert solver_timeouts(30) == {"z3": 30, "cvc5": 30}
        with pytest.raises(ValueError, match=r"a limit for each of z3, cvc5, got \['z3'\]"):
            solver_timeouts({"z3": 30})
        with pytest.raises(ValueError, match=r"timeout_s\['cvc5'\] must be a positive number of seconds, got -1"):
            solver_timeouts({"z3": 30, "cvc5": -1})

    def test_a_z3_only_glob_that_matches_nothing_is_refused(self, tmp_path, capsys):
        argv = ["certify", "--only", "supervision.eb_above_ebi", "--z3-only", "supervision.*,nosuch.*"]
        assert main([*argv, "--dir", str(tmp_path)]) == 2
        assert "--z3-only 'nosuch.*' matches no property" in capsys.readouterr().err

    @pytest.mark.parametrize(
        ("content", "message"),
        [
            ("[]", "properties is missing or not a list"),
            ('{"properties": [], "solver_versions": {}}', "solver_versions.cvc5 must be a version string, got None"),
            (
                '{"properties": [{"checks": [{"sha256": "x"}]}], "solver_versions": {"cvc5": "1"}}',
                "properties[0].checks[0].sha256 must be a SHA-256 in hex, got 'x'",
            ),
        ],
    )
    def test_a_bad_listing_to_reuse_names_the_file_the_field_and_the_value(self, tmp_path, capsys, content, message):
        path = tmp_path / "listing.json"
        path.write_text(content)
        argv = ["certify", "--only", "supervision.eb_above_ebi", "--reuse", str(path), "--dir", str(tmp_path)]
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert f"--reuse {path}: {message}" in err and len(err.strip().splitlines()) == 1, err

    def test_no_matching_property(self, tmp_path, capsys):
        assert main(["certify", "--only", "nosuch.*", "--dir", str(tmp_path)]) == 2
        assert "matches no property" in capsys.readouterr().err

    def test_obligations_need_a_depth(self):
        with pytest.raises(ValueError, match="k must be a non-negative whole number, got -1"):
            obligations(PROPERTIES["supervision.eb_above_ebi"], -1, PROPERTIES)
        with pytest.raises(ValueError, match="solver must be one of z3, cvc5, got 'yices'"):
            check_obligation("yices", obligations(PROPERTIES["supervision.eb_above_ebi"], 0, PROPERTIES)[0], 1)
