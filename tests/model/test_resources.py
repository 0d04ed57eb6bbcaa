"""Resource request and release (seed 001 §3.2, Fig. 5): proved, able to fail, and checked in simulation on
more trains and resources than the proof covers."""

from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from atcs.model.node import Stateless
from atcs.model.ops.exact import EXACT
from atcs.model.resources import HELD, RESOURCES, ResourceInputs, ResourceState
from atcs.proofs.mutation.mutants import falsify
from atcs.properties import PROPERTIES, select
from atcs.sim.monitor import Monitor

RESOURCE_PROPERTIES = [p for p in select("resources.*") if p.node is RESOURCES]

# property -> (text in resource_step, its faulty replacement)
MUTANTS = {
    # a train takes a refusal for a grant
    "resources.protocol_consistent": (
        "settled = o.ite(is_(s.down[j], GRANT), code(HELD), code(FREE))",
        "settled = o.ite(is_(s.down[j], CONFIRM), code(FREE), code(HELD))",
    ),
    # the manager grants a resource another train owns
    "resources.mutual_exclusion": ("o.ite(free, code(GRANT), code(REFUSE))", "code(GRANT)"),
    # a train keeps counting on a resource once it has sent its release
    "resources.manager_records_holder": (
        "o.ite(releases, code(RELEASING), after_reply)",
        "o.ite(releases, code(HELD), after_reply)",
    ),
    # a train sends a request or release it was not asked to send
    "resources.idle_slot_unchanged": (
        "sends = o.and_(i.send[j], o.not_(reply), is_(s.up[j], NO_MESSAGE))",
        "sends = o.and_(o.not_(reply), is_(s.up[j], NO_MESSAGE))",
    ),
    # the manager leaves a delivered message in flight (atcs mutate's not_drop at resource_step:+15)
    "resources.delivery_consumes": (
        "arrives = o.and_(i.deliver_up[j], o.not_(is_(s.up[j], NO_MESSAGE)))",
        "arrives = o.and_(i.deliver_up[j], is_(s.up[j], NO_MESSAGE))",
    ),
    # the manager handles a message before it is delivered (bool_swap at resource_step:+15)
    "resources.manager_acts_on_delivery": (
        "arrives = o.and_(i.deliver_up[j], o.not_(is_(s.up[j], NO_MESSAGE)))",
        "arrives = o.or_(i.deliver_up[j], o.not_(is_(s.up[j], NO_MESSAGE)))",
    ),
    # a resource counted free only while train 1 owns it, so never granted (atcs mutate's literal at
    # resource_step:+17)
    "resources.grants_free_resource": ("free, mine = is_(owner[r], 0)", "free, mine = is_(owner[r], 1)"),
    # a train sends only in a cycle a reply arrives, so never (not_drop at resource_step:+28)
    "resources.sends_when_commanded": (
        "sends = o.and_(i.send[j], o.not_(reply), is_(s.up[j], NO_MESSAGE))",
        "sends = o.and_(i.send[j], reply, is_(s.up[j], NO_MESSAGE))",
    ),
}


def test_every_resource_property_has_a_mutant():
    assert set(MUTANTS) == {p.name for p in RESOURCE_PROPERTIES}


@pytest.mark.parametrize("prop", RESOURCE_PROPERTIES, ids=lambda p: p.name)
def test_proved_by_k_induction(prop, proof_suite_run):
    record = proof_suite_run.by_name[prop.name]  # the session's atcs prove run (conftest.py)
    assert (record["status"], record["engine"]) == ("proved", "k-induction"), record["message"]


@pytest.mark.parametrize("name", sorted(MUTANTS))
def test_mutant_falsified_and_counterexample_replays(name):
    run = falsify(PROPERTIES[name], RESOURCES.step, *MUTANTS[name], max_k=8)
    assert run.killed, run


def test_two_trains_contend_for_one_resource():
    """Both request in the same cycle: the first in slot order gets it, the other is refused."""
    trains, resources = 2, 1
    state = ResourceState(
        owner=(Fraction(0),), holding=(Fraction(0),) * 2, up=(Fraction(0),) * 2, down=(Fraction(0),) * 2
    )
    monitor = Monitor(RESOURCES, Stateless(), state, tuple(RESOURCE_PROPERTIES), ops=EXACT)
    everyone = (True,) * (trains * resources)
    nobody = (False,) * (trains * resources)
    monitor.step(ResourceInputs(send=everyone, deliver_up=nobody, deliver_down=nobody))
    monitor.step(ResourceInputs(send=nobody, deliver_up=everyone, deliver_down=nobody))
    out = monitor.step(ResourceInputs(send=nobody, deliver_up=nobody, deliver_down=everyone))
    assert out.held == (True, False) and monitor.state.owner == (1,)


@settings(max_examples=60)
@given(trains=st.integers(2, 5), resources=st.integers(1, 4), data=st.data())
def test_random_delivery_keeps_every_predicate(trains, resources, data):
    """Random sends and random delivery (any delay, any order) for up to 5 trains and 4 resources: every
    resource property's predicate holds at every cycle."""
    slots = trains * resources
    zero = (Fraction(0),)
    state = ResourceState(owner=zero * resources, holding=zero * slots, up=zero * slots, down=zero * slots)
    monitor = Monitor(RESOURCES, Stateless(), state, tuple(RESOURCE_PROPERTIES), ops=EXACT)
    flags = st.tuples(*[st.booleans()] * slots)
    for _ in range(data.draw(st.integers(10, 60))):
        monitor.step(ResourceInputs(send=data.draw(flags), deliver_up=data.draw(flags), deliver_down=data.draw(flags)))
        assert sum(h == HELD for h in monitor.state.holding) <= resources
    assert all(monitor.applies(p.name) for p in RESOURCE_PROPERTIES)
