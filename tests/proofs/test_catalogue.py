"""The shipped property catalogue (docs/properties.md) is what the generator makes of the current registry, and its
verdicts are the session's prove run's."""

from pathlib import Path

from atcs.proofs.catalogue import COLUMNS, COMMAND, catalogue_markdown
from atcs.properties import PROPERTIES

PAGE = Path(__file__).parents[2] / "docs" / "properties.md"
STALE = f"docs/properties.md is stale: regenerate it with `{COMMAND}`"


def _core(cell: str) -> dict | None:
    """The validity core's complement as the page shows it (``nothing``: the proof needs every part)."""
    if not cell:
        return None
    minimal = not cell.endswith(" (not minimal)")
    parts = cell.removesuffix(" (not minimal)")
    return {"unneeded": [] if parts == "nothing" else parts.split(", "), "minimal": minimal}


def shipped_verdicts() -> dict[str, dict]:
    """The status, engine, k and seconds of each property row of the shipped page."""
    records = {}
    for line in PAGE.read_text(encoding="utf-8").splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split(" | ")]
        if len(cells) == len(COLUMNS) and cells[0].startswith("`") and cells[0].strip("`") in PROPERTIES:
            row = dict(zip(COLUMNS, cells, strict=True))
            records[cells[0].strip("`")] = {
                "status": row["status"],
                "engine": row["engine"],
                "k": int(row["k"]) if row["k"] else None,
                "seconds": float(row["seconds"]) if row["seconds"] else None,
                "core": _core(row["not needed"]),
            }
    return records


def test_the_shipped_catalogue_is_generated_from_the_current_registry():
    shipped = shipped_verdicts()
    assert set(shipped) == set(PROPERTIES), STALE
    assert PAGE.read_text(encoding="utf-8") == catalogue_markdown(PROPERTIES.values(), shipped), STALE


def test_every_part_the_page_says_a_proof_does_without_is_one_of_the_propertys():
    for name, record in shipped_verdicts().items():
        prop = PROPERTIES[name]
        parts = {f"equation {f}" for f in prop.node.sorts("state")}
        parts |= {f"assumption {a.name}" for a in prop.assumptions} | {f"lemma {n}" for n in prop.lemmas}
        if record["engine"] == "k-induction":
            assert record["core"] is not None, f"{name}: no validity core on the page: {STALE}"
            assert set(record["core"]["unneeded"]) <= parts, f"{name}: {record['core']}: {STALE}"


def test_a_property_without_a_verdict_says_so():
    prop = PROPERTIES["supervision.eb_above_ebi"]
    page = catalogue_markdown([prop], {})
    assert "| `supervision.eb_above_ebi` | SUP-01 |" in page and "| not run |" in page
    assert "1 properties in 1 modules: 1 not run." in page


def test_the_shipped_verdicts_are_the_session_prove_runs(proof_suite_run):
    shipped = shipped_verdicts()
    wrong = {
        name: (shipped[name], record["status"], record["engine"], record["k"])
        for name, record in proof_suite_run.by_name.items()
        if (shipped[name]["status"], shipped[name]["engine"], shipped[name]["k"])
        != (record["status"], record["engine"], record["k"])
    }
    assert not wrong, f"{STALE}: {wrong}"
