"""What the static-profile properties assume about the train's position (nodes with the fields
``front_m``, ``probe_m``, ``train_length_m`` and ``line_end_m``)."""

from __future__ import annotations

from atcs.properties.property import Assumption


def rear_m(o, p, i):
    """The rear of the train, or the start of the line if the rear is not on it yet."""
    return o.max(o.const(0), i.front_m - p.train_length_m)


TRAIN_ON_LINE = Assumption(
    "train_on_line",
    "0 <= front < line end, and the probe lies under the train: max(0, front - L) <= probe <= front",
    lambda o, p, s, i: o.and_(
        o.const(0) <= i.front_m, i.front_m < p.line_end_m, rear_m(o, p, i) <= i.probe_m, i.probe_m <= i.front_m
    ),
)
