"""railML 3 import (docs/configuration.md#railml-3-import): the design line of the seeds' configuration read from
railML gives the same line, so the same properties and verdicts; the elements not used are listed; every file
that cannot be read is refused naming the element, the attribute and the value."""

import dataclasses
import re
from pathlib import Path

import pytest

from atcs.model.configuration import load_configuration
from atcs.model.railml import RailmlError, import_line, line_toml
from atcs.proofs.cli import main
from atcs.proofs.cli._common import EXIT_USAGE
from atcs.properties.configured import configuration_properties

DATA = Path(__file__).parent / "data"
LINE = DATA / "design_line.railml"
SEEDS = Path(__file__).parents[2] / "model" / "configurations" / "seeds.toml"


def _with_imported_line(tmp_path) -> Path:
    text = SEEDS.read_text(encoding="utf-8")
    path = tmp_path / "imported.toml"
    path.write_text(text[: text.index("[[lines]]")] + line_toml(import_line(LINE, "design")), encoding="utf-8")
    return path


def test_the_imported_line_is_the_hand_written_one(tmp_path):
    imported, written = load_configuration(_with_imported_line(tmp_path)), load_configuration(SEEDS)
    assert tuple(dataclasses.replace(line, platforms=()) for line in imported.lines) == written.lines


def test_a_platform_edge_is_a_platform_of_the_line(tmp_path):
    (platform,) = load_configuration(_with_imported_line(tmp_path)).lines[0].platforms
    assert (platform.start_m, platform.end_m, platform.side, platform.height_mm) == (3500, 3700, "right", 760)


@pytest.mark.slow
def test_the_imported_line_gives_the_same_properties_and_verdicts(tmp_path, capsys):
    imported = {p.name: p for p in configuration_properties(load_configuration(_with_imported_line(tmp_path)))}
    written = {p.name: p for p in configuration_properties(load_configuration(SEEDS))}
    assert imported.keys() == written.keys()
    assert all(imported[n].fixed_params == written[n].fixed_params for n in written)
    only = ["--only", "curves.ebd_is_braking_curve_seed000_design_*", "--only", "closed_loop.*_seed000_design_w6"]
    assert main(["prove", "--config", str(_with_imported_line(tmp_path)), *only, "--cex-dir", str(tmp_path)]) == 0
    assert main(["prove", "--config", str(SEEDS), *only, "--cex-dir", str(tmp_path)]) == 0
    rows = [line.split("│")[1:4] for line in capsys.readouterr().out.splitlines() if "_design_" in line]
    assert len(rows) == 2 * 14 and rows[:14] == rows[14:]  # 2 CRV-08, CL-00 to CL-10 (two CL-07s) each
    assert {row[2].strip() for row in rows} == {"proved"}


def test_a_platform_edge_for_the_other_direction_only_is_left_out(tmp_path):
    path = tmp_path / "reverse.railml"
    path.write_text(
        TEXT.replace('id="pe1_loc" applicationDirection="both"', 'id="pe1_loc" applicationDirection="reverse"')
    )
    assert import_line(path, "x").platforms == ()


def test_elements_not_used_are_listed():
    assert import_line(LINE, "design").not_used == (
        ("balise", 2),
        ("signalIS", 1),
        ("switchIS", 1),
    )


def test_the_cli_writes_the_table_and_lists_what_it_leaves_out(tmp_path, capsys):
    out = tmp_path / "line.toml"
    assert main(["railml", str(LINE), "--name", "design", "--out", str(out)]) == 0
    captured = capsys.readouterr()
    assert out.read_text() == line_toml(import_line(LINE, "design"))
    assert "not used: 2 <balise>" in captured.err and "not used: 1 <switchIS>" in captured.err


TEXT = LINE.read_text(encoding="utf-8")
SP1 = '<linearLocation id="sp1_loc" applicationDirection="both">\n            <associatedNetElement netElementRef="ne1"'
"""The speed section on ne1's location, up to its associatedNetElement's attributes."""
ON_NE1 = ' keepsOrientation="true" posBegin="0" posEnd="1000"/>'
NE1_TO_NE3 = (
    '<netRelation id="nr13" positionOnA="1" positionOnB="0"><elementA ref="ne1"/><elementB ref="ne3"/></netRelation>'
)
BY_MILEAGE = (
    ' keepsOrientation="true"><linearCoordinateBegin positioningSystemRef="l" measure="0"/></associatedNetElement>'
)


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        (
            '<netElement id="ne2" length="1500">',
            '<netElement id="ne2">',
            "<netElement id='ne2'> length = None is missing",
        ),
        ('length="1500"', 'length="x"', "<netElement id='ne2'> length = 'x' is not a number"),
        ('length="1500"', 'length="-1"', "<netElement id='ne2'> length = '-1' must be positive"),
        ('id="sp1" maxSpeed="80"', 'id="sp1"', "<speedSection id='sp1'> maxSpeed = None is missing"),
        ('id="sp1" maxSpeed="80"', 'id="sp1" maxSpeed="end"', "<speedSection id='sp1'> maxSpeed = 'end' (the end of"),
        (SP1 + ON_NE1, SP1 + ON_NE1.replace("1000", "900"), "no <speedSection> covers the line from 900 m to 1000 m"),
        (SP1 + ON_NE1, SP1 + ON_NE1.replace("1000", "1100"), "posEnd = '1100' lies outside 'ne1' (0 to 1000 m)"),
        (SP1 + ON_NE1, SP1 + BY_MILEAGE, "posBegin = None is missing: a location by linear coordinates alone is not"),
        ('curveType="arc"', 'curveType="clothoid"', "<gradientCurve id='gc2'> curveType = 'clothoid' must be"),
        ('gradient="-40"', 'gradientX="-40"', "<gradientCurve id='gc1'> gradient = None is missing"),
        (
            '<netRelation id="nr12"',
            NE1_TO_NE3 + '<netRelation id="nr12"',
            "the topology branches after net element 'ne1'",
        ),
        ('height="0.76"', 'height="760"', "<platformEdge id='pe1'> height = '760' is outside (0, 2] m (railML gives"),
        ('measure="3500" lateralSide="right"', 'measure="3500"', "<linearCoordinateBegin> lateralSide = None must be"),
        ('measure="3700" lateralSide="right"', 'measure="3700" lateralSide="left"', "lateralSide = None differs along"),
        ("schemas/3.2", "schemas/2.4", "not <railML> of railML 3.1 or 3.2"),
        ("</railML>", "</railm>", "not well-formed XML"),
    ],
)
def test_bad_files_are_named(tmp_path, old, new, message):
    assert old in TEXT
    path = tmp_path / "bad.railml"
    path.write_text(TEXT.replace(old, new, 1), encoding="utf-8")
    with pytest.raises(RailmlError, match=re.escape(message)) as caught:
        import_line(path, "x")
    assert str(caught.value).startswith(str(path))


def test_a_bad_file_is_one_line_exit_2(tmp_path, capsys):
    path = tmp_path / "bad.railml"
    path.write_bytes(b"\xff\xfe not xml")
    assert main(["railml", str(path), "--name", "x"]) == EXIT_USAGE
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and err.startswith(f"atcs: error: railml: {path}: not well-formed XML")


def test_net_elements_in_order_are_checked(tmp_path):
    assert import_line(LINE, "d", ["ne1", "ne2", "ne3"]).length_m == 5000
    with pytest.raises(RailmlError, match="no <netRelation> joins the end of 'ne2' to the start of 'ne1'"):
        import_line(LINE, "d", ["ne2", "ne1"])
    with pytest.raises(RailmlError, match="--net-elements names 'ne9', which is no net element with a length"):
        import_line(LINE, "d", ["ne9"])
