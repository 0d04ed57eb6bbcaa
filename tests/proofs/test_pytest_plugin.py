"""The pytest plugin: ``pytest --atcs-prove`` collects the registered properties as items, a proved one
passes, a broken model's fails with the engine's verdict, and the plugin stays out of the way without the flag."""

from importlib.metadata import entry_points

pytest_plugins = ["pytester"]

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


def test_properties_are_items_and_a_broken_model_fails(pytester):
    pytester.makeconftest(BROKEN)  # a separate process: the registry of this session is untouched
    result = pytester.runpytest_subprocess(
        "--atcs-prove", "--atcs-only", "supervision.eb_above_ebi*", "-v", "--junitxml=report.xml"
    )
    result.assert_outcomes(passed=1, failed=1)
    result.stdout.fnmatch_lines(
        [
            "*supervision.eb_above_ebi PASSED*",
            "*supervision.eb_above_ebi_broken FAILED*",
            "*falsified: violated at step 0 (the exact replay violates it at step 0)*",
        ]
    )
    junit = (pytester.path / "report.xml").read_text()
    assert 'name="status" value="proved"' in junit and 'name="status" value="falsified"' in junit


def test_without_the_flag_nothing_is_collected(pytester):
    pytester.makepyfile("def test_plain():\n    pass\n")
    pytester.runpytest_subprocess().assert_outcomes(passed=1)


def test_a_pattern_that_matches_nothing_is_a_usage_error(pytester):
    result = pytester.runpytest_subprocess("--atcs-prove", "--atcs-only", "nosuch.*")
    assert result.ret == 4  # pytest's usage error
    result.stderr.fnmatch_lines(["*--atcs-only 'nosuch.*' matches no registered property*"])
