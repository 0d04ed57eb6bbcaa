"""railML 3 import (docs/configuration.md#railml-3-import): the design line of the seeds' configuration read from
railML gives the same line, so the same properties and verdicts; the elements not used are listed; every file
that cannot be read is refused naming the element, the attribute and the value."""

import dataclasses
import re
from fractions import Fraction
from pathlib import Path

import pytest

from atcs.model.configuration import load_configuration
from atcs.model.railml import RailmlError, import_line, line_toml
from atcs.proofs.cli import main
from atcs.proofs.cli._common import EXIT_USAGE
from atcs.properties.configured import configuration_properties
from atcs.sim.scenario import load_scenario
from atcs.sim.simulator import Simulation
from tests.sim.test_switches import ATP_ATO

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
    assert tuple(dataclasses.replace(line, platforms=(), tags=None) for line in imported.lines) == written.lines


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
    # every property's fixed parameters are the written line's, so its obligations are the same: proved once, here
    assert main(["prove", "--config", str(_with_imported_line(tmp_path)), *only, "--cex-dir", str(tmp_path)]) == 0
    rows = [line.split("│")[1:4] for line in capsys.readouterr().out.splitlines() if "_design_" in line]
    assert len(rows) == 14  # 2 CRV-08, CL-00 to CL-10 (two CL-07s)
    assert {row[2].strip() for row in rows} == {"proved"}


def test_a_platform_edge_for_the_other_direction_only_is_left_out(tmp_path):
    path = tmp_path / "reverse.railml"
    path.write_text(
        TEXT.replace('id="pe1_loc" applicationDirection="both"', 'id="pe1_loc" applicationDirection="reverse"')
    )
    assert import_line(path, "x").platforms == ()


def test_elements_not_used_are_listed():
    assert import_line(LINE, "design").not_used == (("<signalIS>", 1), ("<switchIS> the line does not run through", 1))


def test_balises_of_no_group_are_tags_numbered_in_line_order():
    assert import_line(LINE, "design").tags == ((200, 1, "bal1"), (1200, 2, "bal2"))


def test_the_cli_writes_the_table_and_lists_what_it_leaves_out(tmp_path, capsys):
    out = tmp_path / "line.toml"
    assert main(["railml", str(LINE), "--name", "design", "--out", str(out)]) == 0
    captured = capsys.readouterr()
    assert out.read_text() == line_toml(import_line(LINE, "design"))
    assert "not used: 1 <signalIS>" in captured.err and "not used: 1 <switchIS> the line does not" in captured.err


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


JUNCTION = DATA / "junction_line.railml"
JUNCTION_TEXT = JUNCTION.read_text(encoding="utf-8")
ORDER = ["a", "b", "c"]


def test_balise_groups_are_tags_with_their_nid_bg():
    line = import_line(JUNCTION, "junction", ORDER)
    assert line.tags == ((300, 101, "bg1"), (1200, 102, "bg2"), (2300, 103, "bg3"))  # bg2 at its first balise
    assert line.not_used == (("<balise> (group) off the line", 1),)  # bg9, on the siding


def test_the_switches_the_line_runs_through_are_its_switch_resources():
    line = import_line(JUNCTION, "junction", ORDER)
    assert line.resources == (
        (0, 1000, "track", None, None),
        (1000, 1060, "switch", "reverse", "swA"),  # facing: its branch's 60 m after the junction; the branch course
        (1060, 1540, "track", None, None),
        (1540, 1600, "switch", "normal", "swB"),  # trailing, by its linear location; the continue course
        (1600, 3000, "track", None, None),
    )


def test_a_train_runs_the_imported_junction_line_through_both_switches(tmp_path):
    config = tmp_path / "junction.toml"
    table = line_toml(import_line(JUNCTION, "junction", ORDER), Fraction(6))
    config.write_text('name = "j"\n[[trains]]\npreset = "seed000"\n' + table, encoding="utf-8")
    (line,) = load_configuration(config).lines
    assert line.tags.ids == (101, 102, 103) and [r.direction for r in line.resources if r.is_switch] == [
        "reverse",
        "normal",
    ]
    scenario = tmp_path / "run.toml"
    scenario.write_text(JUNCTION_RUN, encoding="utf-8")
    sim = Simulation(load_scenario(scenario)).run()  # a violation raises
    assert sim.switch_reversed == [False, True, False, False, False] and sim.trains[0].front_m > 2900


JUNCTION_RUN = f"""name = "junction"
seed = "001 §3.2"
duration_s = 200
cycle_s = 0.1
[line]
configuration = "junction.toml"
max_ma_m = 1500
{ATP_ATO}[[trains]]
front_m = 300
max_speed_kmh = 100
"""
"""A seed 000 train from the junction line's first tag to its end, through both switches."""


def test_the_cli_needs_the_throw_time_for_a_line_with_switches(tmp_path, capsys):
    out = tmp_path / "line.toml"
    base = ["railml", str(JUNCTION), "--name", "j", "--net-elements", "a,b,c", "--out", str(out)]
    assert main(base) == EXIT_USAGE
    assert "runs through 2 switches: give --switch-throw-s" in capsys.readouterr().err
    assert main([*base, "--switch-throw-s", "61"]) == EXIT_USAGE
    assert main([*base, "--switch-throw-s", "6"]) == 0
    assert "switch_throw_s = 6" in out.read_text()
    assert main(["railml", str(LINE), "--name", "d", "--switch-throw-s", "6"]) == EXIT_USAGE
    assert "--switch-throw-s is given, but the line runs through no switch" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ('continueCourse="right" branchCourse="left"', "", "<switchIS id='swA'> continueCourse = None is missing"),
        ('continueCourse="right"', 'continueCourse="up"', "<switchIS id='swA'> continueCourse = 'up' must be left or"),
        (
            'radius="-500" length="60"',
            'radius="-500"',
            "<leftBranch> length = None is missing, and so is the switch's linearLocation",
        ),
        ('radius="-500" length="60"', 'length="1e9"', "<leftBranch> length = '1e9' is out of range"),
        ('radius="-500" length="60"', 'length="2100"', "<leftBranch> length = '2100' takes the switch off the line"),
        ('<leftBranch netRelationRef="nr_bc"', "<leftBranch", "<leftBranch> netRelationRef = None is missing"),
        ('groupID="102"', 'groupID="101"', "<isEurobaliseGroup> groupID = '101' is the id of another balise group"),
        ('groupID="102"', 'groupID="99999"', "groupID = '99999' is not NID_BG, a whole number from 0 to 16383"),
        (
            'belongsToBaliseGroup="bg2"><spotLocation id="b2a',
            'belongsToBaliseGroup="bgX"><spotLocation id="b2a',
            "<balise id='b2a'> belongsToBaliseGroup = 'bgX' names no balise group",
        ),
        (
            'netElementRef="c" applicationDirection="normal" intrinsicCoord="0.5"',
            'netElementRef="c"',
            "<spotLocation id='bg3_loc'> pos = None is missing (and intrinsicCoord)",
        ),
        ('pos="300"', 'pos="1200"', "<spotLocation id='bg1_loc'> pos = '1200' lies outside 'a' (0 to 1000 m)"),
        (
            'posBegin="540" posEnd="600"',
            'posBegin="30" posEnd="600"',
            "<switchIS id='swB'> overlaps <switchIS id='swA'>",
        ),
    ],
)
def test_bad_balises_and_switches_are_named(tmp_path, old, new, message):
    assert old in JUNCTION_TEXT
    path = tmp_path / "bad.railml"
    path.write_text(JUNCTION_TEXT.replace(old, new, 1), encoding="utf-8")
    with pytest.raises(RailmlError, match=re.escape(message)) as caught:
        import_line(path, "x", ORDER)
    assert str(caught.value).startswith(str(path))


def test_a_switch_with_no_extent_takes_the_users_length(tmp_path):
    path = tmp_path / "spot_only.railml"
    path.write_text(JUNCTION_TEXT.replace('radius="-500" length="60"', 'radius="-500"'), encoding="utf-8")
    line = import_line(path, "j", ORDER, switch_length_m=Fraction(45))
    assert line.resources[1] == (1000, 1045, "switch", "reverse", "swA")
    out = tmp_path / "line.toml"
    base = ["railml", str(path), "--name", "j", "--net-elements", "a,b,c", "--switch-throw-s", "6", "--out", str(out)]
    assert main([*base, "--switch-length-m", "45"]) == 0 and "end_m = 1045" in out.read_text()
    for bad in ("0", "1e300000000", "x", "501"):
        assert main([*base, "--switch-length-m", bad]) == EXIT_USAGE


def test_railml_31_balise_groups_fold_their_balises(tmp_path):
    groups = JUNCTION_TEXT[
        JUNCTION_TEXT.index("<baliseGroups>") : JUNCTION_TEXT.index("</balises>") + len("</balises>")
    ]
    old_style = """<balises>
        <balise id="g1" isBaliseGroup="1"><spotLocation id="g1_loc" netElementRef="a" pos="300"/></balise>
        <balise id="g1a" belongsToParent="g1"><spotLocation id="g1a_loc" netElementRef="a" pos="300"/></balise>
        <balise id="g1b" belongsToParent="g1"><spotLocation id="g1b_loc" netElementRef="a" pos="303"/></balise>
        <balise id="lone"><spotLocation id="lone_loc" netElementRef="c" pos="100"/></balise>
      </balises>"""
    path = tmp_path / "v31.railml"
    path.write_text(JUNCTION_TEXT.replace(groups, old_style), encoding="utf-8")
    assert import_line(path, "j", ORDER).tags == ((300, 1, "g1"), (1700, 2, "lone"))


def test_a_country_id_outside_nid_c_is_refused(tmp_path):
    path = tmp_path / "bad.railml"
    path.write_text(JUNCTION_TEXT.replace('countryID="80" groupID="102"', 'countryID="1024" groupID="102"'))
    with pytest.raises(RailmlError, match=re.escape("countryID = '1024' is not NID_C, a whole number from 0 to 1023")):
        import_line(path, "j", ORDER)
