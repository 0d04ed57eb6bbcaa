"""Properties of resource request and release (seed 001 §3.2, Fig. 5).

Over :data:`~atcs.model.resources.RESOURCES` with 3 trains and 3 resources: any
train behaviour that follows the procedure (which resources to request or release
is free), and any delivery of the messages in flight: any delay, any order across
trains and resources (each (train, resource) exchange is one request or release
and its reply). No assumptions.

The train's own side (which resources it requests, releases and commands) is proved over
:data:`~atcs.model.authority.AUTHORITY`, the node that decides it.
"""

from __future__ import annotations

from atcs.model.authority import AUTHORITY
from atcs.model.resources import (
    CONFIRM,
    FREE,
    GRANT,
    HELD,
    NO_MESSAGE,
    REFUSE,
    RELEASE,
    RELEASING,
    REQUEST,
    REQUESTED,
    RESOURCES,
    slot_count,
)
from atcs.properties.authority import resource_ahead, route_resources
from atcs.properties.property import Property


def _slots(s):
    trains, resources = slot_count(s)
    return [(train * resources + r, train, r) for train in range(trains) for r in range(resources)]


def _consistent(o, p, s, i, out, nxt):
    trains, _ = slot_count(s)

    def is_(value, c):
        return o.eq(value, o.const(c))

    facts = [o.or_(*(is_(owner, t) for t in range(trains + 1))) for owner in s.owner]
    for j, train, r in _slots(s):
        own, up, down = is_(s.owner[r], train + 1), s.up[j], s.down[j]
        quiet = o.and_(is_(up, NO_MESSAGE), is_(down, NO_MESSAGE))
        facts.append(
            o.or_(
                o.and_(is_(s.holding[j], FREE), quiet, o.not_(own)),
                o.and_(
                    is_(s.holding[j], REQUESTED),
                    o.or_(
                        o.and_(is_(up, REQUEST), is_(down, NO_MESSAGE), o.not_(own)),
                        o.and_(is_(up, NO_MESSAGE), is_(down, GRANT), own),
                        o.and_(is_(up, NO_MESSAGE), is_(down, REFUSE), o.not_(own)),
                    ),
                ),
                o.and_(is_(s.holding[j], HELD), quiet, own),
                o.and_(
                    is_(s.holding[j], RELEASING),
                    o.or_(
                        o.and_(is_(up, RELEASE), is_(down, NO_MESSAGE), own),
                        o.and_(is_(up, NO_MESSAGE), is_(down, CONFIRM), o.not_(own)),
                    ),
                ),
            )
        )
    return o.and_(*facts)


def _mutual_exclusion(o, p, s, i, out, nxt):
    trains, resources = slot_count(s)
    return o.and_(
        *(
            o.not_(o.and_(out.held[a * resources + r], out.held[b * resources + r]))
            for r in range(resources)
            for a in range(trains)
            for b in range(a + 1, trains)
        )
    )


def _manager_records_holder(o, p, s, i, out, nxt):
    return o.and_(*(o.implies(out.held[j], o.eq(nxt.owner[r], o.const(train + 1))) for j, train, r in _slots(s)))


def _idle_unchanged(o, p, s, i, out, nxt):
    trains, resources = slot_count(s)

    def idle(j):
        return o.and_(o.not_(i.send[j]), o.eq(s.up[j], o.const(NO_MESSAGE)), o.eq(s.down[j], o.const(NO_MESSAGE)))

    facts = [
        o.implies(
            idle(j), o.and_(o.eq(nxt.holding[j], s.holding[j]), o.eq(nxt.up[j], s.up[j]), o.eq(nxt.down[j], s.down[j]))
        )
        for j, _, _ in _slots(s)
    ]
    facts += [
        o.implies(o.and_(*(idle(train * resources + r) for train in range(trains))), o.eq(nxt.owner[r], s.owner[r]))
        for r in range(resources)
    ]
    return o.and_(*facts)


def _delivery_consumes(o, p, s, i, out, nxt):
    facts = []
    for j, _, _ in _slots(s):
        up_arrives = o.and_(i.deliver_up[j], o.not_(o.eq(s.up[j], o.const(NO_MESSAGE))))
        down_arrives = o.and_(i.deliver_down[j], o.not_(o.eq(s.down[j], o.const(NO_MESSAGE))))
        facts += [
            o.implies(up_arrives, o.eq(nxt.up[j], o.const(NO_MESSAGE))),
            o.implies(down_arrives, o.eq(nxt.down[j], o.const(NO_MESSAGE))),
        ]
    return o.and_(*facts)


def _manager_acts_on_delivery(o, p, s, i, out, nxt):
    trains, resources = slot_count(s)

    def delivered(j):
        return o.and_(i.deliver_up[j], o.not_(o.eq(s.up[j], o.const(NO_MESSAGE))))

    return o.and_(
        *(
            o.implies(
                o.not_(o.eq(nxt.owner[r], s.owner[r])),
                o.or_(*(delivered(train * resources + r) for train in range(trains))),
            )
            for r in range(resources)
        )
    )


def _sends_when_commanded(o, p, s, i, out, nxt):
    facts = []
    for j, _, _ in _slots(s):
        reply = o.and_(i.deliver_down[j], o.not_(o.eq(s.down[j], o.const(NO_MESSAGE))))
        free_to_send = o.or_(o.eq(s.holding[j], o.const(FREE)), o.eq(s.holding[j], o.const(HELD)))
        sent = o.not_(o.eq(nxt.up[j], o.const(NO_MESSAGE)))
        facts.append(
            o.implies(o.eq(s.up[j], o.const(NO_MESSAGE)), o.eq(sent, o.and_(i.send[j], o.not_(reply), free_to_send)))
        )
    return o.and_(*facts)


def _grants_free_resource(o, p, s, i, out, nxt):
    trains, resources = slot_count(s)

    def requested(train, r):
        j = train * resources + r
        return o.and_(i.deliver_up[j], o.eq(s.up[j], o.const(REQUEST)))

    return o.and_(
        *(
            o.implies(
                o.and_(
                    requested(train, r),
                    o.eq(s.owner[r], o.const(0)),
                    *(o.not_(requested(earlier, r)) for earlier in range(train)),
                ),
                o.eq(nxt.owner[r], o.const(train + 1)),
            )
            for train in range(trains)
            for r in range(resources)
        )
    )


# --- the train's own requests and releases, over the movement authority's node -----------------------------


def _release_behind_rear(o, p, s, i, out, nxt):
    return o.and_(
        *(
            o.implies(out.release[r], o.and_(i.rear_confirmed, i.held[r], p.resource_end_m[r] <= i.rear_min_m))
            for r in route_resources(p)
        )
    )


def _request_ahead(o, p, s, i, out, nxt):
    horizon = i.front_max_m + p.max_ma_m
    return o.and_(
        *(
            o.implies(
                out.request[r],
                o.and_(
                    o.not_(i.held[r]),
                    resource_ahead(p, i, r),
                    p.resource_start_m[r] < horizon,
                    p.resource_start_m[r] < p.line_end_m,
                ),
            )
            for r in route_resources(p)
        )
    )


def _switch_command(o, p, s, i, out, nxt):
    return o.and_(
        *(o.implies(out.switch_command[r], o.and_(i.held[r], p.resource_is_switch[r])) for r in route_resources(p))
    )


def _release_when_behind(o, p, s, i, out, nxt):
    return o.and_(
        *(
            o.implies(o.and_(i.rear_confirmed, i.held[r], p.resource_end_m[r] <= i.rear_min_m), out.release[r])
            for r in route_resources(p)
        )
    )


def _authority_property(name, requirement, seed, text, holds):
    return Property(name=name, requirement=requirement, seed=seed, text=text, node=AUTHORITY, holds=holds)


PROPERTIES = (
    Property(
        name="resources.protocol_consistent",
        requirement="RES-00",
        seed="001 §3.2 (Fig. 5)",
        text=(
            "The manager's owner of each resource agrees with every train's view and the messages in flight: a "
            "train holds a resource, has a grant for it in flight, or has its release in flight exactly when the "
            "manager records it as the owner."
        ),
        node=RESOURCES,
        holds=_consistent,
    ),
    Property(
        name="resources.mutual_exclusion",
        requirement="RES-01",
        seed="001 §3.2 (Fig. 5)",
        text="No resource is held by two trains at once, whatever the delays and the order of the messages.",
        node=RESOURCES,
        holds=_mutual_exclusion,
        lemmas=("resources.protocol_consistent",),
    ),
    Property(
        name="resources.manager_records_holder",
        requirement="RES-02",
        seed="001 §3.2",
        text="A train holds a resource only while the resource manager records it as the owner.",
        node=RESOURCES,
        holds=_manager_records_holder,
        lemmas=("resources.protocol_consistent",),
    ),
    Property(
        name="resources.idle_slot_unchanged",
        requirement="RES-06",
        seed="001 §3.2",
        text=(
            "A slot with nothing sent and nothing in flight keeps its state, and a resource whose slots are all "
            "idle keeps its owner (the simulator steps the manager on the busy slots only)."
        ),
        node=RESOURCES,
        holds=_idle_unchanged,
    ),
    # the message handling itself (survivors of atcs mutate: the safety claims above allow a protocol that
    # acts on undelivered messages, ignores delivered ones or never sends)
    Property(
        name="resources.delivery_consumes",
        requirement="RES-08",
        seed="001 §3.2 (Fig. 5)",
        text="A message delivered on either channel is taken off it in that cycle (handled, not left in flight).",
        node=RESOURCES,
        holds=_delivery_consumes,
    ),
    Property(
        name="resources.manager_acts_on_delivery",
        requirement="RES-09",
        seed="001 §3.2 (Fig. 5)",
        text="The manager changes a resource's owner only in a cycle in which a train's message about it is delivered.",
        node=RESOURCES,
        holds=_manager_acts_on_delivery,
    ),
    Property(
        name="resources.sends_when_commanded",
        requirement="RES-10",
        seed="001 §3.2 (Fig. 5)",
        text="With nothing of its own in flight, a train sends a request or release exactly when commanded to, "
        "no reply arrives that cycle, and the resource is free to it or held (not mid-exchange).",
        node=RESOURCES,
        holds=_sends_when_commanded,
    ),
    Property(
        name="resources.grants_free_resource",
        requirement="RES-11",
        seed="001 §3.2 (Fig. 5)",
        text="Not over-restrictive: a delivered request for a resource nobody owns is granted, unless a train "
        "earlier in slot order requests it in the same cycle.",
        node=RESOURCES,
        holds=_grants_free_resource,
    ),
    _authority_property(
        "resources.release_behind_rear",
        "RES-03",
        "001 §3.2 (Fig. 5)",
        "A resource is released only if the min safe rear is confirmed (the position confirmed, the train's "
        "integrity confirmed), the train holds it and it lies wholly behind that rear: a position set again from one "
        "tag read, possibly wrong, or a train that may have left wagons behind, releases nothing.",
        _release_behind_rear,
    ),
    _authority_property(
        "resources.request_ahead",
        "RES-04",
        "001 §3.2",
        "A resource is requested only if the train does not hold it, it reaches past the max safe front, and "
        "it starts before dRequestResource (the end of line and MAX_MA ahead).",
        _request_ahead,
    ),
    _authority_property(
        "resources.switch_commanded_only_when_held",
        "RES-05",
        "001 §3.2",
        "The train commands a switch only if it holds the switch resource.",
        _switch_command,
    ),
    _authority_property(
        "resources.release_when_behind_rear",
        "RES-07",
        "001 §3.2 (Fig. 5)",
        "A held resource that lies wholly behind the min safe rear is released once that rear is confirmed.",
        _release_when_behind,
    ),
)

__all__ = ["PROPERTIES"]
