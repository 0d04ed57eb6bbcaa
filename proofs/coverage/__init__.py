"""Proof coverage (``atcs coverage``): which lines and decisions of ``model/`` the terms of each property reach.

- :mod:`.sites`: what is counted, found in the model's source (the statements and Ops decisions of every
  function of ``atcs.model`` but the backends);
- :mod:`.reach`: what each property's terms reach, traced while the engine's terms are built;
- :mod:`.report`: per site the properties reaching it, per module the counts, the allowlist of the code no
  property is meant to reach (each entry with its reason).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from pathlib import Path

from atcs.proofs.coverage.reach import Reached, reach_all, reach_node
from atcs.proofs.coverage.report import (
    ALLOWLIST,
    Allowance,
    AllowlistError,
    Coverage,
    ModuleCounts,
    load_allowlist,
)
from atcs.proofs.coverage.sites import Site, all_sites, model_modules
from atcs.properties import Property


def measure(
    properties: Iterable[Property],
    allowlist: Path | str = ALLOWLIST,
    progress: Callable[[str], None] = lambda name: None,
) -> Coverage:
    """The coverage of the model by ``properties``, with the allowlist in ``allowlist``."""
    allowances = load_allowlist(allowlist)
    return Coverage(all_sites(), tuple(reach_all(list(properties), progress)), allowances)


__all__ = [
    "ALLOWLIST",
    "Allowance",
    "AllowlistError",
    "Coverage",
    "ModuleCounts",
    "Reached",
    "Site",
    "all_sites",
    "load_allowlist",
    "measure",
    "model_modules",
    "reach_all",
    "reach_node",
]
