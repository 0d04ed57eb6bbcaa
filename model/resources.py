"""Resource request and release between the trains and the wayside resource manager (seed 001 §3.2, Fig. 5).

The resource manager records the owner of each track and switch resource and never
lets two trains hold the same one (seed 001: "the resource manager is a database of
the occupied resources and their owners that prevents one resource being occupied by
two or more trains at once"). The procedure of Fig. 5 as messages:

- a train *requests* a free resource; the manager *grants* it if nobody owns it, else
  *refuses*; the train holds the resource once the grant arrives;
- a train *releases* a resource it holds (behind its min safe rear, decided onboard):
  it stops counting on it when it sends the release; the manager frees it and
  *confirms*; the train may request it again only after the confirmation.

Per (train, resource) there is one message slot each way, so at most one exchange is
open at a time; each cycle the environment chooses which trains send (for any
resources: which ones to request is the onboard node's choice), and which messages in
flight are delivered, in any order and after any delay. The manager handles the
requests delivered in one cycle in slot order (train 0 first).

Slot ``j = train * resources + resource``; codes are in :data:`HOLDING`, :data:`UP`
and :data:`DOWN`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Generic

from atcs.model.node import Node, Stateless
from atcs.model.ops import B, N, Ops

FREE, REQUESTED, HELD, RELEASING = 0, 1, 2, 3
HOLDING = {FREE: "free", REQUESTED: "requested", HELD: "held", RELEASING: "releasing"}
"""A train's view of one resource."""
NO_MESSAGE, REQUEST, RELEASE = 0, 1, 2
UP = {NO_MESSAGE: "none", REQUEST: "request", RELEASE: "release"}
"""The message in flight from a train to the manager."""
GRANT, REFUSE, CONFIRM = 1, 2, 3
DOWN = {NO_MESSAGE: "none", GRANT: "grant", REFUSE: "refuse", CONFIRM: "release confirmed"}
"""The message in flight from the manager to a train."""

PROOF_TRAINS = 3
PROOF_RESOURCES = 3
"""The sizes the proofs cover: 3 trains contending for 3 resources (9 slots)."""
PROOF_SLOTS = PROOF_TRAINS * PROOF_RESOURCES


@dataclass(frozen=True)
class ResourceState(Generic[N, B]):
    owner: tuple[N, ...]
    """Per resource: the manager's record, 0 for free or ``train + 1``."""
    holding: tuple[N, ...]
    """Per slot: the train's view of the resource (:data:`HOLDING`)."""
    up: tuple[N, ...]
    """Per slot: the message in flight to the manager (:data:`UP`)."""
    down: tuple[N, ...]
    """Per slot: the message in flight to the train (:data:`DOWN`)."""


@dataclass(frozen=True)
class ResourceInputs(Generic[N, B]):
    send: tuple[B, ...]
    """Per slot: the train requests the resource (if free to it) or releases it (if held)."""
    deliver_up: tuple[B, ...]
    """Per slot: the message to the manager arrives this cycle."""
    deliver_down: tuple[B, ...]
    """Per slot: the message to the train arrives this cycle."""


@dataclass(frozen=True)
class ResourceOutputs(Generic[N, B]):
    held: tuple[B, ...]
    """Per slot after this cycle: the train counts on the resource (for its movement authority)."""


def slot_count(s: ResourceState) -> tuple[int, int]:
    """``(trains, resources)`` of a state."""
    resources = len(s.owner)
    return len(s.holding) // resources, resources


def resource_init(o: Ops, p: Stateless, s: ResourceState):
    """Nothing owned, requested or in flight."""
    zero = o.const(0)
    return o.and_(*(o.eq(v, zero) for v in (*s.owner, *s.holding, *s.up, *s.down)))


def resource_step(o: Ops, p: Stateless, s: ResourceState, i: ResourceInputs):
    """One cycle: trains send, the manager handles what arrives (in slot order), trains take the replies."""
    trains, resources = slot_count(s)

    def code(value):
        return o.const(value)

    def is_(value, c):
        return o.eq(value, code(c))

    owner, holding, up, down = list(s.owner), list(s.holding), list(s.up), list(s.down)
    for j in range(trains * resources):
        train, r = divmod(j, resources)
        # the manager: a message that arrives (sent in an earlier cycle) is answered
        arrives = o.and_(i.deliver_up[j], o.not_(is_(s.up[j], NO_MESSAGE)))
        request, release = o.and_(arrives, is_(s.up[j], REQUEST)), o.and_(arrives, is_(s.up[j], RELEASE))
        free, mine = is_(owner[r], 0), is_(owner[r], train + 1)
        granted = o.and_(request, free)
        owner[r] = o.ite(granted, code(train + 1), o.ite(o.and_(release, mine), code(0), owner[r]))
        down[j] = o.ite(request, o.ite(free, code(GRANT), code(REFUSE)), o.ite(release, code(CONFIRM), down[j]))
        up[j] = o.ite(arrives, code(NO_MESSAGE), up[j])
        # the train: a reply that arrives (sent in an earlier cycle) settles the exchange
        reply = o.and_(i.deliver_down[j], o.not_(is_(s.down[j], NO_MESSAGE)))
        settled = o.ite(is_(s.down[j], GRANT), code(HELD), code(FREE))
        after_reply = o.ite(reply, settled, s.holding[j])
        down[j] = o.ite(reply, code(NO_MESSAGE), down[j])
        # the train sends: a request for a resource free to it, a release of one it holds
        sends = o.and_(i.send[j], o.not_(reply), is_(s.up[j], NO_MESSAGE))
        requests = o.and_(sends, is_(s.holding[j], FREE))
        releases = o.and_(sends, is_(s.holding[j], HELD))
        holding[j] = o.ite(requests, code(REQUESTED), o.ite(releases, code(RELEASING), after_reply))
        up[j] = o.ite(requests, code(REQUEST), o.ite(releases, code(RELEASE), up[j]))
    state = ResourceState(tuple(owner), tuple(holding), tuple(up), tuple(down))
    return state, ResourceOutputs(tuple(is_(h, HELD) for h in holding))


RESOURCES = Node(
    name="resources",
    params=Stateless,
    state=ResourceState,
    inputs=ResourceInputs,
    outputs=ResourceOutputs,
    init=resource_init,
    step=resource_step,
    seed="001 §3.2 (Fig. 5)",
    sizes={
        "owner": PROOF_RESOURCES,
        "holding": PROOF_SLOTS,
        "up": PROOF_SLOTS,
        "down": PROOF_SLOTS,
        "send": PROOF_SLOTS,
        "deliver_up": PROOF_SLOTS,
        "deliver_down": PROOF_SLOTS,
        "held": PROOF_SLOTS,
    },
)
