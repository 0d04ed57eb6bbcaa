"""The refinement of an envelope: each property of a train with ranges is proved over the whole box of its ranges;
a cell that comes back falsified or unknown is split (:func:`~atcs.proofs.envelope.cells.split`) and its halves
proved, down to the ranges' resolution. A cell is proved only when every proof made for it is
(:func:`~atcs.properties.envelope.cell_families`); a property only when every cell of its map is.

The cells run as tasks (:func:`prove_cell`) on an executor: this process, local worker processes, or Ray
(:mod:`atcs.proofs.envelope.executors`); each task is a pure function of its arguments, so the verdicts are the
same on all of them, and a task run twice (a lost worker's, retried) gives the same verdict, recorded once.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from concurrent.futures import FIRST_COMPLETED, wait
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

from atcs.model.configuration import Configuration, ConfiguredTrain, DataRange, Line, load_configuration
from atcs.proofs.engine.prove import Result, prove
from atcs.proofs.engine.split import WORST_FIRST
from atcs.proofs.envelope.cells import split, whole_range
from atcs.properties.configured import curve_family, loop_family
from atcs.properties.envelope import Cell, cell_families
from atcs.properties.property import Property

__all__ = ["WORST_FIRST", "CellVerdict", "PropertyMap", "cell_proofs", "envelope_properties", "prove_cell", "sweep"]


@dataclass
class CellVerdict:
    """The verdict of one property on one cell, with the proofs made for it (one, or one per whole-cycle
    rounding of the closed loop's times)."""

    cell: Cell
    status: str
    seconds: float
    results: tuple[Result, ...]
    reused: int = 0
    """How many of the proofs were reused from the verdict cache."""

    @property
    def failing(self) -> Result | None:
        """The proof that decided a cell not proved (the first of the worst verdict)."""
        return next((r for r in self.results if r.status == self.status), None) if self.status != "proved" else None


@dataclass
class PropertyMap:
    """A property of a train with ranges, and the verdict of each cell of its map."""

    name: str
    requirement: str
    train: str
    line: str
    ranges: tuple[DataRange, ...]
    cells: list[CellVerdict] = field(default_factory=list)

    @property
    def status(self) -> str:
        """proved only if every cell is; else the worst cell verdict."""
        return min((c.status for c in self.cells), key=WORST_FIRST.index, default="unknown")

    @property
    def seconds(self) -> float:
        return sum(c.seconds for c in self.cells)

    def describe(self) -> str:
        counts = {s: sum(c.status == s for c in self.cells) for s in WORST_FIRST}
        parts = [f"{n} {s}" for s, n in counts.items() if n]
        return f"{len(self.cells)} cells: " + ", ".join(parts)


def envelope_properties(config: Configuration) -> dict[str, tuple[ConfiguredTrain, Line]]:
    """The properties of ``config`` proved over ranges (those of its trains with ``[trains.ranges]``), by name,
    with their train and line."""
    found = {}
    for t in config.trains:
        if not t.ranges:
            continue
        for line in config.lines:
            for p in curve_family(config, t, line) + loop_family(config, t, line):
                found[p.name] = (t, line)
    return found


_CONFIGURATIONS: dict[str, Configuration] = {}
"""The configurations a worker process has read, by path."""


def _configuration(path: str) -> Configuration:
    if path not in _CONFIGURATIONS:
        _CONFIGURATIONS[path] = load_configuration(path)
    return _CONFIGURATIONS[path]


def cell_proofs(config: Configuration, name: str, cell: Cell) -> list[tuple[Property, dict[str, Property]]]:
    """The proofs that together prove the property ``name`` over ``cell``, each with the registry of its lemmas."""
    t, line = envelope_properties(config)[name]
    base_curves, base_loop = curve_family(config, t, line), loop_family(config, t, line)
    curves, loops = cell_families(config, t, line, cell)
    names = [p.name for p in base_curves]
    if name in names:
        return [(curves[names.index(name)], {p.name: p for p in curves})]
    j = [p.name for p in base_loop].index(name)
    return [(family[j], {p.name: p for p in family}) for family in loops]


def prove_cell(
    config_path: str, name: str, bounds: tuple, timeout_s: float, cache_dir: str | None = None
) -> CellVerdict:
    """The verdict of property ``name`` of the configuration at ``config_path`` over the cell ``bounds``: every
    proof made for it within ``timeout_s`` each, reusing and keeping proved verdicts in ``cache_dir``."""
    config = _configuration(config_path)
    cell = Cell(tuple((f, Fraction(lo), Fraction(hi)) for f, lo, hi in bounds))
    start = time.monotonic()
    results, reused = [], 0
    proved: dict[str, Result] = {}
    for prop, registry in cell_proofs(config, name, cell):
        cache = None
        if cache_dir is not None:
            from atcs.proofs.engine.cache import VerdictCache

            cache = VerdictCache(cache_dir, registry)
        result = None if cache is None else cache.get(prop)
        if result is not None:
            reused += 1
        else:
            result = prove(prop, timeout_s=timeout_s, lemmas=registry, proved=proved)
            if cache is not None:
                cache.put(prop, result)
        results.append(result)
        if result.status != "proved":
            break  # the cell is not proved; the other roundings would not change that
    status = min((r.status for r in results), key=WORST_FIRST.index)
    return CellVerdict(cell, str(status), time.monotonic() - start, tuple(results), reused)


def sweep(
    config_path: str,
    names: list[str],
    *,
    timeout_s: float,
    executor,
    cache_dir: str | None = None,
    on_cell: Callable[[str, CellVerdict], None] = lambda name, verdict: None,
) -> dict[str, PropertyMap]:
    """The map of each property in ``names`` (of :func:`envelope_properties`), its cells proved as tasks on
    ``executor`` (``submit(fn, *args) -> Future``), refined as the module docstring says; ``on_cell`` is told of
    each final cell. The paths are made absolute first: a Ray worker does not run in this directory."""
    config_path = str(Path(config_path).resolve())
    cache_dir = None if cache_dir is None else str(Path(cache_dir).resolve())
    config = _configuration(config_path)
    owners = envelope_properties(config)
    maps = {}
    pending = {}

    def submit(name: str, cell: Cell) -> None:
        future = executor.submit(prove_cell, config_path, name, cell.bounds, timeout_s, cache_dir)
        pending[future] = (name, cell)

    for name in names:
        t, line = owners[name]
        registered = curve_family(config, t, line) + loop_family(config, t, line)
        requirement = next(p.requirement for p in registered if p.name == name)
        maps[name] = PropertyMap(name, requirement, t.name, line.name, t.ranges)
        submit(name, whole_range(t.ranges))
    while pending:
        done, _ = wait(pending, return_when=FIRST_COMPLETED)
        for future in done:
            name, cell = pending.pop(future)
            verdict = future.result()
            halves = split(cell, maps[name].ranges) if verdict.status in ("falsified", "unknown") else None
            if halves is None:
                maps[name].cells.append(verdict)
                on_cell(name, verdict)
            else:
                for half in halves:
                    submit(name, half)
    for m in maps.values():
        m.cells.sort(key=lambda c: tuple((lo, hi) for _, lo, hi in c.cell.bounds))
    return maps
