"""Relative braking's separation with the reports the leader sends (seed 001 §3.2, Fig. 5 iii and Fig. 6; seed 000
§2.2 and §2.5; EN 50159).

Over :data:`~atcs.model.separation.TWO_TRAINS_REPORTED`: the two-train node with the report it delivers to the
follower taken from the leader's side, as the report channel's node has it
(:data:`~atcs.model.separation.REPORT_CHANNEL`): each cycle the leader's onboard unit makes a report of its position
function (:func:`~atcs.model.t2t_message.sent_report`), the channel carries it on in place of the one on its way or
loses it, and delivers the one on its way any number of cycles later, repeatedly, or never. Its sequence number and
time stamp stay any the environment chooses, as does whether its safety code holds.

With the seed 002 preset: what the two-train node assumes of a delivered report (REPORT_REAR, REPORT_STOP) is
proved here of the report on its way (SEP-11, SEP-12: SEP-07 and SEP-08 of the channel's node), on the leader's
position function being true (LEADER_POSITION); and the two-train node's properties that assumed them (SEP-00,
SEP-03 to SEP-06) are proved again with those two as lemmas in their place (SEP-13 to SEP-17): the bounds the
follower keeps of the leader, computed from the reports the leader's own unit makes, are never ahead of the
leader's true rear and earliest stopping point (SEP-13).

SEP-01 and SEP-02 hold of this node by the two-train node's proofs: its runs are the two-train node's runs
(:func:`~atcs.model.separation.reported_step` is :func:`~atcs.model.separation.two_train_step` on
:func:`~atcs.model.separation.delivered_report`, its initial states the two-train node's), every assumption of
theirs is here the same predicate of the same values, and REPORT_REAR and REPORT_STOP, the two that are not
assumed here, are what SEP-11 and SEP-12 prove (with the report on its way, ``on_way``, as the one delivered).
Proving them again on this node was measured (docs/property-scope.md): SEP-01 in 37 s, SEP-02 unknown at 1,200 s,
the rounding of the report on its way (floors) mixed into the nonlinear braking arithmetic.
"""

from __future__ import annotations

import dataclasses

from atcs.model.separation import TWO_TRAINS_REPORTED, delivered_report
from atcs.properties.closed_loop import PRESETS
from atcs.properties.property import Assumption, Property
from atcs.properties.report_channel import LEADER_POSITION, carried_on
from atcs.properties.separation import (
    REPORT_REAR,
    REPORT_STOP,
    report_behind,
    report_stop_behind,
    separation_properties,
)

PRESET = "seed002"
"""The follower's preset: relative braking's certificates are the quicker of the two presets' for seed 002."""


def on_delivered_report(holds):
    """A predicate of the two-train node, ``holds(o, p, s, i, ...)``, stated on this node: its inputs are the
    two-train node's with the report on its way as the one delivered (:func:`delivered_report`)."""

    def on_product(o, p, s, i, *rest):
        return holds(o, p, s, delivered_report(o, s, i), *rest)

    on_product.__qualname__ = getattr(holds, "__qualname__", "holds")
    return on_product


CARRIED = {"SEP-03": "SEP-14", "SEP-04": "SEP-15", "SEP-05": "SEP-16", "SEP-06": "SEP-17", "SEP-00": "SEP-13"}
"""The two-train node's properties proved again here (relative braking), each under its own id here."""


def _reported_properties() -> tuple[Property, ...]:
    two_trains = {p.requirement: p for p in separation_properties(PRESET, PRESETS[PRESET], "rbd")}
    adapted = {
        a: Assumption(a.name, a.text, on_delivered_report(a.holds))
        for a in two_trains["SEP-00"].assumptions
        if a not in (REPORT_REAR, REPORT_STOP)
    }
    relative = (*adapted.values(), LEADER_POSITION)
    name = {requirement: _renamed(p.name) for requirement, p in two_trains.items()}
    renamed = {p.name: name[requirement] for requirement, p in two_trains.items()}
    rear = f"reported_separation.report_on_way_behind_leader_rbd_{PRESET}"
    stop = f"reported_separation.report_on_way_stop_behind_leader_rbd_{PRESET}"
    carried = {
        requirement: dataclasses.replace(
            two_trains[requirement],
            name=name[requirement],
            requirement=CARRIED[requirement],
            node=TWO_TRAINS_REPORTED,
            holds=on_delivered_report(two_trains[requirement].holds),
            assumptions=relative,
            lemmas=tuple(renamed[n] for n in two_trains[requirement].lemmas)
            + ((rear, stop) if requirement == "SEP-00" else ()),
            text=two_trains[requirement]
            .text.replace(f"{PRESET}:", f"{PRESET}, the reports the leader sends:")
            .replace(", relative braking:", ", relative braking, the reports the leader sends:"),
        )
        for requirement in CARRIED
    }
    on_way_behind = Property(
        name=rear,
        requirement="SEP-11",
        seed="001 §3.2 (Fig. 5 iii, Fig. 6); EN 50159",
        text=(
            f"{PRESET}, relative braking: the report on its way to the follower, made by the leader's onboard unit "
            "at an earlier cycle, gives a min safe rear at most the leader's current rear (what the two-train "
            "node assumes of a delivered report, REPORT_REAR)."
        ),
        node=TWO_TRAINS_REPORTED,
        holds=lambda o, p, s, i, out, nxt: o.implies(s.on_way, report_behind(o, s.on_way_rear_m, s.leader_rear_m)),
        assumptions=relative,
        fixed_params=carried["SEP-00"].fixed_params,
    )
    on_way_stop_behind = dataclasses.replace(
        on_way_behind,
        name=stop,
        requirement="SEP-12",
        text=(
            f"{PRESET}, relative braking: the report on its way gives a min speed >= 0 and an earliest stopping point "
            "at most the leader's current one (REPORT_STOP of the two-train node)."
        ),
        holds=lambda o, p, s, i, out, nxt: o.implies(
            s.on_way, report_stop_behind(o, p, s.on_way_rear_m, s.on_way_speed_mps, s.leader_stop_m)
        ),
        lemmas=(name["SEP-03"],),
    )
    on_its_way = dataclasses.replace(
        on_way_behind,
        name=f"reported_separation.sent_report_on_its_way_rbd_{PRESET}",
        requirement="SEP-18",
        text=(
            f"{PRESET}, relative braking: a report the channel carries on is the leader's min safe rear and min speed "
            "rounded down to the cm and cm/s, on its way from the next cycle until a later one replaces it (SEP-09 "
            "of the channel's node; SEP-11 to SEP-13 are about the reports that do arrive)."
        ),
        holds=lambda o, p, s, i, out, nxt: carried_on(o, p, s, i, nxt),
        assumptions=(),
    )
    return (
        carried["SEP-03"],
        carried["SEP-04"],
        on_way_behind,
        on_way_stop_behind,
        carried["SEP-05"],
        carried["SEP-06"],
        carried["SEP-00"],
        on_its_way,
    )


def _renamed(name: str) -> str:
    return "reported_separation." + name.split(".", 1)[1]


PROPERTIES = _reported_properties()

__all__ = ["CARRIED", "PRESET", "PROPERTIES", "on_delivered_report"]
