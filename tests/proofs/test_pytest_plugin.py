"""The pytest plugin: ``pytest --atcs-prove`` collects the registered properties as items, counted like any test,
a proved one passes, a broken model's fails with the engine's verdict and its counterexample file, and the plugin
stays out of the way without the flag."""

import json
import re
import tomllib
from importlib.metadata import entry_points
from pathlib import Path

import pytest

pytest_plugins = ["pytester"]

ROOT = Path(__file__).resolve().parents[2]

BROKEN = """
import dataclasses

from atcs.proofs.mutation.mutants import mutant_property
from atcs.properties import PROPERTIES

# the EB command compares the speed with the EBI plus 1 m/s (tests/model/test_supervision.py's mutant)
broken = mutant_property(PROPERTIES["supervision.eb_above_ebi"], "over_ebi=i.speed_mps > i.ebi_mps",
                         "over_ebi=i.speed_mps > i.ebi_mps + o.const(1)")
PROPERTIES["supervision.eb_above_ebi_broken"] = dataclasses.replace(broken, name="supervision.eb_above_ebi_broken")
"""


def test_the_plugin_is_installed_as_an_entry_point():
    plugins = {e.name: e.value for e in entry_points(group="pytest11")}
    assert plugins.get("atcs") == "atcs.proofs.pytest_plugin"


def test_the_documented_extra_installs_pytest():
    section = (ROOT / "docs" / "proofs.md").read_text().split("## The pytest plugin")[1].split("\n## ")[0]
    (extra,) = re.findall(r"pip install -e '\.\[(\w+)\]'", section)
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    assert any(re.match(r"pytest\b", requirement) for requirement in extras[extra])


def test_properties_are_items_and_a_broken_model_fails(pytester):
    pytester.makeconftest(BROKEN)  # a separate process: the registry of this session is untouched
    result = pytester.runpytest_subprocess(
        "--atcs-prove", "--atcs-only", "supervision.eb_above_ebi*", "-v", "--junitxml=report.xml"
    )
    result.assert_outcomes(passed=1, failed=1)
    result.stdout.fnmatch_lines(
        [
            "*collected 2 items",
            "*supervision.eb_above_ebi PASSED*",
            "*supervision.eb_above_ebi_broken FAILED*",
            "*falsified: violated at step 0 (the exact replay violates it at step 0); "
            "counterexample: counterexamples/supervision.eb_above_ebi_broken.json",
        ]
    )
    junit = (pytester.path / "report.xml").read_text()
    assert 'name="status" value="proved"' in junit and 'name="status" value="falsified"' in junit
    assert 'name="counterexample" value="counterexamples/supervision.eb_above_ebi_broken.json"' in junit


def test_counterexample_files_as_atcs_prove_writes_them(pytester):
    pytester.makeconftest(BROKEN)
    result = pytester.runpytest_subprocess(
        "--atcs-prove", "--atcs-only", "supervision.eb_above_ebi_broken", "--atcs-cex-dir", "out/cex"
    )
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(["*counterexample: out/cex/supervision.eb_above_ebi_broken.json"])
    cex = pytester.path / "out" / "cex"
    assert sorted(p.name for p in cex.iterdir()) == [
        f"supervision.eb_above_ebi_broken.{suffix}" for suffix in ("csv", "json", "png", "vcd")
    ]
    doc = json.loads((cex / "supervision.eb_above_ebi_broken.json").read_text())
    assert doc["property"] == "supervision.eb_above_ebi_broken" and doc["violation_step"] == 0


def test_a_proved_property_writes_no_counterexample(pytester):
    pytester.runpytest_subprocess("--atcs-prove", "--atcs-only", "supervision.eb_above_ebi").assert_outcomes(passed=1)
    assert not (pytester.path / "counterexamples").exists()


def test_only_is_repeatable_and_selects_the_union(pytester):
    result = pytester.runpytest_subprocess(
        "--atcs-prove",
        "--atcs-only",
        "supervision.eb_above_ebi",
        "--atcs-only",
        "supervision.eb_latched*",
        "--co",
        "-q",
    )
    result.stdout.fnmatch_lines(
        [
            "atcs-proofs::supervision.eb_above_ebi",
            "atcs-proofs::supervision.eb_latched_until_standstill",
            "2 tests collected*",
        ]
    )


@pytest.mark.parametrize(
    ("options", "header"),
    [
        ([], "collected 2 items"),
        (["-k", "eb_latched"], "collected 2 items / 1 deselected / 1 selected"),
    ],
)
def test_the_header_counts_the_properties_with_the_tests(pytester, options, header):
    pytester.makepyfile("def test_plain():\n    pass\n")
    result = pytester.runpytest_subprocess("--atcs-prove", "--atcs-only", "supervision.eb_latched*", "--co", *options)
    result.stdout.fnmatch_lines([header])


def test_without_the_flag_nothing_is_collected(pytester):
    pytester.makepyfile("def test_plain():\n    pass\n")
    pytester.runpytest_subprocess().assert_outcomes(passed=1)


def test_a_pattern_that_matches_nothing_is_a_usage_error(pytester):
    result = pytester.runpytest_subprocess("--atcs-prove", "--atcs-only", "nosuch.*")
    assert result.ret == 4  # pytest's usage error
    result.stderr.fnmatch_lines(["*--atcs-only 'nosuch.*' matches no registered property*"])


def test_an_unwritable_counterexample_directory_is_a_usage_error(pytester):
    (pytester.path / "taken").write_text("a file")
    result = pytester.runpytest_subprocess("--atcs-prove", "--atcs-cex-dir", "taken")
    assert result.ret == 4
    result.stderr.fnmatch_lines(["*--atcs-cex-dir taken: exists and is not a directory*"])
