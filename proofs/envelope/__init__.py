"""Envelopes: a configured train's properties proved over ranges of its train data, cell by cell, refined where a
cell is not proved, into a map of proved, falsified and unknown cells (docs/configuration.md "Ranges of train
data").

- :mod:`.cells`: the cells of a train's ranges and how one is split;
- :mod:`.sweep`: the refinement, on local worker processes or on Ray (:mod:`.executors`);
- :mod:`.maps`: the map as JSON and as plots of 2-D slices.
"""

from atcs.proofs.envelope.cells import split, whole_range
from atcs.proofs.envelope.maps import map_json, plot_slices, write_map
from atcs.proofs.envelope.sweep import CellVerdict, PropertyMap, envelope_properties, sweep

__all__ = [
    "CellVerdict",
    "PropertyMap",
    "envelope_properties",
    "map_json",
    "plot_slices",
    "split",
    "sweep",
    "whole_range",
    "write_map",
]
