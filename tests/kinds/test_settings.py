"""Every kind's settings: each field of its class has one rule in its table, and each rule
refuses an invalid value, as scikit-learn's ``check_param_validation`` checks every
estimator's ``_parameter_constraints``; the values routes and saved models give are read."""

from __future__ import annotations

import math
from dataclasses import fields

import pytest

from pinn_engine.errors import InputError, SettingsError
from pinn_engine.settings import (
    KIND_SETTINGS,
    Counts,
    Interval,
    Options,
    Pattern,
    Places,
    Settings,
    make_settings,
    option_constraints,
    read_settings,
)

KINDS = sorted(KIND_SETTINGS)
RULES = [(kind, name) for kind in KINDS for name in sorted(KIND_SETTINGS[kind].CONSTRAINTS)]


def invalid_values(rule) -> list:
    """Values ``rule`` must refuse, by its kind (scikit-learn's generate_invalid_param_val)."""
    if isinstance(rule, Options):
        return ["".join(map(str, rule.values)) + "?", None]
    if isinstance(rule, Interval):
        below = [rule.low - 1, None, math.nan if rule.kind is float else 1.5]
        return below + ([rule.high + 1] if rule.high < math.inf else [])
    if isinstance(rule, Pattern):
        return ["#", 7]
    if isinstance(rule, Counts):
        wrong_length = max(rule.lengths) + 1
        return [(rule.low - 1,) * max(rule.lengths), (rule.low,) * wrong_length]
    if isinstance(rule, Places):
        place = rule.names[-1] if rule.names else "kmin"
        spaced = [((place, 0.0),), (("middle", 0.1),), ((place, 0.1), (place, 0.2))]
        return spaced if rule.spaced else [("middle",), (7,), (place, place)]
    raise AssertionError(f"a rule of a kind this test does not know: {rule!r}")


def test_every_kind_has_a_settings_class_over_the_core():
    assert KINDS == ["blocks", "blocks3d", "body", "four_sided", "hexa"]
    core = {f.name for f in fields(Settings)}
    for cls in KIND_SETTINGS.values():
        assert issubclass(cls, Settings) and core <= {f.name for f in fields(cls)}
    # each is its kind's package's own
    assert all(
        cls.__module__ == f"pinn_engine.kinds.{k}.settings" for k, cls in KIND_SETTINGS.items()
    )


@pytest.mark.parametrize("kind", KINDS)
def test_every_field_of_a_kind_has_exactly_one_rule(kind):
    cls = KIND_SETTINGS[kind]
    names = [f.name for f in fields(cls)]
    assert sorted(names) == sorted(cls.CONSTRAINTS), set(names) ^ set(cls.CONSTRAINTS)


@pytest.mark.parametrize("kind, name", RULES)
def test_each_rule_passes_the_default_and_refuses_invalid_values(kind, name):
    cls = KIND_SETTINGS[kind]
    rule, default = cls.CONSTRAINTS[name], getattr(make_settings(kind=kind), name)
    assert rule.problem(default) is None
    for bad in invalid_values(rule):
        assert rule.problem(bad), (kind, name, bad)
        with pytest.raises((SettingsError, InputError)):  # the kind's class refuses it
            cls(**{name: bad})


def test_a_kind_narrows_the_core_where_it_takes_less():
    body, hexa = KIND_SETTINGS["body"], KIND_SETTINGS["hexa"]
    with pytest.raises(SettingsError, match="O- and C-grids are made by"):
        make_settings("mgnet", topology="o")
    with pytest.raises(SettingsError, match="takes bottom=H"):
        make_settings(topology="c", spacing="top=0.1")
    with pytest.raises(InputError, match="six-faced 3D domains are meshed by"):
        make_settings("mgnet", size=(9, 9, 9))
    assert body.CONSTRAINTS["method"].problem("mgnet") and hexa.CONSTRAINTS["size"].problem(())


def test_another_kinds_setting_is_refused_in_one_line():
    with pytest.raises(SettingsError, match="farfield: a setting of body domains"):
        make_settings(farfield=20.0)
    with pytest.raises(SettingsError, match="needs topology o or c"):
        make_settings(naca="0012")
    assert type(make_settings(topology="none")).__name__ == "FourSidedSettings"


def test_a_route_option_rule_is_a_kinds_rule():
    """The routes' generic options (the command line's flags) take their rules from the
    kinds' tables: the core's, each kind's own, and a route's topology none."""
    for name, rule in option_constraints().items():
        tables = [
            cls.CONSTRAINTS[name] for cls in KIND_SETTINGS.values() if name in cls.CONSTRAINTS
        ]
        assert rule in tables or name == "topology", name


@pytest.mark.parametrize(
    "name, value",
    [
        ("lattice", [81, 41]),  # a saved model's JSON list
        ("size", [9, 8]),
        ("size", ()),
        ("spacing", "bottom=1e-3,top=0.01"),
        ("spacing", {"bottom": 0.001}),
        ("orthogonal", "left,bottom"),
        ("device", "cuda:1"),
    ],
)
def test_shaped_settings_are_read_then_pass_their_rule(name, value):
    read = getattr(Settings.read(**{name: value}), name)
    assert Settings.CONSTRAINTS[name].problem(read) is None


def test_a_six_faced_domain_takes_patches():
    s = make_settings(size=(9, 9, 9), spacing=("kmin=0.01",), orthogonal=("face3",))
    assert type(s) is KIND_SETTINGS["hexa"]
    assert s.spacing == (("kmin", 0.01),) and s.orthogonal == ("face3",)


def test_settings_are_read_back_as_their_kind():
    """A saved model's settings (``to_dict``), and an older build's holding every kind's
    settings at their defaults, read back as the kind's class."""
    for settings in (make_settings(topology="c", naca="2412"), make_settings(size=(5, 5, 5))):
        assert read_settings(settings.to_dict()) == settings
    older = {**make_settings().to_dict(), "topology": "none", "cell_size": 0.0, "face_angle": 40.0}
    assert read_settings(older) == make_settings()
