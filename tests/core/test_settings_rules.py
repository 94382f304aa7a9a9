"""Every field of Settings has one rule, and each rule refuses an invalid value, as
scikit-learn's ``check_param_validation`` checks every estimator's ``_parameter_constraints``."""

from __future__ import annotations

import math
from dataclasses import fields

import pytest

from pinn_engine.errors import SettingsError
from pinn_engine.settings import (
    PARAMETER_CONSTRAINTS,
    SHAPED_CONSTRAINTS,
    Counts,
    Interval,
    Options,
    Pattern,
    Places,
    Settings,
    make_settings,
)

RULES = {**PARAMETER_CONSTRAINTS, **SHAPED_CONSTRAINTS}


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
        if rule.spaced:
            return [(("bottom", 0.0),), (("middle", 0.1),), (("top", 0.1), ("top", 0.2))]
        return [("middle",), (7,)]
    raise AssertionError(f"a rule of a kind this test does not know: {rule!r}")


def test_every_field_has_exactly_one_rule():
    names = [f.name for f in fields(Settings)]
    assert sorted(names) == sorted(RULES), set(names) ^ set(RULES)
    assert not set(PARAMETER_CONSTRAINTS) & set(SHAPED_CONSTRAINTS)


@pytest.mark.parametrize("name", sorted(RULES))
def test_each_rule_passes_the_default_and_refuses_invalid_values(name):
    rule, default = RULES[name], getattr(make_settings(), name)
    assert rule.problem(default) is None
    for bad in invalid_values(rule):
        assert rule.problem(bad), (name, bad)
        with pytest.raises(SettingsError):  # Settings refuses it, by the rule or on reading it
            Settings(**{name: bad})


@pytest.mark.parametrize(
    "name, value",
    [
        ("lattice", [81, 41]),  # a saved model's JSON list
        ("size", (9, 8, 7)),
        ("size", ()),
        ("spacing", "bottom=1e-3,top=0.01"),
        ("spacing", {"bottom": 0.001}),
        ("orthogonal", "left,bottom"),
        ("device", "cuda:1"),
    ],
)
def test_shaped_settings_are_read_then_pass_their_rule(name, value):
    read = getattr(Settings(**{name: value}), name)
    assert SHAPED_CONSTRAINTS[name].problem(read) is None


def test_a_six_faced_domain_takes_patches():
    s = Settings(size=(9, 9, 9), spacing=("kmin=0.01",), orthogonal=("face3",))
    assert s.spacing == (("kmin", 0.01),) and s.orthogonal == ("face3",)
