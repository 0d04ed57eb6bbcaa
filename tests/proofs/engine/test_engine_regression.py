"""The proof engine on small regression models, sorted by expected verdict (see regression/README.md)."""

import importlib.util
import sys
from pathlib import Path

import pytest

from atcs.proofs.cex.trace import reproduce
from atcs.proofs.engine.prove import bounded_check, prove

ROOT = Path(__file__).parent / "regression"


def load(path: Path, name: str):
    """Import a regression file by path, registered in sys.modules (dataclasses need it)."""
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


load(ROOT / "models.py", "regression_models")
MODULES = {
    f"{p.parent.name}/{p.stem}": load(p, f"regression_{p.parent.name}_{p.stem}") for p in sorted(ROOT.glob("*/*.py"))
}
CASES = [
    pytest.param(module, prop, id=f"{key}:{prop.name}") for key, module in MODULES.items() for prop in module.PROPERTIES
]


def test_every_verdict_has_regression_models():
    assert {key.split("/")[0] for key in MODULES} == {"proved", "falsified", "unknown", "error"}


@pytest.mark.parametrize(("module", "prop"), CASES)
def test_verdict(module, prop):
    expect = module.EXPECT[prop.name]
    lemmas = {p.name: p for p in module.PROPERTIES}
    result = prove(prop, timeout_s=expect.get("timeout_s", 120), lemmas=lemmas)
    assert result.status == expect["status"], result.message
    if "k" in expect:
        assert result.k == expect["k"]
    assert expect.get("message", "") in result.message
    if result.status == "falsified":
        assert result.trace.violation_step == result.k
        assert reproduce(prop, result.trace).first_violation == result.k
    else:
        assert result.trace is None


def test_every_property_has_an_expectation():
    for key, module in MODULES.items():
        assert set(module.EXPECT) == {p.name for p in module.PROPERTIES}, key


def test_node_refuses_field_names_used_twice():
    with pytest.raises(ValueError, match="'x' appears in both state and inputs"):
        MODULES["error/misused_model"].node_with_clashing_fields()


def test_counterexample_that_does_not_replay_is_an_error(monkeypatch):
    """If the solver's trace and the exact replay disagree, the engine reports an internal error, not a verdict."""
    import atcs.proofs.engine.prove as engine

    real_extract = engine.extract

    def corrupted(u, model, k):
        trace = real_extract(u, model, k)
        trace.states[-1] = {n: v + 1 for n, v in trace.states[-1].items()}
        return trace

    monkeypatch.setattr(engine, "extract", corrupted)
    prop = MODULES["falsified/counter_overflow"].PROPERTIES[0]
    result = prove(prop, timeout_s=120)
    assert result.status == "error"
    assert "does not replay" in result.message and "the trace's" in result.message


def test_array_fields_round_trip_through_trace_files(tmp_path):
    """Counterexamples of nodes with array fields are written and read back as lists."""
    import json

    from atcs.proofs.cex.trace import from_json, reproduce, to_csv, to_json

    prop = MODULES["falsified/array_shift_negative"].PROPERTIES[0]
    result = prove(prop, timeout_s=120)
    doc = to_json(result.trace, result.replay)
    assert isinstance(doc["steps"][0]["state"]["cells"], list) and len(doc["steps"][0]["state"]["cells"]) == 3
    path = tmp_path / "cex.json"
    path.write_text(json.dumps(doc))
    again_prop, again = from_json(path, {prop.name: prop})
    assert again == result.trace
    assert reproduce(again_prop, again).first_violation == 3
    assert "state.cells[2]" in to_csv(result.trace, result.replay).splitlines()[0]
    doc["steps"][0]["state"]["cells"] = [0, 0]
    path.write_text(json.dumps(doc))
    with pytest.raises(ValueError, match=r"steps\[0\]\.state\.cells must be a list of 3 values"):
        from_json(path, {prop.name: prop})


@pytest.mark.parametrize(
    ("sizes", "message"),
    [
        ({}, "needs a size >= 1"),
        ({"cells": 0}, "needs a size >= 1"),
        ({"cells": 3, "other": 2}, "'other', which is not an array field"),
    ],
)
def test_node_validates_array_sizes(sizes, message):
    import dataclasses

    with pytest.raises(ValueError, match=message):
        dataclasses.replace(sys.modules["regression_models"].SHIFT, sizes=sizes)


BOUNDED = [case for case in CASES if case.values[0].EXPECT[case.values[1].name]["status"] in ("proved", "falsified")]


@pytest.mark.parametrize(("module", "prop"), BOUNDED)
def test_a_bounded_check_finds_the_same_counterexample_and_proves_nothing(module, prop):
    """BMC alone (what ``atcs mutate`` gives a property a mutant leaves unknown): a falsified model's shortest
    counterexample, replayed; for a proved one, no counterexample up to the depth, and still not proved."""
    expect = module.EXPECT[prop.name]
    lemmas = {p.name: p for p in module.PROPERTIES}
    depth = expect.get("k", 0) + 2
    result = bounded_check(prop, depth=depth, timeout_s=expect.get("timeout_s", 120), lemmas=lemmas)
    if expect["status"] == "falsified":
        assert (result.status, result.engine) == ("falsified", "bmc") and result.k == expect.get("k", result.k)
        assert reproduce(prop, result.trace).first_violation == result.k
    else:
        assert (result.status, result.engine, result.k) == ("unknown", "bmc", depth)
        assert result.message == f"no counterexample up to depth {depth} (a bounded check, not a proof)"


@pytest.mark.parametrize("depth", [-1, 1.5, True, "2"])
def test_a_bounded_check_refuses_a_depth_that_is_not_a_whole_number(depth):
    prop = CASES[0].values[1]
    with pytest.raises(ValueError, match=f"depth must be a whole number >= 0, got {depth!r}"):
        bounded_check(prop, depth=depth)
