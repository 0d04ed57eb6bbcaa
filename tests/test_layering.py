"""The import graph of the packages (docs/design.md, the layers): ``model`` imports nothing of atcs but itself;
``properties`` only ``model``; ``proofs`` ``model`` and ``properties``; ``sim`` ``model``. The crossings below
are the only ones, each for the reason given. Read from the source with ``ast``, so an import inside a function
counts too."""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]
PACKAGES = ("model", "properties", "proofs", "sim")

ALLOWED = {
    "model": {"model"},
    "properties": {"model", "properties"},
    "proofs": {"model", "properties", "proofs"},
    "sim": {"model", "sim"},
}

CROSSINGS = {
    # the command line runs every part
    "proofs/cli": {"sim"},
    # the benchmarks time the simulator against its alternatives
    "proofs/bench": {"sim"},
    # the simulator checks the registered properties every cycle, the very predicates the proofs use
    "sim/monitor.py": {"properties"},
}


def _imports(path: Path) -> set[str]:
    """The atcs packages ``path`` imports (``atcs.<package>``)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        names = []
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names = [node.module]
        for name in names:
            parts = name.split(".")
            if parts[0] == "atcs" and len(parts) > 1:
                found.add(parts[1])
    return found


def _sources():
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            yield package, path


@pytest.mark.parametrize(
    ("package", "path"), list(_sources()), ids=lambda v: str(v.relative_to(ROOT)) if isinstance(v, Path) else v
)
def test_imports_follow_the_layers(package, path):
    relative = path.relative_to(ROOT).as_posix()
    allowed = set(ALLOWED[package])
    for where, extra in CROSSINGS.items():
        if relative == where or relative.startswith(where + "/"):
            allowed |= extra
    wrong = _imports(path) - allowed
    assert not wrong, f"{relative} imports atcs.{', atcs.'.join(sorted(wrong))}, outside its layer"


def test_every_crossing_is_used():
    for where, extra in CROSSINGS.items():
        paths = [ROOT / where] if where.endswith(".py") else sorted((ROOT / where).rglob("*.py"))
        used = set().union(*(_imports(p) for p in paths))
        assert extra <= used, f"{where} no longer imports atcs.{extra - used}: drop the crossing"


def test_importing_the_model_loads_no_solver_nor_numpy():
    import subprocess
    import sys

    code = "import sys, atcs.model, atcs.proofs; print(sorted({'z3', 'numpy', 'cvc5'} & set(sys.modules)))"
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert run.stdout.strip() == "[]", run.stdout + run.stderr
