"""The ParaView panels as data (``routes.panel``): each property's label is its option's on
every route (``routes.names``), its range and default the constraint table's and Settings',
and its values reach a method the filter's algorithm has, which takes its default."""

from __future__ import annotations

import pytest

from pinn_engine.routes.airfoil_algorithm import AirfoilSource
from pinn_engine.routes.algorithm import PinnMeshAlgorithm
from pinn_engine.routes.dictionary_algorithm import PinnBlockMeshDictReader
from pinn_engine.routes.hexa_algorithm import PinnHexaAlgorithm
from pinn_engine.routes.multiblock_algorithm import PinnMultiBlockAlgorithm
from pinn_engine.routes.names import NAMES
from pinn_engine.routes.panel import PANELS
from pinn_engine.settings import (
    DICTIONARY_METHODS,
    KIND_SETTINGS,
    Interval,
    Settings,
    option_constraints,
)

ALGORITHMS = {"four-sided": PinnMeshAlgorithm, "blocks": PinnMultiBlockAlgorithm}
ALGORITHMS |= {"hexa": PinnHexaAlgorithm, "dictionary": PinnBlockMeshDictReader}
ALGORITHMS["airfoil"] = AirfoilSource
CASES = [(kind, prop) for kind, panel in PANELS.items() for prop in panel]


@pytest.mark.parametrize(("kind", "prop"), CASES, ids=[f"{k}-{p.name}" for k, p in CASES])
def test_a_property_sets_its_algorithm_from_its_default(kind, prop):
    """The property's default, as ParaView passes it, is taken by the algorithm's method."""
    alg = ALGORITHMS[kind]()
    values = prop.default if isinstance(prop.default, list) else [prop.default]
    getattr(alg, prop.call)(*prop.before, *map(prop.convert, values))


@pytest.mark.parametrize(("kind", "prop"), CASES, ids=[f"{k}-{p.name}" for k, p in CASES])
def test_a_property_of_an_option_shows_its_label_range_and_default(kind, prop):
    """An option's property is labelled as the option on every route unless the panel says
    otherwise (a preset's twin, a body's wall, the four sides); a setting's whole-number
    range and default are the constraint table's and Settings'."""
    if prop.option is None:
        assert prop.shown is None  # ParaView shows its name
        return
    assert prop.shown == (prop.label or NAMES[prop.option].label)
    rule = option_constraints().get(prop.option)
    if prop.call in ("SetPanelSetting", "SetPresetSetting") and "paper" not in prop.before:
        default = prop.enum[prop.default] if prop.enum else prop.default
        assert default == getattr(Settings(), prop.option) or prop.option == "time_limit"
        if isinstance(rule, Interval) and rule.kind is int and prop.bounds:
            assert prop.bounds == {"min": int(rule.low), "max": int(rule.high)}


def test_the_panels_order_their_properties_once():
    """Each panel's method names are distinct and carry their P-number (ParaView 5.11 lists
    the properties by it)."""
    for panel in PANELS.values():
        methods = [prop.method for prop in panel]
        assert len(set(methods)) == len(methods)
        assert all(m[0] == "P" and m[1:3].isdigit() for m in methods)


def test_the_reader_and_source_panels_take_the_kinds_choices_and_defaults():
    """The blockMeshDict reader's choices are the blocks3d kind's (its methods, its table's
    interfaces) and the Airfoil source's defaults its algorithm's."""
    method, interfaces = PANELS["dictionary"]
    assert method.enum == DICTIONARY_METHODS and method.enum[method.default] == "pinn"
    rule = KIND_SETTINGS["blocks3d"].CONSTRAINTS["interfaces"]
    assert interfaces.enum == rule.values and interfaces.enum[interfaces.default] == "free"
    naca, sharp = PANELS["airfoil"]
    source = AirfoilSource()
    assert (naca.default, bool(sharp.default)) == (source._code, source._sharp)
