"""The bad-input corpus: one case per class of bad input on each surface that reads it, each refused with exit 2 and
one line naming the file (or the option), the field and the value: never a traceback, an internal error or a hang.

Classes: a file that is not UTF-8 text; a number too large to read (``1e300000000``, which an exact reader would
expand into 300 million digits; ``1e5000``, beyond every float).
"""

from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path

import pytest

from atcs.proofs.cli import main
from atcs.properties import PROPERTIES
from tests.proofs.cli.test_errors import one_line

ROOT = Path(__file__).parents[3]
SCENARIO = ROOT / "sim" / "scenarios" / "seed000_normal.toml"
CONFIGURATION = ROOT / "model" / "configurations" / "seeds.toml"
TRAIN = ROOT / "model" / "trains" / "gamma_passenger_P.toml"
RAILML = ROOT / "tests" / "model" / "data" / "junction_line.railml"
PLATFORMS = """
[[platforms.table]]
start_m = 100
length_m = 200
side = "left"
height_mm = 760
"""
NOT_UTF8 = b"\xff\xfe\x00 not text"
HUGE = ("1e300000000", "1e5000")


def _trace(prop_name: str, **inputs) -> dict:
    """A counterexample file of one step of ``prop_name``'s node, every value 0 or false but ``inputs``."""
    node = PROPERTIES[prop_name].node

    def record(part: str, given: dict) -> dict:
        def value(sort):
            one = False if sort.kind == "bool" else "0"
            return one if sort.size is None else [one] * sort.size

        assert set(given) <= set(node.sorts(part)), given
        return {name: given.get(name, value(sort)) for name, sort in node.sorts(part).items()}

    return {
        "format": "atcs-trace/1",
        "property": prop_name,
        "node": node.name,
        "violation_step": 0,
        "params": record("params", {}),
        "steps": [{"state": record("state", {}), "inputs": record("inputs", inputs)}],
        "final_state": record("state", {}),
    }


def _write(tmp_path: Path, name: str, content: str | bytes) -> Path:
    path = tmp_path / name
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content, encoding="utf-8")
    return path


def _edited(source: Path, old: str, new: str) -> str:
    text = source.read_text(encoding="utf-8")
    assert old in text, (source, old)
    return text.replace(old, new, 1)


# --- each surface that reads a file: (argv with {file}, the file's name) ----------------------------------------

FILE_SURFACES = {
    "scenario": (["sim", "{file}"], "s.toml"),
    "configuration": (["prove", "--config", "{file}"], "c.toml"),
    "train data": (["curves", "--train", "{file}", "--out", "{tmp}/out"], "t.toml"),
    "platform data": (["platforms", "{file}"], "p.toml"),
    "railML": (
        ["railml", "{file}", "--name", "x", "--net-elements", "a,b,c", "--switch-throw-s", "6", "--out", "{tmp}/o"],
        "l.railml",
    ),
    "counterexample": (["replay", "{file}"], "cex.json"),
    "prove report": (
        ["certify", "--only", "supervision.eb_above_ebi", "--report", "{file}", "--dir", "{tmp}/c"],
        "r.json",
    ),
    "equivalents": (["mutate", "--list", "--equivalents", "{file}"], "e.toml"),
    "coverage allowlist": (["coverage", "--only", "mrsp.*", "--allowlist", "{file}"], "a.toml"),
    "coverage prove report": (["coverage", "--report", "{file}"], "r.json"),
    "conformance frame": (["conformance", "{file}"], "f.json"),
}


def _run(tmp_path: Path, surface: str, content: str | bytes, capsys) -> str:
    argv, name = FILE_SURFACES[surface]
    path = _write(tmp_path, name, content)
    code = main([a.format(file=path, tmp=tmp_path) for a in argv])
    line = one_line(capsys, "atcs: error: ")
    assert code == 2, line
    assert str(path) in line, line
    return line


@pytest.mark.parametrize("surface", FILE_SURFACES)
def test_a_file_that_is_not_utf8_text_is_refused_naming_it(tmp_path, surface, capsys):
    line = _run(tmp_path, surface, NOT_UTF8, capsys)
    # XML declares its own encoding: the parser reads the bytes, and finds no XML
    reason = "not well-formed XML" if surface == "railML" else "is not UTF-8 text (byte 0 is 0xff)"
    assert reason in line, line


def test_a_vector_file_that_is_not_utf8_text_is_refused_naming_it(tmp_path, capsys):
    _write(tmp_path, "supervision.json", NOT_UTF8)
    assert main(["vectors", "verify", str(tmp_path)]) == 2
    line = one_line(capsys, "atcs: error: ")
    assert f"{tmp_path / 'supervision.json'}: the vector file is not UTF-8 text" in line


HUGE_FILES = {
    "scenario": lambda v: _edited(SCENARIO, "safety_margin_m = 20", f'safety_margin_m = "{v}"'),
    "configuration": lambda v: _edited(CONFIGURATION, "length_m = 5000", f'length_m = "{v}"'),
    "train data": lambda v: _edited(TRAIN, "length_m = 600", f'length_m = "{v}"'),
    "platform data": lambda v: PLATFORMS.replace("start_m = 100", f'start_m = "{v}"'),
    "railML": lambda v: _edited(RAILML, 'pos="300"', f'pos="{v}"'),
    "counterexample": lambda v: json.dumps(_trace("supervision.eb_above_ebi", speed_mps=v)),
}
"""How each file surface is given a huge number as text (JSON numbers that large read as infinity: below)."""


@pytest.mark.parametrize("value", HUGE)
@pytest.mark.parametrize("surface", HUGE_FILES)
def test_a_number_too_large_to_read_is_refused_naming_the_field(tmp_path, surface, value, capsys):
    line = _run(tmp_path, surface, HUGE_FILES[surface](value), capsys)
    assert value in line and ("exponent beyond" in line or "larger than 1e300" in line), line


def _report(status="proved", k=1) -> str:
    return json.dumps({"properties": [{"name": "supervision.eb_above_ebi", "status": status, "k": k}]})


@pytest.mark.parametrize(
    ("report", "message"),
    [
        (_report(k=1e300), "properties[0].k = 1e+300 (of supervision.eb_above_ebi) is not a depth from 0 to"),
        (_report().replace("1}", "1e300000000}"), "properties[0].k = inf"),
        (_report(k=100000), "properties[0].k = 100000 (of supervision.eb_above_ebi) is not a depth from 0 to"),
        (_report(status="Proved"), "properties[0].status = 'Proved' (of supervision.eb_above_ebi) is not a verdict"),
    ],
    ids=["huge", "infinite", "deeper than max_k", "status"],
)
def test_a_prove_report_with_a_bad_verdict_or_depth_is_refused(tmp_path, report, message, capsys):
    line = _run(tmp_path, "prove report", report, capsys)
    assert message in line, line


@pytest.mark.parametrize("value", HUGE)
@pytest.mark.parametrize(
    "argv",
    [
        ["curves", "--eoa", "{v}"],
        ["curves", "--eoa-speed", "{v}"],
        ["curves", "--mrsp", "0:{v}"],
        ["curves", "--gradient", "0:{v}"],
        ["headway", "--speed", "{v}"],
        ["railml", str(RAILML), "--name", "x", "--switch-length-m", "{v}"],
    ],
    ids=lambda a: " ".join(a[:2]) if isinstance(a, list) else a,
)
def test_an_option_too_large_to_read_is_refused_naming_it(tmp_path, argv, value, capsys):
    code = main([a.format(v=value) for a in argv] + (["--out", str(tmp_path / "o")] if argv[0] == "curves" else []))
    line = one_line(capsys, "atcs: error: ")
    assert code == 2 and value in line, line


# --- values out of their range, which were accepted silently -------------------------------------------------


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--mrsp", "500:80"], "--mrsp: starts_m[0] = '500' is not 0"),
        (["--gradient=-100:0,500:5"], "--gradient: starts_m[0] = '-100' is not 0"),
        (["--a-est", "1e9"], "--a-est = 1e+09 is out of range (from 0 to the train's A_max"),
        (["--eoa", "1e200"], "--eoa = 1e+200 is out of range (above 0, at most 1000000 m)"),
        (["--speed", "1000"], "--speed = 1000 is out of range (above 0, at most 600 km/h)"),
    ],
)
def test_a_curves_option_out_of_range_is_refused(tmp_path, argv, message, capsys):
    assert main(["curves", *argv, "--out", str(tmp_path / "o")]) == 2
    assert message in one_line(capsys, "atcs: error: curves: ")
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("kmh = 80 }]", "kmh = 10000 }]", "line.speed_limits[0].kmh = 10000 must be at most 600"),
        (
            "speed_limits = [{ start_m = 0, kmh = 80 }]",
            "speed_limits = [{ start_m = 0, kmh = 80 }]\ngradients = [{ start_m = 0, permille = 500 }]",
            "line.gradients[0].permille = 500 must be at most 100",
        ),
        ("cycle_s = 0.1", "cycle_s = 100", "cycle_s = 100 must be at most 1"),
        ("duration_s = 320", "duration_s = 1e9", "duration_s = 1000000000.0 must be at most 86400"),
        ("max_ma_m = 1500", "max_ma_m = 1e300", "line.max_ma_m = 1e+300 must be at most 1000000"),
        ("safety_margin_m = 20", "safety_margin_m = 1e300", "atp.safety_margin_m = 1e+300 must be at most 1000000"),
        ("report_timeout_s = 2", "report_timeout_s = 1e300", "atp.report_timeout_s = 1e+300 must be at most 86400"),
        (
            "report_timeout_s = 2",
            "report_timeout_s = 2\nclock_skew_s = 2",
            "atp.clock_skew_s = 2 must be below report_timeout_s (2): every message would be stale",
        ),
        ("report_timeout_s = 2", "report_timeout_s = 2\nclock_skew_s = -1", "atp.clock_skew_s = -1 must be at least 0"),
        ("planning_decel_kmhps = 1.5", "planning_decel_kmhps = 99", "ato.planning_decel_kmhps = 99 must be at most 18"),
        ("margin_m = 30", "margin_m = 1e300", "ato.margin_m = 1e+300 must be at most 1000000"),
        ("max_speed_kmh = 80", "max_speed_kmh = 1e300", "trains[0].max_speed_kmh = 1e+300 must be at most 600"),
        ("depart_s = 20", "depart_s = 1e300", "trains[1].depart_s = 1e+300 must be at most 86400"),
        ("length_m = 15000", "length_m = 1e9", "line.length_m = 1000000000.0 must be at most 1000000"),
    ],
)
def test_a_scenario_value_out_of_range_is_refused(tmp_path, old, new, message, capsys):
    path = _write(tmp_path, "s.toml", _edited(SCENARIO, old, new))
    assert main(["sim", str(path)]) == 2
    assert f"{path}: {message}" in one_line(capsys, "atcs: error: sim: ")


# --- vector files: malformed, and edited since they were generated ---------------------------------------------

IMPL = ROOT / "tests" / "proofs" / "vectors" / "impl" / "supervision_impl.py"


@pytest.fixture(scope="module")
def generated(tmp_path_factory):
    out = tmp_path_factory.mktemp("generated")
    assert main(["vectors", "generate", "--function", "supervision", "--out", str(out)]) == 0
    return out


@pytest.fixture
def vectors(generated, tmp_path):
    return Path(shutil.copytree(generated, tmp_path / "v"))


def _edit_vectors(directory: Path, edit) -> Path:
    path = directory / "supervision.json"
    doc = json.loads(path.read_text(encoding="utf-8"))
    edit(doc)
    path.write_text(json.dumps(doc), encoding="utf-8")
    return path


@pytest.mark.parametrize("command", ["verify", "check"])
@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda d: d["vectors"][0].update(covers=[1]), "vectors[0].covers[0] must be a goal id (a string), got 1"),
        (lambda d: d["vectors"][0].pop("expected_float"), "vectors[0].expected_float must be an object, got None"),
    ],
    ids=["covers", "expected_float"],
)
def test_a_malformed_vector_file_is_refused_naming_the_field(vectors, command, edit, message, capsys):
    path = _edit_vectors(vectors, edit)
    extra = ["--impl", f"{sys.executable} {IMPL}"] if command == "check" else []
    assert main(["vectors", command, *extra, str(vectors)]) == 2
    assert f"{path}: {message}" in one_line(capsys, f"atcs: error: vectors {command}: ")


def test_vectors_check_refuses_a_file_edited_since_it_was_generated(vectors, capsys):
    path = _edit_vectors(vectors, lambda d: d["vectors"][0]["expected"]["outputs"].update(emergency_brake=False))
    assert main(["vectors", "check", "--impl", f"{sys.executable} {IMPL}", str(vectors)]) == 2
    line = one_line(capsys, "atcs: error: vectors check: ")
    assert f"{path}: edited: the goals and vectors hash to " in line and "checked only as generated" in line


def test_vectors_verify_reports_a_directory_in_place_of_the_table(vectors, capsys):
    (vectors / "supervision.csv").unlink()
    (vectors / "supervision.csv").mkdir()
    assert main(["vectors", "verify", str(vectors)]) == 1
    assert "supervision.json: supervision.csv is not a file" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("fault", "message"),
    [
        ('{ kind = "spurious_tag", tag_id = 1.5 }', "trains[0].faults[0].tag_id = 1.5 must be a whole number"),
        ('{ kind = "clock_drift", factor = 1e6 }', "trains[0].faults[0].factor = 1000000.0 must be at most 10"),
        ('{ kind = "t2t_delay", delay_s = 1e300 }', "trains[0].faults[0].delay_s = 1e+300 must be at most 86400"),
    ],
)
def test_a_fault_field_out_of_range_is_refused(tmp_path, capsys, fault, message):
    faults = f"\nfaults = [{fault}]\n"
    path = _write(tmp_path, "s.toml", _edited(SCENARIO, "max_speed_kmh = 80\n", "max_speed_kmh = 80" + faults))
    assert main(["sim", str(path)]) == 2
    line = one_line(capsys, "atcs: error: sim: ")
    assert f"{path}: {message}" in line, line


def test_platform_edges_overlapping_on_one_side_are_refused(tmp_path, capsys):
    second = PLATFORMS.replace("start_m = 100", "start_m = 250").replace('side = "left"', 'side = "both"')
    path = _write(tmp_path, "p.toml", PLATFORMS + second)
    assert main(["platforms", str(path)]) == 2
    line = one_line(capsys, "atcs: error: platforms: ")
    assert "table[1]: [250, 450] m overlaps table[0] ([100, 300] m) on the same side" in line, line
    other_side = _write(tmp_path, "q.toml", PLATFORMS + second.replace("both", "right"))
    assert main(["platforms", str(other_side)]) == 0  # an island platform: one edge each side


# --- wrong types, unknown keys and non-finite numbers in each data file ------------------------------------------

TOML_EDITS = {
    "scenario": (SCENARIO, "safety_margin_m = 20"),
    "configuration": (CONFIGURATION, "length_m = 5000"),
    "train data": (TRAIN, "length_m = 600"),
}
"""A data file surface, its shipped example and a numeric field in it."""


@pytest.mark.parametrize("surface", TOML_EDITS)
@pytest.mark.parametrize(
    ("value", "reason"),
    [("nan", "is not finite"), ("inf", "is not finite"), ('"fast"', "is not a number"), ("[1]", "is not a number")],
    ids=["nan", "inf", "text", "list"],
)
def test_a_number_field_of_another_type_is_refused_naming_it(tmp_path, surface, value, reason, capsys):
    source, field = TOML_EDITS[surface]
    key = field.split(" = ")[0]
    line = _run(tmp_path, surface, _edited(source, field, f"{key} = {value}"), capsys)
    assert f"{key} = " in line and reason in line, line


@pytest.mark.parametrize("surface", TOML_EDITS)
def test_an_unknown_field_is_refused_naming_it(tmp_path, surface, capsys):
    source, field = TOML_EDITS[surface]
    line = _run(tmp_path, surface, _edited(source, field, f"{field}\ncolour = 1"), capsys)
    assert "colour: unknown field" in line, line


@pytest.mark.parametrize(
    ("packet", "message"),
    [
        ("zz", "'z' is not a hex digit"),
        ("45", "truncated"),
        ("ff" * 5000, "255 is neither 69 nor 44"),
        ("4 5 0", "3 hex digits are not whole bytes"),
    ],
    ids=["not hex", "truncated", "long", "odd digits"],
)
def test_a_bad_packet_is_refused_naming_the_bit(packet, message, capsys):
    assert main(["platforms", "--packet", packet, "--reference-m", "0"]) == 2
    assert message in one_line(capsys, "atcs: error: platforms: --packet: ")
