"""The mutation campaign (``atcs mutate``): its sites, its verdicts and kill rates, the registry of
equivalent mutants, and the command line's errors."""

from __future__ import annotations

import dataclasses
import json
import subprocess
import sys
import types
from dataclasses import dataclass
from fractions import Fraction

import pytest

from atcs.model.ops.exact import EXACT
from atcs.proofs.cli import main
from atcs.proofs.mutation import campaign as mutation
from atcs.proofs.mutation.equivalents import EquivalentsError, load_equivalents
from atcs.proofs.mutation.mutants import mutate_function
from atcs.proofs.mutation.sites import OPERATORS, function_mutants
from atcs.properties import PROPERTIES


@dataclass(frozen=True)
class SampleState:
    flag: bool
    count: int


def sample_step(o, p, s: SampleState, i):
    """A small step function with one site of every operator."""
    late = o.and_(i.a, o.not_(s.flag))
    d = o.min(i.x + i.y, o.const(Fraction(1, 2)) - i.z)
    return SampleState(flag=late, count=s.count + 2), o.or_(late, i.x <= d)


SAMPLE_NODES = [types.SimpleNamespace(state=SampleState)]


@pytest.fixture(scope="module")
def mutants():
    return mutation.all_mutants()


class TestSites:
    def test_every_operator_on_a_small_function(self):
        found = {(m.operator, m.original, m.replacement) for m in function_mutants(sample_step, SAMPLE_NODES)}
        assert found == {
            ("bool_swap", "and_", "or_"),
            ("not_drop", "o.not_(s.flag)", "s.flag"),
            ("minmax", "min", "max"),
            ("arith_sign", "+", "-"),
            ("arith_sign", "-", "+"),
            ("arith_drop", "i.x + i.y", "i.x"),
            ("arith_drop", "i.x + i.y", "i.y"),
            ("arith_drop", "o.const(Fraction(1, 2)) - i.z", "o.const(Fraction(1, 2))"),
            ("const", "o.const(Fraction(1, 2))", "(o.const(Fraction(1, 2)) * 11 + 1) / 10"),
            ("delay_hold", "late", "s.flag"),
            ("delay_late", "late", "s.flag"),
            ("delay_hold", "s.count + 2", "s.count"),
            ("arith_drop", "s.count + 2", "s.count"),
            ("arith_drop", "s.count + 2", "2"),
            ("literal", "2", "3"),
            ("bool_swap", "or_", "and_"),
            ("cmp_strict", "<=", "<"),
            ("cmp_flip", "<=", ">="),
        }

    def test_each_mutant_changes_the_function_as_its_diff_says(self):
        o, i = EXACT, types.SimpleNamespace(a=True, x=Fraction(1), y=Fraction(2), z=Fraction(0))
        real = sample_step(o, None, SampleState(False, 0), i)
        for m in function_mutants(sample_step, SAMPLE_NODES):
            fake = mutate_function(sample_step, m.old, m.new)
            removed = [line for line in m.diff.splitlines() if line.startswith("-") and not line.startswith("---")]
            added = [line for line in m.diff.splitlines() if line.startswith("+") and not line.startswith("+++")]
            assert len(removed) == len(added) == 1, m.id
            assert m.original.split()[0] in removed[0], m.id
            fake(o, None, SampleState(False, 0), i)  # every mutant of this function runs
        assert real == (SampleState(True, 2), True)

    def test_ids_are_unique_and_name_module_function_line_operator_change(self, mutants):
        ids = [m.id for m in mutants]
        assert len(ids) == len(set(ids))
        m = next(m for m in mutants if m.id == "supervision.supervision_step:+4:cmp_strict:> -> >=")
        assert (m.model_module, m.function, m.operator, m.original, m.replacement) == (
            "supervision",
            "supervision_step",
            "cmp_strict",
            ">",
            ">=",
        )
        assert m.line == m.resolve().__code__.co_firstlineno + 3

    def test_the_model_has_sites_of_every_operator(self, mutants):
        assert {m.operator for m in mutants} == set(OPERATORS)

    def test_sites_are_in_step_init_and_the_helpers_they_call(self, mutants):
        functions = {(m.model_module, m.function) for m in mutants}
        assert {
            ("supervision", "supervision_step"),
            ("supervision", "supervision_init"),
            ("supervision", "supervise"),
            ("doors", "platform_covers_doors"),
        } <= functions
        assert not any(module in ("ops", "node") for module, _ in functions)


class TestCampaign:
    def test_doors_enable_campaign(self, mutants):
        chosen = mutation.select_mutants(mutants, "doors.door_enable:*")
        outcomes = mutation.run(chosen, timeout_s=60, nodes=("door_enable",))
        rates = mutation.kill_rates(outcomes)["doors"]
        killed = [o for o in outcomes if o.verdict == "killed"]
        assert killed and rates["killed"] == len(killed)
        counted = sum(rates[v] for v in mutation.COUNTED)
        assert rates["kill_rate"] == round(len(killed) / counted, 4)
        for o in killed:  # the counterexample replays on the mutant, and the real model satisfies it
            assert o.run.killed and o.run.reproduced.reproduced
            assert o.run.on_real_model.first_violation is None
            assert o.killed_by in {p.name for p in mutation.affected_properties(o.mutant)}

    def test_a_lemma_is_proved_about_the_mutant_first(self, mutants):
        # position properties need their lemmas: a survivor must be proved with them, not left unknown
        m = next(m for m in mutants if m.id == "supervision.supervision_step:+4:cmp_strict:> -> >=")
        props = [p.name for p in mutation.affected_properties(m)]
        for name in props:
            for lemma in PROPERTIES[name].lemmas:
                assert props.index(lemma) < props.index(name)

    def test_the_time_limit_gives_timeout_never_killed(self, mutants):
        m = next(m for m in mutants if m.model_module == "closed_loop")
        outcome = mutation.run_mutant(m, timeout_s=0.05)
        assert outcome.verdict == "timeout" and outcome.killed_by is None

    def test_a_mutant_whose_code_never_returns_is_stopped_as_a_timeout(self, mutants, monkeypatch):
        m = next(m for m in mutants if m.id == "psl.merge_min:+8:cmp_strict:> -> >=")  # while len(...) >= 1
        monkeypatch.setattr(mutation, "HANG_GRACE_S", 1)
        outcome = mutation.run_mutant(m, timeout_s=1)
        assert outcome.verdict == "timeout" and "did not return" in outcome.message and outcome.seconds < 30

    def test_each_property_gets_a_share_first_and_the_rest_after(self, mutants, monkeypatch):
        """A slow first property does not starve the one after it that kills the mutant."""
        m = next(m for m in mutants if m.id == "supervision.supervision_step:+4:cmp_strict:> -> >=")
        limits = []
        real = mutation.affected_properties

        def two_properties(mutant, nodes=None):
            return [
                p
                for p in real(mutant, nodes)
                if p.name in ("supervision.eb_latched_until_standstill", "supervision.eb_above_ebi")
            ]

        import atcs.proofs.engine.prove as engine

        prove = engine.prove

        def recording(prop, *, timeout_s, **kw):
            limits.append((prop.name, round(timeout_s)))
            return prove(prop, timeout_s=timeout_s, **kw)

        monkeypatch.setattr(mutation, "affected_properties", two_properties)
        monkeypatch.setattr(engine, "prove", recording)
        outcome = mutation.run_mutant(m, timeout_s=60)
        assert [limit for _, limit in limits] == [30] * len(limits) and outcome.verdict in ("killed", "survived")

    def test_a_bounded_check_kills_where_the_proof_is_unknown(self, mutants, monkeypatch):
        """The proofs of a broken model made to end unknown (as an inductive step too hard for the solver does):
        the bounded check of the unknown properties still finds the fault, replayed and absent from the real
        model."""
        m = next(m for m in mutants if m.id == "supervision.supervision_step:+4:cmp_strict:> -> >=")
        import atcs.proofs.engine.prove as engine

        prove = engine.prove

        def unknown_instead(prop, **kw):
            result = prove(prop, **kw)
            if result.status != "falsified":
                return result
            return dataclasses.replace(result, status="unknown", message="timeout in the inductive step at depth 0")

        monkeypatch.setattr(engine, "prove", unknown_instead)
        outcome = mutation.run_mutant(m, timeout_s=60)
        assert outcome.verdict == "killed" and "a bounded check" in outcome.message, outcome.message
        assert outcome.run.killed and outcome.run.on_real_model.first_violation is None

    def test_a_mutant_that_cannot_be_made_is_incompetent(self, mutants):
        m = dataclasses.replace(mutants[0], old="no such text", new="x")
        outcome = mutation.run_mutant(m, timeout_s=10)
        assert outcome.verdict == "incompetent" and "occurs 0 times" in outcome.message

    def test_workers_give_the_same_verdicts(self, mutants):
        chosen = mutation.select_mutants(mutants, "doors.closed_and_locked:*")
        serial = [o.verdict for o in mutation.run(chosen, timeout_s=60, nodes=("door_loop",))]
        parallel = [o.verdict for o in mutation.run(chosen, timeout_s=60, nodes=("door_loop",), jobs=2)]
        assert serial == parallel and "killed" in serial


class TestEquivalents:
    def test_the_shipped_registry_names_current_mutants(self, mutants):
        reasons = load_equivalents(known={m.id for m in mutants})
        assert all(reason for reason in reasons.values())

    def test_a_registered_mutant_is_reported_equivalent(self, tmp_path, capsys):
        mutant_id = "doors.dcu_init:+3:bool_swap:and_ -> or_"
        registry = tmp_path / "eq.toml"
        registry.write_text(f'["{mutant_id}"]\nreason = "power-up is not a property of the DCU"\n')
        report = tmp_path / "m.json"
        code = main(["mutate", "--only", "doors.dcu_init:*", "--equivalents", str(registry), "--json", str(report)])
        doc = json.loads(report.read_text())
        record = next(r for r in doc["mutants"] if r["id"] == mutant_id)
        assert record["verdict"] == "equivalent" and record["message"] == "power-up is not a property of the DCU"
        assert doc["kill_rates"]["doors"]["equivalent"] == 1
        assert code in (0, 1)

    @pytest.mark.parametrize(
        ("text", "needle"),
        [
            ('["no.such:+1:cmp_flip:< -> >"]\nreason = "x"\n', "names no mutant"),
            ('["doors.dcu_init:+3:bool_swap:and_ -> or_"]\nreason = ""\n', "reason must be a non-empty string"),
            ('["doors.dcu_init:+3:bool_swap:and_ -> or_"]\nwhy = "x"\n', "exactly one key"),
            ("[[", "not valid TOML"),
        ],
    )
    def test_a_bad_registry_is_refused(self, tmp_path, mutants, text, needle):
        registry = tmp_path / "eq.toml"
        registry.write_text(text)
        with pytest.raises(EquivalentsError, match=needle):
            load_equivalents(registry, known={m.id for m in mutants})


class TestCommandLine:
    @pytest.mark.parametrize(
        ("args", "needle"),
        [
            (["--only", "nothing*"], "--only 'nothing*' matches no mutant"),
            (["--timeout", "0"], "--timeout: must be a positive number of seconds, got '0'"),
            (["--timeout", "soon"], "--timeout: must be a number of seconds, got 'soon'"),
            (["--jobs", "0"], "--jobs: must be at least 1, got '0'"),
            (["--nodes", "zz"], "--nodes 'zz' matches no node"),
            (["--only", "closed_loop.*", "--nodes", "door*"], "no selected mutant's function is run by"),
            (["--equivalents", "/nonexistent/eq.toml"], "/nonexistent/eq.toml: cannot read"),
            (["--json", "/nonexistent/dir/m.json"], "--json /nonexistent/dir/m.json"),
        ],
    )
    def test_bad_input_is_one_line_and_exit_2(self, args, needle):
        run = subprocess.run(
            [
                sys.executable,
                "-c",
                "import sys; from atcs.proofs.cli import main; sys.exit(main(sys.argv[1:]))",
                "mutate",
                *args,
            ],
            capture_output=True,
            text=True,
        )
        assert run.returncode == 2
        assert run.stderr.count("\n") == 1 and needle in run.stderr, run.stderr
        assert run.stdout == ""

    def test_list_prints_the_selected_ids(self, capsys):
        assert main(["mutate", "--list", "--only", "supervision.supervision_init:*"]) == 0
        assert capsys.readouterr().out.splitlines() == [
            "supervision.supervision_init:+3:bool_swap:and_ -> or_",
            "supervision.supervision_init:+3:not_drop:o.not_(s.sb_latched) -> s.sb_latched",
        ]

    def test_report_and_exit_code(self, tmp_path, capsys):
        report = tmp_path / "m.json"
        code = main(
            ["mutate", "--only", "supervision.supervision_step:*", "--nodes", "supervision", "--json", str(report)]
        )
        doc = json.loads(report.read_text())
        verdicts = {r["verdict"] for r in doc["mutants"]}
        assert code == (1 if "survived" in verdicts else 3 if "timeout" in verdicts else 0)
        assert doc["kill_rates"]["supervision"]["killed"] >= 1
        shown = capsys.readouterr().out
        assert "kill rate" in shown
        for r in doc["mutants"]:
            assert r["diff"].startswith("--- a/supervision.py:supervision_step")
            if r["verdict"] == "survived":
                assert r["id"] in shown
