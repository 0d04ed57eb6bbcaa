"""The property registry and the validation of property definitions."""

import dataclasses

import pytest

from atcs.model import NODES
from atcs.properties import PROPERTIES, select
from atcs.properties.property import Property

EB = PROPERTIES["supervision.eb_above_ebi"]


class TestRegistry:
    def test_names_are_module_first_and_nodes_registered(self):
        for name, prop in PROPERTIES.items():
            assert name == prop.name and prop.module.isidentifier(), name
            assert NODES.get(prop.node.name) is prop.node, f"{name}: node {prop.node.name!r} is not in model.NODES"

    def test_every_property_is_documented(self):
        for prop in PROPERTIES.values():
            assert prop.requirement and prop.seed and prop.text.endswith("."), prop.name

    def test_select_by_glob(self):
        assert select("supervision.eb_*") == [
            EB,
            PROPERTIES["supervision.eb_latched_until_standstill"],
            PROPERTIES["supervision.eb_without_position"],
        ]
        assert select("nosuch.*") == []
        assert select() == list(PROPERTIES.values())


class TestValidation:
    @pytest.mark.parametrize("name", ["eb_above_ebi", "Supervision.eb", "supervision.", "supervision.eb-above"])
    def test_bad_name(self, name):
        with pytest.raises(ValueError, match="must be dotted lower-case words"):
            dataclasses.replace(EB, name=name)

    def test_bad_max_k(self):
        with pytest.raises(ValueError, match="max_k must be a non-negative int, got -1"):
            dataclasses.replace(EB, max_k=-1)

    def test_fixed_param_must_exist(self):
        with pytest.raises(ValueError, match=r"'brakes_fitted', which is not a parameter .* service_brake_fitted"):
            Property("supervision.x", "R", "S", "T.", EB.node, EB.holds, fixed_params={"brakes_fitted": True})


@pytest.mark.parametrize("prop", list(PROPERTIES.values()), ids=list(PROPERTIES))
def test_assumptions_are_satisfiable_from_an_initial_state(prop):
    """A proof under contradictory assumptions would be vacuous: each property's assumptions admit a first step."""
    import z3

    from atcs.proofs.engine.system import Unrolling

    u = Unrolling(prop)
    solver = z3.Solver()
    solver.add(u.init(), u.frame(0).trans, u.frame(0).assumed)
    assert solver.check() == z3.sat
