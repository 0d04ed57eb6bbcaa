"""Properties proved in parts (:mod:`atcs.proofs.engine.split`): a limit of authority's theorems split into bands of
the target speed, the parts made from their names (in workers too), proved and falsified like any property, and a
property that comes back unknown proved through its parts by ``atcs prove`` and ``atcs certify``."""

from __future__ import annotations

import json

import pytest

from atcs.proofs.cli import main
from atcs.proofs.engine import suite
from atcs.proofs.engine.prove import Result
from atcs.proofs.engine.split import PropertyRegistry, covering_parts, leaves, prove_in_parts
from atcs.proofs.mutation.mutants import falsify
from tests.properties.test_decreases import COARSE_CONFIG, DECREASE_MUTANTS

W0 = "seed000_design_w0"
W5 = "seed000_design_w5"
INVARIANT, UNDER = f"closed_loop.loa_invariant_{W5}", f"closed_loop.under_loa_{W5}"


@pytest.fixture(scope="module")
def config_path(tmp_path_factory):
    path = tmp_path_factory.mktemp("split") / "coarse.toml"
    path.write_text(COARSE_CONFIG, encoding="utf-8")
    return path


@pytest.fixture
def registry(config_path):
    return suite.configured_registry(str(config_path))


def _band(prop) -> str:
    return next(a.text for a in prop.assumptions if a.name == "target_speed_band")


# --- the split of a limit of authority's theorems -------------------------------------------------------------------


def test_a_limit_of_authoritys_theorems_split_into_the_halves_of_the_target_speeds(registry):
    assert isinstance(registry, PropertyRegistry)
    lower, upper = registry[INVARIANT].split()
    assert (lower.name, upper.name) == (f"{INVARIANT}_h0", f"{INVARIANT}_h1")
    assert (_band(lower), _band(upper)) == (
        "the target speed is in [0, 40] km/h",  # the line's top limit is 80 km/h
        "the target speed is in [40, 80] km/h",
    )
    under = registry[f"{UNDER}_h1_h0"]
    assert _band(under) == "the target speed is in [40, 60] km/h"
    assert under.lemmas == (f"{INVARIANT}_h1_h0",)
    assert registry[f"{INVARIANT}_h1_h0"].assumptions == tuple(
        a for a in under.assumptions if a in registry[f"{INVARIANT}_h1_h0"].assumptions
    )
    assert [a.name for a in under.assumptions].count("target_speed_band") == 1


def test_the_split_stops_at_the_resolution_and_unknown_names_are_not_made(registry):
    assert registry[f"{INVARIANT}_h0_h1_h1"].split is None  # 10 km/h wide
    assert _band(registry[f"{INVARIANT}_h0_h1_h1"]) == "the target speed is in [30, 40] km/h"
    for name in (f"{INVARIANT}_h0_h1_h1_h0", f"{INVARIANT}_h2", f"closed_loop.window_reach_{W5}_h0", "nothing_h0"):
        assert name not in registry
        with pytest.raises(KeyError):
            registry[name]
    assert registry.get(f"{INVARIANT}_h2") is None


def test_covering_parts_are_complete_halves_or_none():
    whole = "m.p"
    assert covering_parts(whole, [whole]) == [whole]
    assert covering_parts(whole, [f"{whole}_h0", f"{whole}_h1_h0", f"{whole}_h1_h1"]) == [
        f"{whole}_h0",
        f"{whole}_h1_h0",
        f"{whole}_h1_h1",
    ]
    assert covering_parts(whole, [f"{whole}_h0", f"{whole}_h1_h0"]) is None  # the upper quarter is missing
    assert covering_parts(whole, []) is None


# --- the parts are properties like any other ------------------------------------------------------------------------


def test_the_parts_are_proved_by_workers_that_make_them_from_their_names(config_path, registry):
    parts = [registry[f"{name}_h{j}"] for name in (INVARIANT, UNDER) for j in (0, 1)]
    results = {r.name: r for r in suite.run(parts, timeout_s=300, jobs=2, configuration=str(config_path))}
    assert {name: r.status for name, r in results.items()} == {p.name: "proved" for p in parts}


def test_a_part_is_falsified_by_a_mutant_and_its_counterexample_is_in_its_band(registry):
    part = registry[f"closed_loop.under_loa_{W0}_h0"]
    run = falsify(part, *DECREASE_MUTANTS[0], max_k=8)
    assert run.killed, run
    target_kmh = run.result.trace.params["mrsp_after_mps"] * 3.6
    assert 0 <= target_kmh <= 40


# --- proving in parts -----------------------------------------------------------------------------------------------


def _scripted(verdicts: dict[str, str], default: str = "proved"):
    """A prover that gives each property the verdict ``verdicts`` names (else ``default``), k = 3 when proved."""
    rounds = []

    def run(level):
        rounds.append([p.name for p in level])
        for p in level:
            status = verdicts.get(p.name, default)
            yield Result(p.name, p.requirement, status, "scripted", 3 if status == "proved" else None, 1.0, status)

    return run, rounds


def test_an_unknown_property_is_proved_through_its_halves_down_to_where_they_close(registry):
    run, rounds = _scripted({INVARIANT: "unknown", f"{INVARIANT}_h1": "unknown"})
    (result,) = prove_in_parts([registry[INVARIANT]], run)
    assert rounds == [[INVARIANT], [f"{INVARIANT}_h0", f"{INVARIANT}_h1"], [f"{INVARIANT}_h1_h0", f"{INVARIANT}_h1_h1"]]
    assert (result.name, result.status, result.engine, result.k) == (INVARIANT, "proved", "split", 3)
    assert result.seconds == 5.0  # every attempt counts, the unknown ones too
    assert [r.name for r in leaves([result])] == [f"{INVARIANT}_h0", f"{INVARIANT}_h1_h0", f"{INVARIANT}_h1_h1"]
    assert result.message == "3 parts: 3 proved"


def test_a_property_takes_its_worst_parts_verdict(registry):
    run, _ = _scripted({INVARIANT: "unknown", f"{INVARIANT}_h0": "falsified", f"{INVARIANT}_h1": "unknown"})
    (result,) = prove_in_parts([registry[INVARIANT]], run)
    assert result.status == "falsified"
    assert result.message == f"3 parts: 1 falsified, 2 proved; {INVARIANT}_h0: falsified"
    run, rounds = _scripted({}, default="unknown")
    (result,) = prove_in_parts([registry[INVARIANT]], run)
    assert [len(names) for names in rounds] == [1, 2, 4, 8]  # 80, 40, 20 and 10 km/h wide
    assert (result.status, result.message) == ("unknown", f"8 parts: 8 unknown; {INVARIANT}_h0_h0_h0: unknown")


def test_a_split_that_does_not_name_its_halves_so_is_refused(registry):
    import dataclasses

    wrong = dataclasses.replace(registry[INVARIANT], split=lambda: (registry[UNDER], registry[UNDER]))
    run, _ = _scripted({INVARIANT: "unknown"})
    with pytest.raises(ValueError, match=r"_h0 and .*_h1"):
        list(prove_in_parts([wrong], run))


# --- atcs prove and atcs certify ----------------------------------------------------------------------------------


@pytest.fixture
def whole_unknown(monkeypatch):
    """The prover gives a limit of authority's whole theorems ``unknown`` (as z3 may at the time limit), and proves
    their parts for real."""
    real = suite.run

    def run(props, **kwargs):
        parts = [p for p in props if p.name.endswith(("_h0", "_h1"))]
        for p in props:
            if p not in parts:
                yield Result(p.name, p.requirement, "unknown", "k-induction", None, 0.5, "timed out (scripted)")
        if parts:
            yield from real(parts, **kwargs)

    monkeypatch.setattr(suite, "run", run)


def test_atcs_prove_proves_an_unknown_theorem_in_parts_and_reports_them(config_path, tmp_path, whole_unknown):
    report = tmp_path / "report.json"
    args = ["prove", "--config", str(config_path), "--only", INVARIANT, "--json", str(report), "--jobs", "2"]
    assert main([*args, "--cache", str(tmp_path / "cache")]) == 0
    doc = json.loads(report.read_text())
    whole, *parts = doc["properties"]
    assert (whole["name"], whole["status"], whole["engine"]) == (INVARIANT, "proved", "split")
    assert whole["parts"] == [f"{INVARIANT}_h0", f"{INVARIANT}_h1"] == [p["name"] for p in parts]
    assert {(p["status"], p["part_of"]) for p in parts} == {("proved", INVARIANT)}
    assert doc["summary"]["proved"] == 1
    assert main([*args, "--cache", str(tmp_path / "cache")]) == 0  # the whole kept, with its parts
    assert [p["name"] for p in json.loads(report.read_text())["properties"]] == [INVARIANT, *whole["parts"]]


def test_atcs_certify_certifies_a_theorem_proved_in_parts_by_its_parts(config_path, tmp_path, whole_unknown):
    out = tmp_path / "certificates"
    assert main(["certify", "--config", str(config_path), "--only", INVARIANT, "--dir", str(out), "--jobs", "2"]) == 0
    doc = json.loads((out / "certificates.json").read_text())
    whole, *parts = doc["properties"]
    assert (whole["name"], whole["status"], whole["parts"]) == (INVARIANT, "certified", [p["name"] for p in parts])
    assert [p["name"] for p in parts] == [f"{INVARIANT}_h0", f"{INVARIANT}_h1"]
    assert all(p["status"] == "certified" and p["checks"] and p["part_of"] == INVARIANT for p in parts)
    assert doc["summary"]["certified"] == 1


def test_atcs_certify_takes_the_parts_from_a_prove_report_and_refuses_parts_that_leave_a_band_out(
    config_path, tmp_path, whole_unknown
):
    report = tmp_path / "report.json"
    assert main(["prove", "--config", str(config_path), "--only", INVARIANT, "--json", str(report)]) == 0
    certify = ["certify", "--config", str(config_path), "--only", INVARIANT, "--report", str(report)]
    assert main([*certify, "--dir", str(tmp_path / "all")]) == 0
    doc = json.loads((tmp_path / "all" / "certificates.json").read_text())
    assert (doc["properties"][0]["name"], doc["properties"][0]["status"]) == (INVARIANT, "certified")
    proved = json.loads(report.read_text())
    proved["properties"] = [p for p in proved["properties"] if p["name"] != f"{INVARIANT}_h1"]
    report.write_text(json.dumps(proved))
    assert main([*certify, "--dir", str(tmp_path / "half")]) == 3
    doc = json.loads((tmp_path / "half" / "certificates.json").read_text())
    assert [(p["name"], p["status"], p["message"]) for p in doc["properties"]] == [
        (INVARIANT, "not proved", "no proof to certify, and its proved parts do not cover it")
    ]
