"""``atcs prove --config``: a configuration's properties proved in this process and in workers alike, what is not
covered said and counted as incomplete, a bad configuration one line, and a configured property that can fail."""

import json
from pathlib import Path

import pytest

from atcs.model import curves
from atcs.model.configuration import load_configuration
from atcs.proofs.cex.trace import replay, reproduce
from atcs.proofs.cli import main
from atcs.proofs.cli._common import EXIT_UNKNOWN, EXIT_USAGE
from atcs.proofs.cli.prove import SCOPE
from atcs.proofs.engine.prove import prove
from atcs.proofs.mutation.mutants import patched
from atcs.properties.configured import configuration_properties

SHIPPED = Path(__file__).parents[3] / "model" / "configurations"


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_a_configuration_is_proved(jobs, tmp_path, capsys):
    report = tmp_path / "r.json"
    argv = ["prove", "--config", str(SHIPPED / "seeds.toml"), "--only", "curves.spacing_*", "--jobs", jobs]
    assert main([*argv, "--json", str(report), "--cex-dir", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "curves.spacing_seed000_design_0" in out and "curves.spacing_seed002_design_0" in out
    assert "not covered" not in out
    assert f"scope {SCOPE}" in out and "for each speed decrease of the line's MRSP as a target" in out


def test_what_is_not_covered_is_said_and_incomplete(tmp_path, capsys):
    argv = ["prove", "--config", str(SHIPPED / "example_line.toml"), "--only", "curves.spacing_*_example_0"]
    assert main([*argv, "--cex-dir", str(tmp_path), "--json", str(tmp_path / "r.json")]) == EXIT_UNKNOWN
    out = capsys.readouterr().out
    assert "not covered lambda_passenger_P_100: the closed-loop theorems (CL-00 to CL-06) are not made" in out
    assert out.count(" proved ") == 2
    doc = json.loads((tmp_path / "r.json").read_text())
    assert doc["configuration"] == argv[2] and doc["not_covered"][0].startswith("lambda_passenger_P_100: the")


def test_a_bad_configuration_is_one_line(tmp_path, capsys):
    bad = tmp_path / "c.toml"
    bad.write_text((SHIPPED / "seeds.toml").read_text().replace("cycle_s = 0.1", "cycle_s = -1"), encoding="utf-8")
    assert main(["prove", "--config", str(bad)]) == EXIT_USAGE
    err = capsys.readouterr().err
    assert err.strip() == f"atcs: error: prove: {bad}: atp.cycle_s = -1 must be positive"


def test_an_only_matching_nothing_in_the_configuration_is_a_usage_error(capsys):
    assert main(["prove", "--config", str(SHIPPED / "seeds.toml"), "--only", "supervision.*"]) == EXIT_USAGE
    assert "--only 'supervision.*' matches no property (modules: closed_loop, curves)" in capsys.readouterr().err


def test_a_configured_property_falsified_by_a_mutant_replays():
    """A configured property is a registered one's statement over other data: the registered kind's mutant (the
    indication curve at the permitted curve) falsifies it, and the counterexample replays exactly."""
    config = load_configuration(SHIPPED / "example_line.toml")
    prop = next(p for p in configuration_properties(config) if p.name == "curves.spacing_gamma_passenger_p_example_3")
    assert prove(prop, timeout_s=120).status == "proved"
    with patched(curves.curves_from_ebd_and_ebi, "permitted - speed_mps * n.t_indication_s", "permitted"):
        result = prove(prop, timeout_s=120)
        assert result.status == "falsified", result.message
        assert reproduce(prop, result.trace).first_violation == result.k
    assert replay(prop, result.trace).first_violation is None


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_a_configuration_is_certified(jobs, tmp_path, capsys):
    argv = ["certify", "--config", str(SHIPPED / "seeds.toml"), "--only", "curves.spacing_*", "--jobs", jobs]
    assert main([*argv, "--dir", str(tmp_path / "c")]) == 0
    out = capsys.readouterr().out
    assert "curves.spacing_seed000_design_0" in out and out.count("certified") >= 2
    assert list((tmp_path / "c" / "curves.spacing_seed002_design_0").glob("*.smt2"))


def test_a_prove_report_of_a_configuration_is_read_with_it(tmp_path, capsys):
    report = tmp_path / "r.json"
    config = str(SHIPPED / "seeds.toml")
    assert main(["prove", "--config", config, "--only", "curves.spacing_seed000*", "--json", str(report)]) == 0
    assert (
        main(
            [
                "certify",
                "--config",
                config,
                "--only",
                "curves.spacing_seed000*",
                "--report",
                str(report),
                "--dir",
                str(tmp_path / "c"),
            ]
        )
        == 0
    )
    assert main(["certify", "--report", str(report), "--dir", str(tmp_path / "d")]) == EXIT_USAGE
    assert "properties[0].name = 'curves.spacing_seed000_design_0' is not a registered property" in (
        capsys.readouterr().err
    )


def test_a_train_with_a_normal_service_brake_gets_its_own_guidance_curve_proved(tmp_path):
    """CRV-12 with the train file's normal service brake (three merged speed steps here), not the design one."""
    from atcs.model.braking_data import guidance_data
    from atcs.model.node import as_dict

    train = tmp_path / "guided.toml"
    train.write_text(
        (SHIPPED.parent / "trains" / "gamma_passenger_P.toml").read_text()
        + "\n[normal_service]\na_sb01_mps2 = 0.5\na_sb12_mps2 = 0.9\nkn_plus = [{ from_kmh = 0, mps2 = 3 }]\n"
        "kn_minus = [{ from_kmh = 0, mps2 = 5 }, { from_kmh = 100, mps2 = 4 }]\n[normal_service.p]\n"
        "model_0 = [{ from_kmh = 0, mps2 = 0.4 }]\n"
        "model_1 = [{ from_kmh = 0, mps2 = 0.6 }, { from_kmh = 60, mps2 = 0.5 }]\n"
        "model_2 = [{ from_kmh = 0, mps2 = 0.7 }]\n",
        encoding="utf-8",
    )
    config = tmp_path / "c.toml"
    config.write_text(
        (SHIPPED / "seeds.toml").read_text().replace('preset = "seed002"', f'file = "{train}"'), encoding="utf-8"
    )
    loaded = load_configuration(config)
    (gui,) = [p for p in configuration_properties(loaded) if p.requirement == "CRV-12"]
    for key, value in as_dict(guidance_data(loaded.trains[1].rail)).items():
        assert gui.fixed_params[key] == value and gui.node.sizes[key] == len(value)
    assert prove(gui, timeout_s=120).status == "proved"


@pytest.mark.slow
def test_the_closed_loop_is_proved_in_each_window_of_the_line(tmp_path, capsys):
    argv = ["prove", "--config", str(SHIPPED / "seeds.toml"), "--only", "closed_loop.no_overrun_seed000_design_w*"]
    assert main([*argv, "--json", str(tmp_path / "r.json"), "--cex-dir", str(tmp_path), "--jobs", "2"]) == 0
    doc = json.loads((tmp_path / "r.json").read_text())
    statuses = {p["name"]: p["status"] for p in doc["properties"]}
    assert statuses == {f"closed_loop.no_overrun_seed000_design_w{k}": "proved" for k in range(7)}
    last = next(p for p in doc["properties"] if p["name"].endswith("_w6"))
    (window,) = [a for a in last["assumptions"] if a.startswith("the end of authority lies in")]
    assert window.startswith("the end of authority lies in [12700/3, 5000] m, the MRSP is at most the line's top")
