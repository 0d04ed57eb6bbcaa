"""Counterexample traces: exact values in files, round trips, and files that were edited or are malformed."""

import json
from fractions import Fraction

import pytest
from hypothesis import given
from hypothesis import strategies as st

from atcs.model.supervision import supervise
from atcs.proofs.cex.trace import (
    ReplayError,
    TraceFileError,
    format_value,
    from_json,
    replay,
    reproduce,
    to_csv,
    to_json,
)
from atcs.proofs.engine.prove import prove
from atcs.proofs.mutation.mutants import mutant_property
from atcs.properties import PROPERTIES

NAME = "supervision.eb_latched_until_standstill"


@pytest.fixture(scope="module")
def falsified():
    mutant = mutant_property(
        PROPERTIES[NAME], "eb_released = o.and_(standstill, eb_release)", "eb_released = eb_release", helper=supervise
    )
    result = prove(mutant, timeout_s=120)
    assert result.status == "falsified"
    return mutant, result


def write(tmp_path, doc):
    path = tmp_path / "t.json"
    path.write_text(json.dumps(doc))
    return path


class TestValues:
    @given(st.fractions())
    def test_format_is_exact(self, value):
        assert Fraction(format_value(value)) == value

    @pytest.mark.parametrize(
        ("value", "text"),
        [
            (Fraction(1, 2), "0.5"),
            (Fraction(-5, 4), "-1.25"),
            (Fraction(1, 3), "1/3"),
            (Fraction(7), "7"),
            (True, True),
        ],
    )
    def test_decimal_when_finite(self, value, text):
        assert format_value(value) == text


class TestFiles:
    def test_json_round_trip(self, falsified, tmp_path):
        mutant, result = falsified
        path = write(tmp_path, to_json(result.trace, result.replay))
        prop, trace = from_json(path, {NAME: mutant})
        assert prop is mutant and trace == result.trace

    def test_csv_one_row_per_step(self, falsified):
        _, result = falsified
        lines = to_csv(result.trace, result.replay).splitlines()
        assert len(lines) == 1 + len(result.trace.inputs)
        assert lines[-1].endswith(",False,True")  # holds=False, violation=True on the last step

    def test_edited_trace_is_not_a_run_of_the_model(self, falsified, tmp_path):
        mutant, result = falsified
        doc = to_json(result.trace, result.replay)
        doc["final_state"]["eb_latched"] = not doc["final_state"]["eb_latched"]
        prop, trace = from_json(write(tmp_path, doc), {NAME: mutant})
        assert replay(prop, trace).problems
        with pytest.raises(ReplayError, match="the trace's"):
            reproduce(prop, trace)

    @pytest.mark.parametrize(
        ("edit", "message"),
        [
            (lambda d: d.update(violation_step=99), "field 'violation_step'"),
            (lambda d: d.update(violation_step=True), "field 'violation_step'"),
            (lambda d: d.update(steps=[]), "field 'steps'"),
            (lambda d: d.update(node="other"), "field 'node'"),
            (lambda d: d["params"].update(service_brake_fitted="yes"), "params.service_brake_fitted"),
            (lambda d: d["steps"][0]["inputs"].update(speed_mps="fast"), "steps[0].inputs.speed_mps"),
            (lambda d: d["steps"][0]["inputs"].update(speed_mps=1.5), "steps[0].inputs.speed_mps"),
            (lambda d: d["steps"][0]["inputs"].pop("ebi_mps"), "missing fields ['ebi_mps']"),
            (lambda d: d["steps"][0]["state"].update(extra=True), "unknown fields ['extra']"),
            (lambda d: d.pop("final_state"), "final_state must be an object"),
        ],
    )
    def test_malformed_file_names_field_and_value(self, falsified, tmp_path, edit, message):
        mutant, result = falsified
        doc = to_json(result.trace, result.replay)
        edit(doc)
        path = write(tmp_path, doc)
        with pytest.raises(TraceFileError) as caught:
            from_json(path, {NAME: mutant})
        assert str(caught.value).startswith(f"{path}: ")
        assert message in str(caught.value)
