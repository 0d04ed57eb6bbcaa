"""Test configuration: a deterministic hypothesis profile for CI (and by default)."""

import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path
from types import SimpleNamespace

import pytest
from hypothesis import HealthCheck, settings

settings.register_profile(
    "ci", deadline=None, derandomize=True, max_examples=200, suppress_health_check=[HealthCheck.too_slow]
)
settings.register_profile("dev", deadline=None, max_examples=1000)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


_PROOF_RUN: dict = {}


def pytest_collection_modifyitems(session, config, items):
    """The tests that read the session's proof report run last, so the rest overlaps the proof run."""
    items.sort(key=lambda item: "proof_suite_run" in getattr(item, "fixturenames", ()))


def pytest_collection_finish(session):
    """Start ``atcs prove --jobs 2`` over the whole registry as soon as the tests that read its report are
    collected, so its two workers prove while this process runs the other tests."""
    if not any("proof_suite_run" in getattr(item, "fixturenames", ()) for item in session.items):
        return
    out_dir = Path(tempfile.mkdtemp(prefix="atcs-prove-"))
    paths = SimpleNamespace(json=out_dir / "r.json", junit=out_dir / "r.xml", cex=out_dir / "cex",
                            stdout=out_dir / "stdout.txt")
    argv = ["prove", "--jobs", "2", "--json", str(paths.json), "--junit", str(paths.junit), "--cex-dir", str(paths.cex)]
    with paths.stdout.open("w") as stdout:
        process = subprocess.Popen(
            [sys.executable, "-c", "import sys; from atcs.proofs.cli import main; sys.exit(main(sys.argv[1:]))", *argv],
            stdout=stdout, stderr=subprocess.STDOUT)
    _PROOF_RUN.update(process=process, paths=paths, dir=out_dir)


def pytest_sessionfinish(session, exitstatus):
    """Stop the proof run if the session ends before it does, and remove its files."""
    if _PROOF_RUN:
        if _PROOF_RUN["process"].poll() is None:
            _PROOF_RUN["process"].kill()
            _PROOF_RUN["process"].wait()
        shutil.rmtree(_PROOF_RUN["dir"], ignore_errors=True)


@pytest.fixture(scope="session")
def proof_suite_run():
    """The report of ``atcs prove --jobs 2 --json --junit --cex-dir`` over every registered property, run once
    per test session in a subprocess (started at collection): the tests of the command line and of each proof
    module read it instead of proving again."""
    process, paths = _PROOF_RUN["process"], _PROOF_RUN["paths"]
    code = process.wait()
    if not paths.json.exists():
        pytest.fail(f"atcs prove exited with {code} and wrote no report:\n{paths.stdout.read_text()}")
    doc = json.loads(paths.json.read_text())
    return SimpleNamespace(code=code, doc=doc, by_name={p["name"]: p for p in doc["properties"]},
                           stdout=paths.stdout.read_text(), json=paths.json, junit=paths.junit, cex=paths.cex)
