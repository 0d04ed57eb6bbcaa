"""Proof-suite reports: the JSON report, JUnit XML, counterexample files; all written atomically."""

from __future__ import annotations

import json
import os
import tempfile
import time
import xml.etree.ElementTree as ET
from pathlib import Path

from atcs.proofs.engine import STATUSES, Result
from atcs.proofs.trace import input_changes, to_csv, to_json
from atcs.properties.property import Property


class OutputPathError(ValueError):
    """An output path cannot be written; the message names the option and the path."""


def _probe(option: str, path: str, directory: Path) -> None:
    """Create and delete a file in ``directory``: the only reliable writability test (root ignores modes)."""
    try:
        with tempfile.NamedTemporaryFile(dir=directory, prefix=".atcs-probe-"):
            pass
    except OSError as exc:
        raise OutputPathError(f"{option} {path}: cannot write in {directory}: {exc.strerror}") from None


def check_writable_file(option: str, path: str) -> None:
    """Fail early (before any proof runs) if ``path`` cannot be written as a file."""
    p = Path(path)
    if p.is_dir():
        raise OutputPathError(f"{option} {path}: is a directory")
    if not p.parent.is_dir():
        raise OutputPathError(f"{option} {path}: directory {p.parent} does not exist")
    _probe(option, path, p.parent)


def check_writable_dir(option: str, path: str) -> None:
    """Fail early if ``path`` is not, and cannot become, a writable directory (it is created later)."""
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise OutputPathError(f"{option} {path}: exists and is not a directory")
    existing = p
    while not existing.exists():
        existing = existing.parent
    if not existing.is_dir():
        raise OutputPathError(f"{option} {path}: {existing} is not a directory")
    _probe(option, path, existing)


def write_atomic(path: str | Path, text: str | bytes) -> None:
    """Write ``text`` (or bytes) to a temporary file beside ``path``, then rename it over ``path``."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)  # an ordinary file, not mkstemp's private 0600
    try:
        if isinstance(text, bytes):
            with os.fdopen(fd, "wb") as fh:
                fh.write(text)
        else:
            with os.fdopen(fd, "w", encoding="utf-8", newline="") as fh:
                fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def write_counterexample(directory: str | Path, prop: Property, result: Result) -> Path:
    """Write ``<dir>/<property>.json``, ``.csv``, ``.vcd`` (:mod:`atcs.proofs.waveform`) and ``.png``
    (:mod:`atcs.proofs.cex_plot`) for a falsified property; returns the JSON path."""
    from atcs.proofs.cex_plot import plot_counterexample
    from atcs.proofs.waveform import to_vcd

    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    json_path = directory / f"{prop.name}.json"
    doc = to_json(result.trace, result.replay, requirement=prop.requirement)
    if result.smoothing is not None:
        doc["smoothing"] = result.smoothing.as_json()
    write_atomic(json_path, json.dumps(doc, indent=2) + "\n")
    write_atomic(directory / f"{prop.name}.csv", to_csv(result.trace, result.replay))
    write_atomic(directory / f"{prop.name}.vcd", to_vcd(result.trace, result.replay,
                                                       date=time.strftime("%Y-%m-%d %H:%M:%S %Z")))
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
        "witnesses": [{"what": w.what, "step": w.step} for w in result.witnesses],
    }


FAILURES = ("vacuous", "falsified", "unknown")
"""The JUnit failures (an error is a JUnit error)."""


def write_witnesses(directory: str | Path, prop: Property, result: Result) -> Path:
    """Write ``<dir>/<property>.witnesses.json``: each witness run of a proved property (what it shows, the step,
    the trace)."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    path = directory / f"{prop.name}.witnesses.json"
    doc = {"property": prop.name, "requirement": prop.requirement,
           "witnesses": [{"what": w.what, "step": w.step, "trace": to_json(w.trace, requirement=prop.requirement)}
                         for w in result.witnesses]}
    write_atomic(path, json.dumps(doc, indent=2) + "\n")
    return path


def json_report(records: list[dict], *, timeout_s: float, wall_s: float) -> str:
    counts = {s: sum(r["status"] == s for r in records) for s in STATUSES}
    doc = {"tool": "atcs", "timeout_s": timeout_s, "wall_seconds": round(wall_s, 3), "summary": counts,
           "properties": records}
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
            [ET.Element("property", name="requirement", value=r["requirement"]),
             ET.Element("property", name="engine", value=str(r["engine"])),
             ET.Element("property", name="k", value=str(r["k"]))]
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
