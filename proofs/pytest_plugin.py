"""A pytest plugin: the registered properties as test items, so that ``pytest --atcs-prove`` runs the
proof suite with pytest's usual reporting (``-k``, ``-x``, ``--junitxml``, ...).

Installed with atcs (entry point ``pytest11``); it adds only its options until ``--atcs-prove`` is given. Each
property is one item named after it: ``proved`` passes; ``falsified``, ``unknown`` and ``error`` fail, with the
engine's message (and, for a counterexample, the violating step of its exact replay). The k, the engine and
the time go to the JUnit report as properties of the test case.
"""

from __future__ import annotations

import pytest

from atcs.model.errors import AtcsError
from atcs.proofs.engine.prove import Result, prove
from atcs.properties import PROPERTIES, Property, select


def pytest_addoption(parser):
    group = parser.getgroup("atcs", "atcs proof suite")
    group.addoption("--atcs-prove", action="store_true", help="collect the registered atcs properties as tests")
    group.addoption(
        "--atcs-only",
        metavar="PATTERN",
        default=None,
        help="only the properties whose name matches this glob (e.g. 'supervision.*')",
    )
    group.addoption(
        "--atcs-timeout",
        metavar="SECONDS",
        type=float,
        default=600.0,
        help="per-property time limit, lemmas included (default 600)",
    )


def pytest_configure(config):
    config.addinivalue_line("markers", "atcs_property: a registered atcs property, proved by the engine")
    if config.getoption("--atcs-prove"):
        timeout = config.getoption("--atcs-timeout")
        if not timeout > 0:
            raise pytest.UsageError(f"--atcs-timeout must be a positive number of seconds, got {timeout!r}")
        pattern = config.getoption("--atcs-only")
        if not select(pattern):
            raise pytest.UsageError(f"--atcs-only {pattern!r} matches no registered property")


def pytest_collection_modifyitems(session, config, items):
    if not config.getoption("--atcs-prove"):
        return
    suite = ProofSuite.from_parent(session, name="atcs-proofs")
    items.extend(
        PropertyItem.from_parent(suite, name=prop.name, prop=prop) for prop in select(config.getoption("--atcs-only"))
    )


class ProofSuite(pytest.Collector):
    """The registered properties (:data:`atcs.properties.PROPERTIES`), as one collector."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.proved: dict[str, Result] = {}
        """Results so far, shared by the items: a lemma is proved once per session."""

    def collect(self):
        return []


class PropertyFailed(AtcsError):
    """A property not proved: falsified, unknown or error."""


class PropertyItem(pytest.Item):
    def __init__(self, *, prop: Property, **kwargs):
        super().__init__(**kwargs)
        self.prop = prop
        self.add_marker(pytest.mark.atcs_property)

    def runtest(self):
        timeout = self.config.getoption("--atcs-timeout")
        result = prove(self.prop, timeout_s=timeout, lemmas=PROPERTIES, proved=self.parent.proved)
        self.parent.proved[self.prop.name] = result
        for key, value in (
            ("requirement", self.prop.requirement),
            ("status", result.status),
            ("engine", result.engine),
            ("k", result.k),
            ("seconds", round(result.seconds, 3)),
        ):
            self.user_properties.append((key, value))
        if result.status != "proved":
            detail = f"{result.status}: {result.message}"
            if result.replay is not None and result.replay.first_violation is not None:
                detail += f" (the exact replay violates it at step {result.replay.first_violation})"
            raise PropertyFailed(detail)

    def repr_failure(self, excinfo):
        if isinstance(excinfo.value, PropertyFailed):
            return (
                f"{self.prop.name} ({self.prop.requirement}, seed {self.prop.seed}): {self.prop.text}\n{excinfo.value}"
            )
        return super().repr_failure(excinfo)

    def reportinfo(self):
        return self.path, None, f"atcs property {self.prop.name}"
