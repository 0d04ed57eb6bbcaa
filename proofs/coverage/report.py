"""Proof coverage as a report: per site the properties reaching it, per module the counts, the allowlist.

The allowlist (``allowlist.toml`` beside this module) names, by a glob over ``module.function``, the model code
no property reaches, each with its reason: code no property is meant to reach (a file reader whose checks raise on
bad data, a helper of the simulator's), or an open hole, its reason starting ``OPEN:``. Every entry must match
some site no property reaches, so that a stale one shows.
"""

from __future__ import annotations

import fnmatch
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from atcs.model.data_files import read_toml
from atcs.model.errors import AtcsInputError
from atcs.proofs.coverage.reach import Reached
from atcs.proofs.coverage.sites import Site

ALLOWLIST = Path(__file__).with_name("allowlist.toml")


class AllowlistError(AtcsInputError):
    """The allowlist file cannot be read, or an entry is malformed."""


@dataclass(frozen=True)
class Allowance:
    """Model code no property is meant to reach: a glob over ``module.function``, and why."""

    functions: str
    reason: str

    @property
    def open(self) -> bool:
        """Code that should be reached and is not yet: the reason says ``OPEN:``."""
        return self.reason.startswith("OPEN:")

    def covers(self, site: Site) -> bool:
        return fnmatch.fnmatchcase(f"{site.module}.{site.function}", self.functions)


def load_allowlist(path: Path | str = ALLOWLIST) -> tuple[Allowance, ...]:
    """The entries of an allowlist file: ``[[allow]]`` tables with ``functions`` and ``reason``."""
    doc = read_toml(path, AllowlistError, "the coverage allowlist")
    entries = doc.get("allow", [])
    if not isinstance(entries, list) or set(doc) - {"allow"}:
        raise AllowlistError(f"{path}: expected only [[allow]] tables, got the keys {sorted(doc)}")
    allowances = []
    for n, entry in enumerate(entries, start=1):
        where = f"{path}: [[allow]] #{n}"
        if not isinstance(entry, dict) or set(entry) != {"functions", "reason"}:
            keys = sorted(entry) if isinstance(entry, dict) else entry
            raise AllowlistError(f"{where}: expected the keys functions and reason, got {keys!r}")
        for key in ("functions", "reason"):
            if not isinstance(entry[key], str) or not entry[key].strip():
                raise AllowlistError(f"{where}: {key} must be a non-empty string, got {entry[key]!r}")
        if not entry["functions"].startswith("atcs.model."):
            raise AllowlistError(f"{where}: functions must name model code (atcs.model.*), got {entry['functions']!r}")
        allowances.append(Allowance(entry["functions"], entry["reason"].strip()))
    return tuple(allowances)


@dataclass(frozen=True)
class ModuleCounts:
    module: str
    lines: int
    lines_reached: int
    decisions: int
    decisions_reached: int
    allowlisted: int
    """Sites (lines and decisions) no property reaches, allowlisted."""
    open: int
    """Of those, the ones allowlisted as open (not yet proved: the entry's reason starts ``OPEN:``)."""
    unreached: int
    """Sites no property reaches, not allowlisted."""


@dataclass(frozen=True)
class Coverage:
    """Which properties reach each site; the allowlist applied."""

    sites: tuple[Site, ...]
    reached: tuple[Reached, ...]
    allowlist: tuple[Allowance, ...]

    def properties_at(self, site: Site) -> list[str]:
        """The properties whose terms reach ``site``, in the order given."""
        return self._by_site().get(site, [])

    def _by_site(self) -> dict[Site, list[str]]:
        cached = self.__dict__.get("_cache")
        if cached is None:
            lines: dict[tuple, list[str]] = {}
            for r in self.reached:
                for key in r.lines:
                    lines.setdefault((*key, "line"), []).append(r.property)
                for key in r.decisions:
                    lines.setdefault(key, []).append(r.property)
            cached = {s: lines.get((s.module, s.line, s.kind), []) for s in self.sites}
            object.__setattr__(self, "_cache", cached)
        return cached

    def allowance(self, site: Site) -> Allowance | None:
        """The allowlist entry covering ``site``, if no property reaches it."""
        if self.properties_at(site):
            return None
        return next((a for a in self.allowlist if a.covers(site)), None)

    def unreached(self) -> list[Site]:
        """The sites no property reaches and no allowlist entry covers."""
        return [s for s in self.sites if not self.properties_at(s) and self.allowance(s) is None]

    def unused_allowances(self) -> list[Allowance]:
        """Allowlist entries that cover no unreached site (stale)."""
        return [a for a in self.allowlist if not any(a.covers(s) and not self.properties_at(s) for s in self.sites)]

    def modules(self) -> list[ModuleCounts]:
        rows = []
        for module in sorted({s.module for s in self.sites}):
            sites = [s for s in self.sites if s.module == module]
            lines = [s for s in sites if s.kind == "line"]
            decisions = [s for s in sites if s.kind != "line"]
            rows.append(
                ModuleCounts(
                    module=module,
                    lines=len(lines),
                    lines_reached=sum(bool(self.properties_at(s)) for s in lines),
                    decisions=len(decisions),
                    decisions_reached=sum(bool(self.properties_at(s)) for s in decisions),
                    allowlisted=sum(self.allowance(s) is not None for s in sites),
                    open=sum(a is not None and a.open for a in map(self.allowance, sites)),
                    unreached=sum(not self.properties_at(s) and self.allowance(s) is None for s in sites),
                )
            )
        return rows

    def record(self) -> dict:
        """The JSON document of ``atcs coverage --json``."""
        return {
            "tool": "atcs coverage",
            "properties": [r.property for r in self.reached],
            "modules": [vars(row) for row in self.modules()],
            "sites": [
                {
                    "module": s.module,
                    "function": s.function,
                    "line": s.line,
                    "kind": s.kind,
                    "properties": self.properties_at(s),
                    "allowlisted": a.reason if (a := self.allowance(s)) is not None else None,
                }
                for s in self.sites
            ],
            "unused_allowances": [a.functions for a in self.unused_allowances()],
        }

    def annotated(self, module: str, source: Iterable[str]) -> str:
        """``module``'s source with a gutter: at each line site the number of properties reaching it, ``!!``
        where none does, ``allow`` where none does and the allowlist says why; the decisions after the line."""
        by_line: dict[int, list[Site]] = {}
        for s in self.sites:
            if s.module == module:
                by_line.setdefault(s.line, []).append(s)
        out = []
        for number, text in enumerate(source, start=1):
            gutter = ""
            for s in sorted(by_line.get(number, []), key=lambda s: s.kind != "line"):
                count = len(self.properties_at(s))
                mark = str(count) if count else ("allow" if self.allowance(s) is not None else "!!")
                gutter += mark if s.kind == "line" else f" {s.kind}:{mark}"
            out.append(f"{gutter:>22} | {text.rstrip()}")
        return "\n".join(out) + "\n"


__all__ = [
    "ALLOWLIST",
    "Allowance",
    "AllowlistError",
    "Coverage",
    "ModuleCounts",
    "load_allowlist",
]
