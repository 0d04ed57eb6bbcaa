"""Counterexample traces: exact values in files, readable values on screen and in the CSV, round trips, and files
that were edited or are malformed."""

import csv
import io
import json
import re
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
    readable_value,
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

    @pytest.mark.parametrize(
        ("value", "text"),
        [
            (Fraction(1, 10), "0.1"),
            (Fraction(-5, 4), "-1.25"),
            (Fraction(10**6), "1000000"),
            (Fraction(1, 3), "0.333333 (1/3)"),
            (Fraction(81757, 49152), "1.66335 (81757/49152)"),
            (Fraction(1234567), "1.23457e+6 (1234567)"),
            (Fraction(1, 10) - Fraction(1, 10**30), "0.1 (0.099999999999999999999999999999)"),
            (True, "True"),
            ((Fraction(1), Fraction(1, 3)), "[1, 0.333333 (1/3)]"),
        ],
    )
    def test_readable_decimal_with_the_exact_value_when_it_differs(self, value, text):
        assert readable_value(value) == text

    @given(st.fractions())
    def test_readable_value_rounds_to_six_digits_and_keeps_the_exact_one(self, value):
        text = readable_value(value)
        shown, exact = re.fullmatch(r"(\S+)(?: \((\S+)\))?", text).groups()
        assert Fraction(exact or shown) == value
        assert abs(Fraction(shown) - value) <= Fraction(5, 10**6) * abs(value)
        assert (exact is None) == (Fraction(shown) == value)


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

    def test_csv_numbers_are_the_decimals_of_the_nearest_doubles(self, falsified):
        _, result = falsified
        trace = result.trace
        third = dict(trace.inputs[0], speed_mps=Fraction(1, 3), permitted_mps=Fraction(7))
        edited = type(trace)(trace.property, trace.node, 0, trace.params, trace.states[:2], [third])
        rows = list(csv.DictReader(io.StringIO(to_csv(edited, result.replay))))
        assert rows[0]["input.speed_mps"] == "0.3333333333333333" and rows[0]["input.permitted_mps"] == "7"
        for name, value in third.items():
            cell = rows[0][f"input.{name}"]
            assert cell == str(value) if isinstance(value, bool) else float(cell) == float(value)

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
