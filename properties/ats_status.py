"""Properties of the ATS's line status as the train receives it (seed 000 §2.5, 002 §3.2 and §4.2; EN 50159).

Over :data:`~atcs.model.ats_status.ATS_STATUS` with every field symbolic: any status delivered or lost, intact or
corrupted, any number, time stamp, clock, skew, timeout and position. Each claim is stated from the message's
fields, not through the node's own acceptance check. Together with AUT-03 (the end of authority before the zone
the node gives): a zone is respected from the first status accepted that sets it until a newer one lifts it, and a
train that stops hearing the ATS stops (ATS-04).
"""

from __future__ import annotations

from atcs.model.ats_status import ATS_STATUS
from atcs.properties.property import Property


def _rejected(o, p, s, i):
    """This cycle's status is lost, corrupted, numbered at most the last one accepted (replayed, repeated,
    overtaken) or stamped later than the onboard clock plus the skew."""
    return o.or_(
        o.not_(i.status_delivered),
        o.not_(i.status_intact),
        o.and_(s.status_known, i.status_seq <= s.last_status_seq),
        i.status_sent_s > i.now_s + p.clock_skew_max_s,
    )


def _sent_within_timeout(o, p, i, sent_s):
    return i.now_s - sent_s + p.clock_skew_max_s <= p.status_timeout_s


def _fresh_exactly_when(o, p, s, i, out, nxt):
    arrived = o.and_(o.not_(_rejected(o, p, s, i)), _sent_within_timeout(o, p, i, i.status_sent_s))
    kept = o.and_(s.status_known, _sent_within_timeout(o, p, i, s.freshest_status_sent_s))
    return o.eq(out.status_fresh, o.or_(arrived, kept))


def _accepted_sets_zone(o, p, s, i, out, nxt):
    return o.implies(
        o.not_(_rejected(o, p, s, i)),
        o.and_(
            out.status_accepted,
            o.eq(nxt.kept_zone_active, i.status_zone_active),
            o.eq(nxt.kept_zone_start_m, i.status_zone_start_m),
            o.eq(nxt.last_status_seq, i.status_seq),
        ),
    )


def _rejected_changes_nothing(o, p, s, i, out, nxt):
    return o.implies(
        _rejected(o, p, s, i),
        o.and_(
            o.not_(out.status_accepted),
            o.eq(nxt.kept_zone_active, s.kept_zone_active),
            o.eq(nxt.kept_zone_start_m, s.kept_zone_start_m),
            o.eq(nxt.status_known, s.status_known),
            o.eq(nxt.last_status_seq, s.last_status_seq),
            o.eq(nxt.freshest_status_sent_s, s.freshest_status_sent_s),
        ),
    )


def _zone_respected(o, p, s, i, out, nxt):
    at_front = o.and_(out.zone_active, o.eq(out.zone_start_m, i.front_max_m))
    kept = o.and_(o.eq(out.zone_active, nxt.kept_zone_active), o.eq(out.zone_start_m, nxt.kept_zone_start_m))
    return o.ite(out.status_fresh, kept, at_front)


PROPERTIES = (
    Property(
        name="ats_status.fresh_exactly_within_timeout",
        requirement="ATS-01",
        seed="000 §2.5, 002 §3.2; EN 50159 (time stamp, time-out)",
        text="The ATS's status is fresh exactly when a status accepted this cycle or before was sent no longer "
        "than the timeout ago (by its time stamp, the onboard clock and the clock skew).",
        node=ATS_STATUS,
        holds=_fresh_exactly_when,
    ),
    Property(
        name="ats_status.accepted_status_sets_zone",
        requirement="ATS-02",
        seed="000 §2.5, 002 §4.2; EN 50159 (sequence number, safety code)",
        text="A status that arrives intact, numbered after the last one accepted (any number for the first) and "
        "stamped no later than the onboard clock plus the skew is accepted: the zone kept is the one it sets, "
        "and its number is kept as the last one.",
        node=ATS_STATUS,
        holds=_accepted_sets_zone,
    ),
    Property(
        name="ats_status.rejected_status_changes_nothing",
        requirement="ATS-03",
        seed="000 §2.5; EN 50159 (repetition, resequencing, corruption, delay)",
        text="A status lost, corrupted, replayed or overtaken (numbered at most the last one accepted) or stamped "
        "in the future is not accepted and changes nothing: the zone kept stays the last accepted status's, and "
        "the last number and time stamp kept stay as they were, so it cannot lift a zone nor hold off the "
        "time-out.",
        node=ATS_STATUS,
        holds=_rejected_changes_nothing,
    ),
    Property(
        name="ats_status.stale_status_stops",
        requirement="ATS-04",
        seed="000 §2.5, 002 §3.2; EN 50159 (time-out)",
        text="While the status is fresh the zone the train respects is the one kept; while it is not (a zone or a "
        "restriction set since may be unknown, power-up included), a zone from the max safe front on: the end of "
        "authority lies there (AUT-03) and the train stops.",
        node=ATS_STATUS,
        holds=_zone_respected,
    ),
)

__all__ = ["PROPERTIES"]
