"""The scenario file reference (docs/simulator.md) documents exactly the keys the loader accepts, table by table.

The loader names the fields it allows wherever it refuses an unknown one, so each table of a valid scenario is
given an unknown key and the fields the error lists are compared with the keys the manual's table documents."""

import re
import tomllib
from pathlib import Path

import pytest

from atcs.sim.scenario import FAULT_FIELDS, ScenarioError, load_scenario, resolve

ROOT = Path(__file__).parents[2]
MANUAL = ROOT / "docs" / "simulator.md"
UNKNOWN = "not_a_documented_key"


def documented_tables() -> dict[str, set[str]]:
    """The keys of each table of the reference, by its heading or the sentence that introduces it."""
    text = MANUAL.read_text(encoding="utf-8")
    reference = text.split("## Scenario file reference", 1)[1].split("\n## ", 1)[0]
    tables: dict[str, set[str]] = {}
    label = None
    for line in reference.splitlines():
        if line.startswith("### ") or line.startswith("Each "):
            label = line.removeprefix("### ").strip()
        elif line.startswith("| `") and label is not None:
            tables.setdefault(label, set()).update(re.findall(r"`\[*([a-z_0-9.]+)\]*`", line.split(" | ")[0]))
    return tables


def toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{k} = {toml_value(v)}" for k, v in value.items()) + " }"
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    return repr(value)


def toml_text(document: dict) -> str:
    """``document`` as TOML: scalars at the top, then each table and array of tables, nested values inline."""
    lines = [f"{k} = {toml_value(v)}" for k, v in document.items() if not isinstance(v, (dict, list))]
    for key, value in document.items():
        if isinstance(value, dict):
            lines += [f"[{key}]", *(f"{k} = {toml_value(v)}" for k, v in value.items())]
        elif isinstance(value, list):
            for entry in value:
                lines += [f"[[{key}]]", *(f"{k} = {toml_value(v)}" for k, v in entry.items())]
    return "\n".join(lines) + "\n"


def base_scenario() -> dict:
    """A valid scenario with every table: the shipped timetable, with a zone, a restriction, an outage and a
    fault added."""
    document = tomllib.loads(resolve("seed002_timetable").read_text(encoding="utf-8"))
    document["duration_s"] = 1
    document["zones"] = [{"start_m": 5000}]
    document["restrictions"] = [{"start_m": 4000, "end_m": 5000, "kmh": 30}]
    document["manager_outages"] = [{"from_s": 0, "until_s": 1, "zone": 1}]
    document["trains"][0]["faults"] = [{"kind": "missed_tag"}]
    return document


def allowed_fields(tmp_path: Path, document: dict) -> set[str]:
    """The fields the loader's error lists for the unknown key planted in ``document``."""
    path = tmp_path / "s.toml"
    path.write_text(toml_text(document), encoding="utf-8")
    with pytest.raises(ScenarioError) as refused:
        load_scenario(path)
    message = str(refused.value)
    assert UNKNOWN in message, message
    listed = re.search(r"\(fields(?: here)?: ([^)]*)\)", message)
    assert listed, message
    return {field.strip() for field in listed.group(1).split(",")}


def test_the_base_scenario_is_valid(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(toml_text(base_scenario()), encoding="utf-8")
    load_scenario(path)


PLACES = {
    "Top level": lambda d: d,
    "`[line]`": lambda d: d["line"],
    "`[atp]`": lambda d: d["atp"],
    "`[ato]`": lambda d: d["ato"],
    "`[[trains]]`": lambda d: d["trains"][0],
    "`[[zones]]`": lambda d: d["zones"][0],
    "`[[restrictions]]`": lambda d: d["restrictions"][0],
    "`[[stations]]`": lambda d: d["stations"][0],
    "`[platforms]`": lambda d: d["platforms"],
    "Each `[[platforms.table]]` entry:": lambda d: d["platforms"]["table"][0],
    "`[[manager_outages]]`": lambda d: d["manager_outages"][0],
}


def test_every_table_of_the_reference_is_checked():
    assert set(documented_tables()) == {*PLACES, "Each entry of `faults`:"}


@pytest.mark.parametrize("table", list(PLACES))
def test_the_loader_accepts_exactly_the_documented_keys(tmp_path, table):
    document = base_scenario()
    PLACES[table](document)[UNKNOWN] = 1
    assert allowed_fields(tmp_path, document) == documented_tables()[table]


def test_a_fault_accepts_exactly_the_documented_keys(tmp_path):
    """A fault's fields depend on its kind: their union over the kinds is the documented set."""
    allowed = set()
    for kind in FAULT_FIELDS:
        document = base_scenario()
        document["trains"][0]["faults"] = [{"kind": kind, **_own_field(kind), UNKNOWN: 1}]
        allowed |= allowed_fields(tmp_path, document)
    assert allowed == documented_tables()["Each entry of `faults`:"]


def _own_field(kind: str) -> dict:
    """The required field of a fault kind, at a valid value."""
    return {name: 1 for name in FAULT_FIELDS[kind] if name != "tag_id"}
