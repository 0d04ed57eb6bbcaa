"""``atcs vectors generate --config``: vectors of the functions of a configuration's properties, in the
environments of its trains and lines; ``verify`` re-checks them with the configuration, refuses them without it,
and reports a configuration whose data changed since."""

import json
import re
from pathlib import Path

import pytest

from atcs.proofs.cli import main
from atcs.proofs.cli._common import EXIT_FALSIFIED, EXIT_OK, EXIT_UNKNOWN, EXIT_USAGE

SEEDS = Path(__file__).parents[3] / "model" / "configurations" / "seeds.toml"


@pytest.fixture(scope="module")
def configured_vectors(tmp_path_factory):
    out = tmp_path_factory.mktemp("configured_vectors")
    code = main(["vectors", "generate", "--config", str(SEEDS), "--function", "curves", "--out", str(out)])
    assert code in (EXIT_OK, EXIT_UNKNOWN)
    return out


def test_the_vectors_are_in_the_configurations_environments(configured_vectors):
    doc = json.loads((configured_vectors / "curves.json").read_text())
    assert doc["manifest"]["configuration"]["name"] == "seeds"
    contexts = {v["context"] for v in doc["vectors"]} - {""}
    assert contexts and all(re.search(r"_design_(0|whole|w\d+)$", c) for c in contexts)
    assert doc["manifest"]["coverage"]["requirement"]["unknown"] == 0


def test_they_verify_with_the_configuration(configured_vectors, capsys):
    assert main(["vectors", "verify", str(configured_vectors), "--config", str(SEEDS)]) == EXIT_OK


def test_without_the_configuration_they_are_refused_in_one_line(configured_vectors, capsys):
    assert main(["vectors", "verify", str(configured_vectors)]) == EXIT_USAGE
    err = capsys.readouterr().err
    assert "made for the configuration 'seeds': give it with --config FILE" in err and len(err.splitlines()) == 1


def test_a_configuration_whose_data_changed_is_a_problem(configured_vectors, tmp_path, capsys):
    changed = tmp_path / "seeds.toml"
    changed.write_text(SEEDS.read_text().replace("permille = 40", "permille = 30"))
    assert main(["vectors", "verify", str(configured_vectors), "--config", str(changed)]) == EXIT_FALSIFIED
    assert "the configuration's data for curves changed since the vectors were made" in capsys.readouterr().out


def test_a_function_not_of_the_configuration_is_a_usage_error(tmp_path, capsys):
    argv = ["vectors", "generate", "--config", str(SEEDS), "--function", "supervision", "--out", str(tmp_path)]
    assert main(argv) == EXIT_USAGE
    err = capsys.readouterr().err
    listed = "(functions: curves, prepared_curves, table_order, closed_loop"
    assert "'supervision' is not a function of the configuration's properties " + listed in err
