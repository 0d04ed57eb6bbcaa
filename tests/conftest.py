"""Test configuration: a deterministic hypothesis profile for CI (and by default)."""

import os

from hypothesis import HealthCheck, settings

settings.register_profile(
    "ci", deadline=None, derandomize=True, max_examples=200, suppress_health_check=[HealthCheck.too_slow]
)
settings.register_profile("dev", deadline=None, max_examples=1000)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


def pytest_collection_modifyitems(session, config, items):
    """Run the closed-loop proofs first. z3's search on some of their mutants' BMC queries depends on the terms
    the process made before (its heuristics follow term ids): in a fresh process each takes seconds, after the
    rest of the suite one took over 300 s. Until the engine builds each proof in a fresh z3 context, they go
    first (README, Determinism)."""
    first = [item for item in items if item.path.name == "test_closed_loop.py"]
    items[:] = first + [item for item in items if item.path.name != "test_closed_loop.py"]
