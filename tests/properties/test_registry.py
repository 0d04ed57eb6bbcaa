"""The property registry: each module ``properties/<prefix>.py`` holds exactly the properties named
``<prefix>.*``, and every such module is registered."""

import importlib
import pkgutil
import re

import atcs.properties
from atcs.properties import PROPERTIES
from atcs.properties.property import Property

# modules of the package that hold no properties of their own (configured: a configuration's, made on demand;
# envelope: a configuration's over a cell of its ranges)
HELPERS = {"configured", "envelope", "property", "under_train"}


def _property_modules() -> dict[str, object]:
    names = [m.name for m in pkgutil.iter_modules(atcs.properties.__path__) if m.name not in HELPERS]
    return {name: importlib.import_module(f"atcs.properties.{name}") for name in names}


def test_each_module_holds_exactly_its_prefix():
    for name, module in _property_modules().items():
        props = module.PROPERTIES
        assert props, f"properties/{name}.py holds no property"
        assert all(isinstance(p, Property) for p in props)
        stray = [p.name for p in props if p.module != name]
        assert not stray, f"properties/{name}.py holds properties of another module: {stray}"


def test_every_property_lives_in_its_module_and_is_registered():
    modules = _property_modules()
    in_modules = {p.name for m in modules.values() for p in m.PROPERTIES}
    assert in_modules == set(PROPERTIES), "a module's properties are not all registered, or the reverse"
    for name, prop in PROPERTIES.items():
        assert prop.module in modules, f"{name}: no module properties/{prop.module}.py"
        assert prop in modules[prop.module].PROPERTIES


def test_helper_modules_hold_no_properties():
    for name in HELPERS:
        module = importlib.import_module(f"atcs.properties.{name}")
        assert not isinstance(getattr(module, "PROPERTIES", None), tuple), f"properties/{name}.py registers properties"


def test_a_requirement_id_names_one_claim():
    """Properties share a requirement id only as variants of one claim (a train preset, a braking mode, a curve
    model): two different claims under one id would make the catalogue ambiguous."""
    variant = re.compile(r"(_(bw|rbd|seed\d+|stepped|gamma|lambda))+$")
    claims: dict[str, set[str]] = {}
    for prop in PROPERTIES.values():
        claims.setdefault(prop.requirement, set()).add(variant.sub("", prop.name))
    shared = {req: sorted(names) for req, names in claims.items() if len(names) > 1}
    assert not shared, shared
