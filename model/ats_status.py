"""The line status the ATS sends each train: the protection zones and temporary speed restrictions in force
(seed 000 §2.5, 002 §3.2 and §4.2), received over the same open radio channel as the T2T reports and defended the
same way (EN 50159).

The ATS sends every train its status each cycle, numbered and time stamped by the ATS's clock, with a safety code.
A status is *accepted* when it arrives, its safety code checks (corruption, masquerade), its number is above the
last one accepted (repetition, resequencing: an old status must not lift a zone a newer one set) and its time stamp
is not ahead of the onboard clock by more than the clock skew (:func:`message_accepted`, the check the T2T reports
pass too). The train keeps the zone of the last status accepted, so a status lost for a cycle lifts nothing.

The status is *fresh* while the freshest accepted was sent no longer than ``status_timeout_s`` ago (by its time
stamp, the onboard clock and the skew). A zone or a restriction set since may be unknown to a stale train, so
while the status is not fresh the zone the train respects starts at its max safe front: the movement authority
ends there (:mod:`atcs.model.authority`, AUT-03), the train stops, and stays stopped until a fresh status
arrives. The ATS's side of the bargain, outside this model: a zone or a
restriction is in force for the track side only once every train has either received it or been stopped, i.e.
``status_timeout_s`` plus a train's emergency stopping time after the ATS starts sending it, and no earlier than
where a train may be by then (docs/property-scope.md).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Generic

from atcs.model.node import Node
from atcs.model.ops import B, N, Ops


def message_accepted(o: Ops, known, last_seq, delivered, intact, seq, sent_s, now_s, clock_skew_max_s):
    """A message arrives, its safety code checks, it is numbered after the last one accepted (any number for the
    first) and stamped no later than the onboard clock plus the clock skew (EN 50159: sequence number, time
    stamp, safety code)."""
    in_sequence = o.or_(o.not_(known), seq > last_seq)
    return o.and_(delivered, intact, in_sequence, sent_s <= now_s + clock_skew_max_s)


def message_age_s(now_s, sent_s, clock_skew_max_s):
    """The longest time since a message stamped ``sent_s`` by the sender's clock was sent: the clocks may differ
    by the skew."""
    return now_s - sent_s + clock_skew_max_s


@dataclass(frozen=True)
class AtsStatusParams(Generic[N, B]):
    status_timeout_s: N
    """The oldest the freshest status accepted may be for the train to run on it."""
    clock_skew_max_s: N
    """The largest difference between the ATS's clock and this train's."""


@dataclass(frozen=True)
class AtsStatusState(Generic[N, B]):
    status_known: B
    """A status has been accepted."""
    last_status_seq: N
    """The number of the last status accepted."""
    freshest_status_sent_s: N
    """The latest time stamp of a status accepted (the ATS's clock)."""
    kept_zone_active: B
    kept_zone_start_m: N
    """The protection zone of the last status accepted."""


@dataclass(frozen=True)
class AtsStatusInputs(Generic[N, B]):
    now_s: N
    """The onboard clock."""
    front_max_m: N
    """The train's max safe front."""
    status_delivered: B
    """A status arrives this cycle."""
    status_intact: B
    """Its safety code checks."""
    status_seq: N
    status_sent_s: N
    """Its number and time stamp."""
    status_zone_active: B
    status_zone_start_m: N
    """The protection zone it sets: the first active one ahead of the train's rear."""


@dataclass(frozen=True)
class AtsStatusOutputs(Generic[N, B]):
    status_accepted: B
    """This cycle's status passed every check and replaced the one kept."""
    status_fresh: B
    """The freshest status accepted is no older than the timeout: the train may run on it."""
    zone_active: B
    zone_start_m: N
    """The protection zone the train respects: the last status accepted's while the status is fresh; from the max
    safe front on while it is not."""


def ats_status_init(o: Ops, p: AtsStatusParams, s: AtsStatusState):
    """No status accepted yet: not fresh, so the train stays where it powered up until one arrives."""
    zero = o.const(0)
    return o.and_(
        o.not_(s.status_known),
        o.eq(s.last_status_seq, zero),
        o.eq(s.freshest_status_sent_s, zero),
        o.not_(s.kept_zone_active),
        o.eq(s.kept_zone_start_m, zero),
    )


def ats_status_step(o: Ops, p: AtsStatusParams, s: AtsStatusState, i: AtsStatusInputs):
    """One cycle: accept this cycle's status if it passes every check, keep the last one accepted (module
    docstring)."""
    accepted = message_accepted(
        o,
        s.status_known,
        s.last_status_seq,
        i.status_delivered,
        i.status_intact,
        i.status_seq,
        i.status_sent_s,
        i.now_s,
        p.clock_skew_max_s,
    )
    freshest = o.ite(o.not_(s.status_known), i.status_sent_s, o.max(s.freshest_status_sent_s, i.status_sent_s))
    kept = AtsStatusState(
        status_known=o.or_(s.status_known, accepted),
        last_status_seq=o.ite(accepted, i.status_seq, s.last_status_seq),
        freshest_status_sent_s=o.ite(accepted, freshest, s.freshest_status_sent_s),
        kept_zone_active=o.ite(accepted, i.status_zone_active, s.kept_zone_active),
        kept_zone_start_m=o.ite(accepted, i.status_zone_start_m, s.kept_zone_start_m),
    )
    age = message_age_s(i.now_s, kept.freshest_status_sent_s, p.clock_skew_max_s)
    fresh = o.and_(kept.status_known, age <= p.status_timeout_s)
    zone_active = o.or_(o.not_(fresh), kept.kept_zone_active)
    zone_start = o.ite(fresh, kept.kept_zone_start_m, i.front_max_m)
    return kept, AtsStatusOutputs(accepted, fresh, zone_active, zone_start)


ATS_STATUS = Node(
    name="ats_status",
    params=AtsStatusParams,
    state=AtsStatusState,
    inputs=AtsStatusInputs,
    outputs=AtsStatusOutputs,
    init=ats_status_init,
    step=ats_status_step,
    seed="000 §2.5, 002 §3.2, §4.2; EN 50159 defences",
)

__all__ = [
    "ATS_STATUS",
    "AtsStatusInputs",
    "AtsStatusOutputs",
    "AtsStatusParams",
    "AtsStatusState",
    "message_accepted",
    "message_age_s",
]
