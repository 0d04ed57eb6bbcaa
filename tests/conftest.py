"""Test configuration: a deterministic hypothesis profile for CI (and by default)."""

import contextlib
import io
import json
import os
from types import SimpleNamespace

import pytest
from hypothesis import HealthCheck, settings

settings.register_profile(
    "ci", deadline=None, derandomize=True, max_examples=200, suppress_health_check=[HealthCheck.too_slow]
)
settings.register_profile("dev", deadline=None, max_examples=1000)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


@pytest.fixture(scope="session")
def proof_suite_run(tmp_path_factory):
    """``atcs prove --jobs 2`` over every registered property, once per test session: the command line's own
    run, whose report the tests of the command line and of each proof module read (the proofs are the suite's
    biggest cost; each is run once, in worker processes, so this process's z3 context stays fresh)."""
    from atcs.proofs.cli import main

    out_dir = tmp_path_factory.mktemp("prove")
    paths = SimpleNamespace(json=out_dir / "r.json", junit=out_dir / "r.xml", cex=out_dir / "cex")
    stdout = io.StringIO()
    with contextlib.redirect_stdout(stdout):
        code = main(["prove", "--jobs", "2", "--json", str(paths.json), "--junit", str(paths.junit),
                     "--cex-dir", str(paths.cex)])
    doc = json.loads(paths.json.read_text())
    return SimpleNamespace(code=code, doc=doc, by_name={p["name"]: p for p in doc["properties"]},
                           stdout=stdout.getvalue(), **vars(paths))
