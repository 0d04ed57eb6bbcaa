"""Validity cores (``atcs prove --cores``): the parts of the model, the assumptions and the lemmas a proof needs."""

from __future__ import annotations

import json

import pytest

from atcs.proofs.cli import main
from atcs.proofs.engine.cores import validity_core
from atcs.properties import PROPERTIES


def _core(name: str, k: int):
    prop = PROPERTIES[name]
    return validity_core(prop, tuple(PROPERTIES[n] for n in prop.lemmas), k, timeout_s=60)


def test_an_assumption_the_proof_does_without_is_left_out():
    core = _core("supervision.no_intervention_below_permitted", 0)
    assert core.needs == ("assumption curve_order",) and core.minimal
    assert "assumption speed_non_negative" in core.unneeded


def test_a_lemma_can_carry_what_an_assumption_would():
    core = _core("authority.behind_leader", 0)
    assert "lemma authority.rear_bound_behind_stop_bound" in core.needs
    assert "assumption leader_data" in core.unneeded


def test_an_inductive_proof_needs_the_equation_of_the_state_it_keeps():
    core = _core("supervision.sb_held_above_permitted", 1)
    assert core.needs == ("equation sb_latched",) and core.unneeded == ("equation eb_latched",)


def test_a_depth_the_property_is_not_proved_at_has_no_core():
    with pytest.raises(ValueError, match="not proved at depth 0"):
        _core("supervision.sb_held_above_permitted", 0)


def test_prove_gives_each_proved_property_its_core_and_names_what_no_proof_needs(tmp_path, capsys):
    report = tmp_path / "r.json"
    argv = ["prove", "--only", "supervision.no_intervention_below_permitted", "--cores", "--json", str(report)]
    assert main([*argv, "--cex-dir", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "supervision.no_intervention_below_permitted: the proof does not need assumption speed_non_negative" in out
    (record,) = json.loads(report.read_text())["properties"]
    assert record["core"] == {
        "needs": ["assumption curve_order"],
        "unneeded": ["equation eb_latched", "equation sb_latched", "assumption speed_non_negative"],
        "minimal": True,
    }
