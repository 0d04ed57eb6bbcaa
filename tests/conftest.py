"""Test configuration: a deterministic hypothesis profile for CI (and by default)."""

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
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

CERTIFY_TIMEOUTS_S = {"z3": 600, "cvc5": 1200}
"""Per-check time limits of the session's ``atcs certify`` run: several times each solver's longest check on an
idle machine (docs/benchmarks.md, ``atcs certify``), so that a slower machine gives the same verdicts."""

CERTIFY_Z3_ONLY = (
    "closed_loop.braking_invariant_seed000",
    "separation.braking_invariant_bw_seed002",
    "separation.braking_invariant_rbd_seed000",
    "separation.no_collision_rbd_seed000",
    "ato.ma_speed_with_no_nearer_limit",
)
"""The certificates the suite checks with z3 alone (``--z3-only``): cvc5 needs most of the suite's time for the
first four (docs/benchmarks.md, ``atcs certify``), so the suite has cvc5 confirm the other seed's certificate of
each of these properties and leaves these ``unconfirmed``; ``atcs certify`` without ``--z3-only`` certifies those
four with both solvers. ATO-04's nonlinear base check is left ``unknown`` by cvc5 (tried for 2 minutes)."""

CERTIFIED_BEFORE = Path(__file__).parent / "proofs" / "certify" / "suite_certificates.json"
"""The listing of an earlier run of the suite's ``atcs certify`` (``--reuse``): cvc5 is not asked again about a
script byte for byte the same as one it found unsat there with the same cvc5 version (docs/proofs.md,
"Certificates"); z3 checks every script each run. Refreshed by copying a later run's ``certificates.json`` here."""

_BACKGROUND = """
import json
import sys
from pathlib import Path
from atcs.proofs.cli import main
prove, certify, done, certify_out = sys.argv[1], sys.argv[2], Path(sys.argv[3]), sys.argv[4]
code = main(json.loads(prove))
done.write_text(str(code))
if certify:
    sys.stdout.flush()
    sys.stdout = sys.stderr = open(certify_out, "w")
    code = main(json.loads(certify))
sys.exit(code)
"""


def _uses(item, fixture: str) -> bool:
    return fixture in getattr(item, "fixturenames", ())


@pytest.hookimpl(tryfirst=True)  # before ``-m`` deselects by marker
def pytest_collection_modifyitems(session, config, items):
    """The tests that read the session's proof report are ``slow`` (they wait for the whole suite's proofs) and
    run last, so the rest overlaps the proof run; those that read its certificates after them."""
    for item in items:
        if _uses(item, "proof_suite_run") or _uses(item, "certify_suite_run"):
            item.add_marker(pytest.mark.slow)
    items.sort(
        key=lambda item: (
            _uses(item, "proof_suite_run") or _uses(item, "certify_suite_run"),
            _uses(item, "certify_suite_run"),
        )
    )


def pytest_collection_finish(session):
    """Start ``atcs prove --jobs 2`` over the whole registry as soon as the tests that read its report are
    collected, so its two workers prove while this process runs the other tests; when tests read the
    certificates, the same subprocess then runs ``atcs certify --report`` on that report (no proof runs twice)."""
    proofs = any(_uses(item, "proof_suite_run") for item in session.items)
    certificates = any(_uses(item, "certify_suite_run") for item in session.items)
    if not (proofs or certificates):
        return
    out_dir = Path(tempfile.mkdtemp(prefix="atcs-prove-"))
    paths = SimpleNamespace(
        json=out_dir / "r.json",
        junit=out_dir / "r.xml",
        cex=out_dir / "cex",
        stdout=out_dir / "stdout.txt",
        proved=out_dir / "prove.exit",
        certificates=out_dir / "certificates",
        certify_stdout=out_dir / "certify.txt",
    )
    prove = [
        "prove",
        "--jobs",
        "2",
        "--json",
        str(paths.json),
        "--junit",
        str(paths.junit),
        "--cex-dir",
        str(paths.cex),
    ]
    certify = [
        "certify",
        "--report",
        str(paths.json),
        "--dir",
        str(paths.certificates),
        "--jobs",
        "2",
        *(a for solver, limit in CERTIFY_TIMEOUTS_S.items() for a in (f"--{solver}-timeout", str(limit))),
        "--z3-only",
        ",".join(CERTIFY_Z3_ONLY),
        "--reuse",
        str(CERTIFIED_BEFORE),
    ]
    with paths.stdout.open("w") as stdout:
        process = subprocess.Popen(
            [
                sys.executable,
                "-c",
                _BACKGROUND,
                json.dumps(prove),
                json.dumps(certify) if certificates else "",
                str(paths.proved),
                str(paths.certify_stdout),
            ],
            stdout=stdout,
            stderr=subprocess.STDOUT,
        )
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
    while not paths.proved.exists() and process.poll() is None:  # the same process may go on to certify
        time.sleep(0.5)
    code = int(paths.proved.read_text()) if paths.proved.exists() else process.wait()
    if not paths.json.exists():
        pytest.fail(f"atcs prove exited with {code} and wrote no report:\n{paths.stdout.read_text()}")
    doc = json.loads(paths.json.read_text())
    return SimpleNamespace(
        code=code,
        doc=doc,
        by_name={p["name"]: p for p in doc["properties"]},
        stdout=paths.stdout.read_text(),
        json=paths.json,
        junit=paths.junit,
        cex=paths.cex,
    )


@pytest.fixture(scope="session")
def certify_suite_run(proof_suite_run):
    """``atcs certify --report`` on the session's prove report, both solvers (z3 alone on :data:`CERTIFY_Z3_ONLY`),
    :data:`CERTIFY_TIMEOUTS_S`, two workers, run by the proof run's subprocess once it has proved."""
    process, paths = _PROOF_RUN["process"], _PROOF_RUN["paths"]
    code = process.wait()
    listing = paths.certificates / "certificates.json"
    if not listing.exists():
        output = paths.certify_stdout.read_text() if paths.certify_stdout.exists() else ""
        pytest.fail(f"atcs certify exited with {code} and wrote no certificates.json:\n{output}")
    doc = json.loads(listing.read_text())
    return SimpleNamespace(
        code=code,
        doc=doc,
        by_name={p["name"]: p for p in doc["properties"]},
        dir=paths.certificates,
        stdout=paths.certify_stdout.read_text(),
        timeouts_s=CERTIFY_TIMEOUTS_S,
        z3_only=CERTIFY_Z3_ONLY,
    )
