"""The registry of equivalent mutants (``proofs/mutation/equivalent_mutants.toml``), read by ``atcs mutate``.

A surviving mutant is either killed by a new property or listed here, keyed by its stable id
(:attr:`atcs.proofs.mutation.sites.Mutant.id`), with the reason no property can tell it from the real model;
the campaign then reports it ``equivalent`` instead of ``survived``. Each entry::

    ["supervision.supervise:+23:delay_hold:emergency_brake -> s.eb_latched"]
    reason = "why the mutant cannot violate any safety property"
"""

from __future__ import annotations

from pathlib import Path

from atcs.model.data_files import read_toml
from atcs.model.errors import AtcsInputError

REGISTRY = Path(__file__).with_name("equivalent_mutants.toml")


class EquivalentsError(AtcsInputError):
    """The registry is malformed or names an unknown mutant; the message names the file, entry and value."""


def load_equivalents(path: str | Path = REGISTRY, known: set[str] | None = None) -> dict[str, str]:
    """``{mutant id: reason}``; with ``known`` (every mutant's id), an entry naming no mutant is an error."""
    path = Path(path)
    doc = read_toml(path, EquivalentsError, "the equivalents")
    reasons = {}
    for mutant_id, entry in doc.items():
        if not isinstance(entry, dict) or set(entry) != {"reason"}:
            raise EquivalentsError(
                f"{path}: [{mutant_id!r}] must be a table with exactly one key, reason; got {entry!r}"
            )
        reason = entry["reason"]
        if not isinstance(reason, str) or not reason.strip():
            raise EquivalentsError(f"{path}: [{mutant_id!r}].reason must be a non-empty string, got {reason!r}")
        if known is not None and mutant_id not in known:
            raise EquivalentsError(
                f"{path}: [{mutant_id!r}] names no mutant of the current model (a stale id: the function changed)"
            )
        reasons[mutant_id] = reason.strip()
    return reasons
