"""Proof coverage: what it counts, what a property's terms reach, the allowlist, and the whole model."""

from __future__ import annotations

import json

import pytest

from atcs.model.authority import STOPPING_POINT
from atcs.proofs import coverage
from atcs.proofs.cli import main
from atcs.proofs.coverage.sites import Site, module_sites, statement_lines
from atcs.properties import PROPERTIES, Property
from tests.proofs.cli.test_errors import one_line

SOURCE = '''
"""A module."""
from x import y


def step(o, p, s, i):
    """A docstring, not a line."""
    speed = (
        i.speed_mps
        + p.margin
    )
    if o.and_(speed > p.limit, s.on):
        return o.ite(
            speed > p.limit, speed, p.limit
        )

    def inner(v):
        return o.or_(v, v)

    return inner(speed)


INIT = lambda o, p, s: o.and_(s.on, s.on)


class Record:
    def total(self):
        return 1
'''


@pytest.fixture
def sample(tmp_path):
    path = tmp_path / "sample.py"
    path.write_text(SOURCE)
    return path


# --- what is counted --------------------------------------------------------------------------------------------


def test_statements_and_decisions_of_functions_are_sites_and_docstrings_and_module_code_are_not(sample):
    sites = {(s.function, s.line, s.kind) for s in module_sites("m", sample)}
    assert sites == {
        ("step", 8, "line"),
        ("step", 12, "line"),
        ("step", 12, "and_"),
        ("step", 13, "line"),
        ("step", 13, "ite"),
        ("step", 17, "line"),  # the nested def is a statement of step's
        ("step.<locals>.inner", 18, "line"),
        ("step.<locals>.inner", 18, "or_"),
        ("step", 20, "line"),
        ("<lambda>", 23, "line"),
        ("<lambda>", 23, "and_"),
        ("Record.total", 28, "line"),
    }


def test_a_statement_over_several_lines_is_counted_at_its_first(sample, monkeypatch):
    monkeypatch.setattr(coverage.sites, "model_modules", lambda: {"m": sample})
    statement_lines.cache_clear()
    try:
        owner = statement_lines("m")
    finally:
        statement_lines.cache_clear()
    assert [owner[line] for line in (8, 9, 10, 11)] == [8, 8, 8, 8]
    assert [owner[line] for line in (13, 14, 15)] == [13, 13, 13]
    assert 6 not in owner  # the def line is the module's, not step's


def test_every_model_module_but_the_backends_is_in_scope():
    modules = coverage.model_modules()
    assert "atcs.model.authority" in modules and "atcs.model.railml" in modules
    assert not [m for m in modules if m.startswith("atcs.model.ops")]
    assert all(path.exists() for path in modules.values())


# --- what a property's terms reach ------------------------------------------------------------------------------


def _stopping_point_property(holds) -> Property:
    return Property(name="coverage.probe", requirement="COV-T", seed="-", text="-", node=STOPPING_POINT, holds=holds)


def test_a_property_reaches_its_nodes_step_and_the_functions_it_calls():
    prop = _stopping_point_property(lambda o, p, s, i, out, nxt: out.stop_m >= i.rear_m)
    (reached,) = coverage.reach_node([prop])
    lines = {line for module, line in reached.lines if module == "atcs.model.authority"}
    lines_of = {s.line for s in coverage.all_sites() if s.kind == "line"}
    step = [s.line for s in coverage.all_sites() if s.function in ("stopping_point_step", "stopping_point_m")]
    assert set(step) & lines_of <= lines
    locked = [s.line for s in coverage.all_sites() if s.function == "locked_end_m" and s.kind == "line"]
    assert not set(locked) & lines  # the authority's own step is not this node's


def test_the_decisions_a_property_reaches_are_the_ops_calls_its_terms_make():
    (reached,) = coverage.reach_node([PROPERTIES["authority.locked_end_is_first_blocked"]])
    sites = {(s.module, s.line, s.kind) for s in coverage.all_sites() if s.kind != "line"}
    assert reached.decisions <= sites
    confirmed = {(s.line, s.kind) for s in coverage.all_sites() if s.function == "confirmed" and s.kind != "line"}
    assert confirmed and confirmed <= {(line, kind) for module, line, kind in reached.decisions}


def test_properties_of_one_node_share_its_step_and_keep_their_own_predicates():
    a, b = (PROPERTIES[n] for n in ("authority.within_held_resources", "authority.freshest_report_kept"))
    first, second = coverage.reach_node([a, b])
    step = {s.line for s in coverage.all_sites() if s.function == "authority_step" and s.kind == "line"}
    for reached in (first, second):
        assert step <= {line for module, line in reached.lines if module == "atcs.model.authority"}


# --- the allowlist ------------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("[[allow]]\nfunctions = 'atcs.model.x.*'\n", "expected the keys functions and reason, got ['functions']"),
        ("[[allow]]\nfunctions = 'atcs.model.x.*'\nreason = ' '\n", "reason must be a non-empty string, got ' '"),
        ("[[allow]]\nfunctions = 'sim.*'\nreason = 'r'\n", "must name model code (atcs.model.*), got 'sim.*'"),
        ("colour = 1\n", "expected only [[allow]] tables, got the keys ['colour']"),
        ("[[allow]\n", "not valid TOML"),
    ],
    ids=["no reason", "blank reason", "not model code", "unknown key", "not toml"],
)
def test_a_malformed_allowlist_is_refused_naming_the_file_the_entry_and_the_value(tmp_path, text, message):
    path = tmp_path / "a.toml"
    path.write_text(text)
    with pytest.raises(coverage.AllowlistError) as error:
        coverage.load_allowlist(path)
    assert str(error.value).startswith(str(path)) and message in str(error.value)


def test_an_allowance_covers_only_sites_no_property_reaches_and_a_stale_one_is_reported():
    site_a = Site("atcs.model.m", "f", 1)
    site_b = Site("atcs.model.m", "g", 2)
    reached = coverage.Reached("p", frozenset({("atcs.model.m", 1)}), frozenset())
    allow_f = coverage.Allowance("atcs.model.m.f", "reached anyway")
    allow_g = coverage.Allowance("atcs.model.m.g", "OPEN: not yet")
    result = coverage.Coverage((site_a, site_b), (reached,), (allow_f, allow_g))
    assert result.properties_at(site_a) == ["p"] and result.allowance(site_a) is None
    assert result.allowance(site_b) is allow_g and allow_g.open
    assert result.unreached() == [] and result.unused_allowances() == [allow_f]
    (row,) = result.modules()
    assert (row.lines_reached, row.lines, row.allowlisted, row.open, row.unreached) == (1, 2, 1, 1, 0)
    bare = coverage.Coverage((site_a, site_b), (reached,), ())
    assert bare.unreached() == [site_b]


# --- the whole model ----------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def whole_model():
    return coverage.measure(PROPERTIES.values())


def test_every_line_and_decision_of_the_model_is_reached_by_a_property_or_allowlisted(whole_model):
    assert [s.where for s in whole_model.unreached()] == []


def test_every_allowlist_entry_covers_code_no_property_reaches(whole_model):
    assert [a.functions for a in whole_model.unused_allowances()] == []


def test_every_line_and_decision_a_property_reaches_is_a_counted_site(whole_model):
    lines = {(s.module, s.line) for s in whole_model.sites if s.kind == "line"}
    decisions = {(s.module, s.line, s.kind) for s in whole_model.sites if s.kind != "line"}
    for reached in whole_model.reached:
        assert reached.lines <= lines, reached.property
        assert reached.decisions <= decisions, reached.property


def test_each_step_function_of_a_registered_node_is_reached_by_its_properties(whole_model):
    for prop in PROPERTIES.values():
        step = prop.node.step
        module = step.__module__
        first = step.__code__.co_firstlineno
        lines = [
            s.line
            for s in whole_model.sites
            if s.module == module and s.function == step.__qualname__ and s.kind == "line"
        ]
        reached = {line for m, line in next(r for r in whole_model.reached if r.property == prop.name).lines}
        assert lines and set(lines) <= reached, (prop.name, step.__qualname__, first)


# --- the command line ---------------------------------------------------------------------------------------------


def test_the_command_counts_the_authority_properties_alone_and_names_what_they_leave(tmp_path, capsys):
    report, annotated = tmp_path / "c.json", tmp_path / "annotated"
    code = main(["coverage", "--only", "authority.*", "--json", str(report), "--annotate", str(annotated)])
    assert code == 1  # the other nodes' code is reached by no selected property
    out = capsys.readouterr().out
    assert "unreached atcs.model.supervision.supervise" in out
    doc = json.loads(report.read_text())
    assert doc["tool"] == "atcs coverage" and len(doc["properties"]) == 14
    row = next(m for m in doc["modules"] if m["module"] == "atcs.model.authority")
    assert row["lines_reached"] == row["lines"] - 1  # all but the stopping-point node's own step
    site = next(s for s in doc["sites"] if s["function"] == "locked_end_m" and s["kind"] == "ite")
    assert "authority.locked_end_is_first_blocked" in site["properties"]
    text = (annotated / "atcs.model.authority.txt").read_text().splitlines()
    line = text[site["line"] - 1]
    gutter = line.split("|")[0].split()
    assert gutter[0] == "14" and "ite:14" in gutter and "o.ite(" in line  # the line, then each decision on it


def test_the_command_counts_only_the_properties_a_prove_report_gives_as_proved(tmp_path, capsys):
    report = tmp_path / "r.json"
    records = [
        {"name": "authority.within_held_resources", "status": "proved"},
        {"name": "authority.behind_leader", "status": "unknown"},
    ]
    report.write_text(json.dumps({"properties": records}))
    out_json = tmp_path / "c.json"
    assert main(["coverage", "--only", "authority.*", "--report", str(report), "--json", str(out_json)]) == 1
    assert json.loads(out_json.read_text())["properties"] == ["authority.within_held_resources"]


def test_a_prove_report_that_is_not_one_is_refused_naming_it(tmp_path, capsys):
    report = tmp_path / "r.json"
    report.write_text(json.dumps({"properties": [{"status": "proved"}]}))
    assert main(["coverage", "--report", str(report)]) == 2
    line = one_line(capsys, "atcs: error: coverage: --report ")
    assert f"{report}: properties[0] = {{'status': 'proved'}} has no name and status" in line
