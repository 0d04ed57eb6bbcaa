"""Vacuity: a proved property comes with witness runs (its assumptions met, each implication's condition
reached), and a property true only because nothing it speaks of can happen is reported vacuous, never proved."""

import dataclasses
import json

import z3

from atcs.proofs.cex.trace import replay
from atcs.proofs.cli import main
from atcs.proofs.engine.prove import prove
from atcs.proofs.engine.vacuity import WITNESS_DEPTH, antecedents
from atcs.properties import PROPERTIES, Assumption

EB_ABOVE_EBI = PROPERTIES["supervision.eb_above_ebi"]
NOT_OVER = Assumption("never_over_ebi", "the speed never exceeds the EBI", lambda o, p, s, i: i.speed_mps <= i.ebi_mps)


class TestVacuous:
    def test_a_condition_the_assumptions_rule_out_is_vacuous(self):
        # true (EB whenever over the EBI) only because the speed is assumed never to be over it
        prop = dataclasses.replace(EB_ABOVE_EBI, name="supervision.eb_above_ebi_never_tested", assumptions=(NOT_OVER,))
        result = prove(prop, timeout_s=60, lemmas=PROPERTIES)
        assert result.status == "vacuous" and result.k == 0
        assert f"no run reaches antecedent 0 (speed_mps@0 > ebi_mps@0) within {WITNESS_DEPTH} steps" in result.message
        assert [w.what for w in result.witnesses] == ["assumptions"]

    def test_assumptions_no_run_meets_are_vacuous(self):
        never = Assumption(
            "contradiction",
            "a speed both below and above 0",
            lambda o, p, s, i: o.and_(i.speed_mps < o.const(0), i.speed_mps > o.const(0)),
        )
        prop = dataclasses.replace(EB_ABOVE_EBI, name="supervision.eb_above_ebi_contradiction", assumptions=(never,))
        result = prove(prop, timeout_s=60, lemmas=PROPERTIES)
        assert result.status == "vacuous" and "no initial state and input meet the assumptions" in result.message

    def test_the_command_line_does_not_pass_a_vacuous_property(self, monkeypatch, tmp_path, capsys):
        prop = dataclasses.replace(EB_ABOVE_EBI, name="supervision.eb_above_ebi_never_tested", assumptions=(NOT_OVER,))
        monkeypatch.setitem(PROPERTIES, prop.name, prop)
        report = tmp_path / "r.json"
        code = main(["prove", "--only", prop.name, "--json", str(report), "--cex-dir", str(tmp_path)])
        (record,) = json.loads(report.read_text())["properties"]
        assert code == 3 and record["status"] == "vacuous"
        assert "vacuous supervision.eb_above_ebi_never_tested: proved, but no run reaches" in capsys.readouterr().out


class TestWitnesses:
    def test_a_proved_property_has_a_witness_for_each_condition_and_they_replay(self):
        prop = PROPERTIES["supervision.eb_latched_until_standstill"]
        result = prove(prop, timeout_s=60, lemmas=PROPERTIES)
        assert result.status == "proved"
        assert [w.what.split(":")[0] for w in result.witnesses] == ["assumptions", "antecedent 0"]
        for w in result.witnesses:
            assert replay(prop, w.trace).problems == []  # a run of the model from an initial state
        w = result.witnesses[1]  # EB latched, and not both standstill and the release: the condition, met
        state, inputs = w.trace.states[w.step], w.trace.inputs[w.step]
        assert state["eb_latched"] and not (inputs["standstill"] and inputs["eb_release"])

    def test_witness_files_and_report(self, tmp_path):
        report, witnesses = tmp_path / "r.json", tmp_path / "w"
        assert (
            main(
                [
                    "prove",
                    "--only",
                    "supervision.eb_above_ebi",
                    "--json",
                    str(report),
                    "--cex-dir",
                    str(tmp_path),
                    "--witness-dir",
                    str(witnesses),
                ]
            )
            == 0
        )
        (record,) = json.loads(report.read_text())["properties"]
        assert record["witnesses"] == [
            {"what": "assumptions", "step": 0},
            {"what": "antecedent 0: speed_mps@0 > ebi_mps@0", "step": 0},
        ]
        doc = json.loads((witnesses / "supervision.eb_above_ebi.witnesses.json").read_text())
        assert [w["step"] for w in doc["witnesses"]] == [0, 0] and doc["witnesses"][1]["trace"]["steps"]

    def test_every_registered_property_is_shown_not_vacuous(self, proof_suite_run):
        for name, record in proof_suite_run.by_name.items():  # the session's atcs prove run (conftest.py)
            assert record["status"] == "proved", (name, record["message"])
            assert record["witnesses"][0] == {"what": "assumptions", "step": 0}, name


class TestAntecedents:
    def test_through_conjunctions_and_nested_consequents(self):
        a, b, c, d, e = z3.Bools("a b c d e")
        term = z3.And(z3.Implies(a, b), z3.Implies(c, z3.Implies(d, e)), e)
        assert [str(x) for x in antecedents(term)] == ["a", "c", "And(c, d)"]
        assert antecedents(z3.Or(a, b)) == []
