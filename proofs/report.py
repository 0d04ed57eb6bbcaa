"""Proof-suite reports: the JSON report, JUnit XML, counterexample files; all written atomically."""

from __future__ import annotations

import json
import time
import xml.etree.ElementTree as ET
from pathlib import Path

from atcs.proofs.cex.trace import input_changes, to_csv, to_json
from atcs.proofs.engine.prove import Result, Status
from atcs.proofs.files import write_atomic
from atcs.properties.property import Property


def write_counterexample(directory: str | Path, prop: Property, result: Result) -> Path:
    """Write ``<dir>/<property>.json``, ``.csv``, ``.vcd`` (:mod:`atcs.proofs.cex.vcd`) and ``.png``
    (:mod:`atcs.proofs.cex.plot`) for a falsified property; returns the JSON path."""
    from atcs.proofs.cex.plot import plot_counterexample
    from atcs.proofs.cex.vcd import to_vcd

    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    json_path = directory / f"{prop.name}.json"
    doc = to_json(result.trace, result.replay, requirement=prop.requirement)
    if result.smoothing is not None:
        doc["smoothing"] = result.smoothing.as_json()
    if result.nominal is not None:
        doc["nominal"] = result.nominal.as_json()
    write_atomic(json_path, json.dumps(doc, indent=2) + "\n")
    write_atomic(directory / f"{prop.name}.csv", to_csv(result.trace, result.replay))
    write_atomic(
        directory / f"{prop.name}.vcd", to_vcd(result.trace, result.replay, date=time.strftime("%Y-%m-%d %H:%M:%S %Z"))
    )
    plot_counterexample(prop.node, result.trace, result.replay, directory / f"{prop.name}.png")
    return json_path


def result_record(prop: Property, result: Result, counterexample: str | None) -> dict:
    return {
        "name": result.name,
        "requirement": result.requirement,
        "seed": prop.seed,
        "text": prop.text,
        "assumptions": [a.text for a in prop.assumptions],
        "status": result.status,
        "engine": result.engine or None,
        "k": result.k,
        "seconds": round(result.seconds, 4),
        "message": result.message,
        "counterexample": counterexample,
        "input_changes": None if result.trace is None else input_changes(result.trace),
        "smoothing": None if result.smoothing is None else result.smoothing.as_json(),
        "nominal": None if result.nominal is None else result.nominal.as_json(),
        "witnesses": [{"what": w.what, "step": w.step} for w in result.witnesses],
        "parts": [part.name for part in result.parts],
    }


FAILURES = ("vacuous", "falsified", "unknown")
"""The JUnit failures (an error is a JUnit error)."""


def write_witnesses(directory: str | Path, prop: Property, result: Result) -> Path:
    """Write ``<dir>/<property>.witnesses.json``: each witness run of a proved property (what it shows, the step,
    the trace)."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    path = directory / f"{prop.name}.witnesses.json"
    doc = {
        "property": prop.name,
        "requirement": prop.requirement,
        "witnesses": [
            {"what": w.what, "step": w.step, "trace": to_json(w.trace, requirement=prop.requirement)}
            for w in result.witnesses
        ],
    }
    write_atomic(path, json.dumps(doc, indent=2) + "\n")
    return path


def json_report(
    records: list[dict],
    *,
    timeout_s: float,
    wall_s: float,
    configuration: str | None = None,
    not_covered=(),
    envelopes: list[dict] | None = None,
) -> str:
    """The report of ``atcs prove``; with ``--config``, the configuration file and what it does not cover, and the
    map of each property proved over ranges of train data (:func:`atcs.proofs.envelope.map_json`)."""
    counts = {s: sum(r["status"] == s for r in records if r.get("part_of") is None) for s in Status}
    doc = {
        "tool": "atcs",
        "timeout_s": timeout_s,
        "wall_seconds": round(wall_s, 3),
        "summary": counts,
        "properties": records,
    }
    if configuration is not None:
        doc |= {"configuration": configuration, "not_covered": list(not_covered)}
    if envelopes is not None:
        doc["envelopes"] = envelopes
    return json.dumps(doc, indent=2) + "\n"


def junit_report(records: list[dict], *, wall_s: float) -> str:
    """One test case per property: vacuous, falsified and unknown are failures, error is an error."""
    suite = ET.Element(
        "testsuite",
        name="atcs.prove",
        tests=str(len(records)),
        failures=str(sum(r["status"] in FAILURES for r in records)),
        errors=str(sum(r["status"] == "error" for r in records)),
        skipped="0",
        time=f"{wall_s:.3f}",
    )
    for r in records:
        case = ET.SubElement(
            suite, "testcase", classname=f"atcs.{r['name'].split('.')[0]}", name=r["name"], time=f"{r['seconds']:.3f}"
        )
        ET.SubElement(case, "properties").extend(
            [
                ET.Element("property", name="requirement", value=r["requirement"]),
                ET.Element("property", name="engine", value=str(r["engine"])),
                ET.Element("property", name="k", value=str(r["k"])),
            ]
        )
        if r["status"] in FAILURES:
            detail = r["message"] + (f"; counterexample: {r['counterexample']}" if r["counterexample"] else "")
            ET.SubElement(case, "failure", type=r["status"], message=f"{r['status']}: {r['message']}").text = detail
        elif r["status"] == "error":
            ET.SubElement(case, "error", type="error", message=r["message"]).text = r["message"]
    root = ET.Element("testsuites")
    root.append(suite)
    ET.indent(root)
    return '<?xml version="1.0" encoding="utf-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
