"""A pytest plugin: the registered properties as test items, so that ``pytest --atcs-prove`` runs the
proof suite with pytest's usual reporting (``-k``, ``-x``, ``--junitxml``, ...).

Installed with atcs (entry point ``pytest11``); it adds only its options until ``--atcs-prove`` is given. The
properties are one collector, ``atcs-proofs``, collected beside the test files (so pytest counts them as
collected), with one item per property named after it: ``proved`` passes; ``vacuous``, ``falsified``,
``unknown`` and ``error`` fail, with the engine's message (and, for a counterexample, the violating step of its
exact replay and the counterexample file, written as ``atcs prove`` writes it). The k, the engine and the time
go to the JUnit report as properties of the test case.
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
        action="append",
        default=None,
        help="only the properties whose name matches this glob (e.g. 'supervision.*'); repeatable (the "
        "properties any matches)",
    )
    group.addoption(
        "--atcs-timeout",
        metavar="SECONDS",
        type=float,
        default=600.0,
        help="per-property time limit, lemmas included (default 600)",
    )
    group.addoption(
        "--atcs-cex-dir",
        metavar="DIR",
        default="counterexamples",
        help="where counterexamples are written as JSON, CSV, VCD and PNG (default ./counterexamples)",
    )


def pytest_configure(config):
    config.addinivalue_line("markers", "atcs_property: a registered atcs property, proved by the engine")
    if config.getoption("--atcs-prove"):
        from atcs.proofs.files import OutputPathError, check_writable_dir

        timeout = config.getoption("--atcs-timeout")
        if not timeout > 0:
            raise pytest.UsageError(f"--atcs-timeout must be a positive number of seconds, got {timeout!r}")
        for pattern in config.getoption("--atcs-only") or ():
            if not select(pattern):
                raise pytest.UsageError(f"--atcs-only {pattern!r} matches no registered property")
        try:
            check_writable_dir("--atcs-cex-dir", config.getoption("--atcs-cex-dir"))
        except OutputPathError as exc:
            raise pytest.UsageError(str(exc)) from None


def selected_properties(patterns: list[str] | None) -> list[Property]:
    """The registered properties any of the globs matches (all without one), in registry order."""
    if not patterns:
        return select()
    chosen = {p.name for pattern in patterns for p in select(pattern)}
    return [p for name, p in PROPERTIES.items() if name in chosen]


@pytest.hookimpl(wrapper=True)
def pytest_make_collect_report(collector):
    """The session collects the proof suite beside its test files: pytest then collects and counts the
    properties like any test (header, ``-k`` deselection, ``--collect-only``)."""
    report = yield
    if isinstance(collector, pytest.Session) and collector.config.getoption("--atcs-prove") and report.passed:
        name = "atcs-proofs"
        report.result.append(ProofSuite.from_parent(collector, name=name, path=collector.path / name, nodeid=name))
    return report


class ProofSuite(pytest.Collector):
    """The selected registered properties (:data:`atcs.properties.PROPERTIES`), as one collector."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.proved: dict[str, Result] = {}
        """Results so far, shared by the items: a lemma is proved once per session."""

    def collect(self):
        patterns = self.config.getoption("--atcs-only")
        return [PropertyItem.from_parent(self, name=prop.name, prop=prop) for prop in selected_properties(patterns)]


class PropertyFailed(AtcsError):
    """A property not proved: vacuous, falsified, unknown or error."""


class PropertyItem(pytest.Item):
    def __init__(self, *, prop: Property, **kwargs):
        super().__init__(**kwargs)
        self.prop = prop
        self.add_marker(pytest.mark.atcs_property)

    def runtest(self):
        timeout = self.config.getoption("--atcs-timeout")
        result = prove(self.prop, timeout_s=timeout, lemmas=PROPERTIES, proved=self.parent.proved)
        self.parent.proved[self.prop.name] = result
        counterexample = self._write_counterexample(result)
        for key, value in (
            ("requirement", self.prop.requirement),
            ("status", result.status),
            ("engine", result.engine),
            ("k", result.k),
            ("seconds", round(result.seconds, 3)),
            ("counterexample", counterexample),
        ):
            self.user_properties.append((key, value))
        if result.status != "proved":
            detail = f"{result.status}: {result.message}"
            if result.replay is not None and result.replay.first_violation is not None:
                detail += f" (the exact replay violates it at step {result.replay.first_violation})"
            if counterexample is not None:
                detail += f"; counterexample: {counterexample}"
            raise PropertyFailed(detail)

    def _write_counterexample(self, result: Result) -> str | None:
        """Write the counterexample files as ``atcs prove`` does; the JSON trace's path, or None if there is no
        replayed counterexample."""
        from atcs.proofs.report import write_counterexample

        if result.trace is None or result.replay is None:
            return None
        return str(write_counterexample(self.config.getoption("--atcs-cex-dir"), self.prop, result))

    def repr_failure(self, excinfo):
        if isinstance(excinfo.value, PropertyFailed):
            return (
                f"{self.prop.name} ({self.prop.requirement}, seed {self.prop.seed}): {self.prop.text}\n{excinfo.value}"
            )
        return super().repr_failure(excinfo)

    def reportinfo(self):
        return self.path, None, f"atcs property {self.prop.name}"
