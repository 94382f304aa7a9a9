"""Each kind's settings class by its name, and the settings of a run from a method, a preset
and overrides (``make_settings``) or from a saved model (``read_settings``)."""

from __future__ import annotations

import functools
from dataclasses import asdict, fields

from pinn_engine.errors import SettingsError, unknown_name
from pinn_engine.settings.core import Settings
from pinn_engine.settings.limits import HEXA_SIZE, TOPOLOGIES
from pinn_engine.settings.rules import (
    CORE_CONSTRAINTS,
    SHAPED_CONSTRAINTS,
    Interval,
    Options,
    Pattern,
)

# Each kind's settings class by its name (``register``): its package registers it on import,
# as meshio's formats register their readers, so that ``make_settings`` and ``read_settings``
# find the class of the kind their values describe
KIND_SETTINGS: dict[str, type[Settings]] = {}


def register(kind: str):
    """A class decorator: ``cls`` is the settings class of ``kind``."""

    def add(cls: type[Settings]) -> type[Settings]:
        KIND_SETTINGS[kind] = cls
        return cls

    return add


def settings_kind(values: dict) -> str:
    """The kind whose settings ``values`` describe, where a route or a saved model did not
    name it: three sizes a six-faced domain, a topology o or c a body, a cell size or
    interfaces a multi-block domain, else a four-sided domain."""
    if len(values.get("size") or ()) == len(HEXA_SIZE) or "face_angle" in values:
        return "hexa"
    if values.get("topology", "none") != "none":
        return "body"
    if "cell_size" in values or "interfaces" in values:
        return "blocks"
    return "four_sided"


@functools.cache
def option_constraints() -> dict[str, Options | Interval | Pattern]:
    """The rules of the settings the routes take as generic options (the command line's
    flags, the VTK algorithms' ``SetSetting``): the core's, then each kind's own scalar
    settings' from its table; a route's topology none is the four-sided domain."""
    rules = dict(CORE_CONSTRAINTS)
    for cls in KIND_SETTINGS.values():
        for name, rule in cls.CONSTRAINTS.items():
            if name not in CORE_CONSTRAINTS and name not in SHAPED_CONSTRAINTS:
                rules.setdefault(name, rule)
    return {**rules, "topology": Options(TOPOLOGIES)}


def setting_problem(name: str, value) -> str | None:
    """What is wrong with ``value`` for the setting ``name`` (None: nothing); each route
    prefixes its own name for the setting."""
    rule = option_constraints().get(name)
    return rule.problem(value) if rule is not None else None


def setting_names() -> frozenset[str]:
    """Every kind's settings' names."""
    return frozenset(f.name for cls in KIND_SETTINGS.values() for f in fields(cls))


def _kind_values(cls: type[Settings], values: dict) -> dict:
    """``values`` less the settings ``cls`` does not carry, where they say no more than that
    (a topology none, no NACA code); another kind's setting refused in one line."""
    own = {f.name for f in fields(cls)}
    out = {}
    for name, value in values.items():
        if name in own:
            out[name] = value
        elif name == "naca" and value:
            raise SettingsError(f"naca {value}: a NACA section needs topology o or c")
        elif (name, value) not in (("topology", "none"), ("naca", "")):
            kinds = [k for k, c in KIND_SETTINGS.items() if name in c.__dataclass_fields__]
            if not kinds:
                raise unknown_name(name, setting_names(), "setting")
            raise SettingsError(f"{name}: a setting of {' and '.join(kinds)} domains, not this one")
    return out


def read_settings(values: dict, kind: str | None = None) -> Settings:
    """The settings a saved model or report holds (``Settings.to_dict``), as the class of
    ``kind`` (or the kind they describe); other kinds' settings, which a file of an older
    build holds at their defaults, are dropped, and a name no kind has is refused."""
    shape = {name: values[name] for name in ("size", "topology") if name in values}
    cls = KIND_SETTINGS[kind or settings_kind(shape)]
    own, known = {f.name for f in fields(cls)}, setting_names()
    unknown = sorted(values.keys() - known)
    if unknown:
        raise unknown_name(unknown[0], sorted(known), "setting")
    return cls.read(**{k: v for k, v in values.items() if k in own})


PAPER = {
    "boundary_mode": "penalty",
    "boundary_fit": "tree",
    "warm_start": "none",
    "residual": "paper",
    "hidden_layers": 4,
    "neurons": 30,
    "activation": "tanh",
    "adam_epochs": 5000,
    "learning_rate": 1e-3,
    "lr_decay": 0.9,
    "lr_decay_every": 1000,
    "batch_size": 100,
    "lbfgs_iterations": 500,
    "lbfgs_points": 1000,
    "lambda2": 10.0,
    "elliptic_iterations": 1000,
    "objective": "winslow",
}


# Training from TFI (no warm start) takes the paper's schedule and losses.
FROM_TFI = {
    "adam_epochs": 5000,
    "lbfgs_iterations": 500,
    "lbfgs_points": 1000,
    "lambda2": 10.0,
    "residual": "paper",
    "objective": "winslow",
}


def make_settings(
    method: str = "pinn", preset: str = "default", kind: str | None = None, **overrides
) -> Settings:
    """Settings of ``kind`` (``KIND_SETTINGS``; None: the kind ``overrides`` describe,
    ``settings_kind``) for ``method`` under ``preset``, then ``overrides`` (None values
    ignored).

    The elliptic warm start needs the hard boundary: asking for the penalty boundary without
    naming a warm start turns it off, and a run without warm start gets the schedule and
    losses of ``FROM_TFI`` unless they are given. A kind's ``OVER_PRESET`` settings (a
    six-faced domain's L-BFGS iterations) apply unless told otherwise.
    """
    given = {k: v for k, v in overrides.items() if v is not None}
    cls = KIND_SETTINGS[kind or settings_kind(given)]
    given = _kind_values(cls, given)
    if given.get("objective") == "quality" and method != "pinn":
        raise SettingsError(f"objective quality is for the pinn method, not {method}")
    if given.get("boundary_mode") == "penalty" and "warm_start" not in given:
        given["warm_start"] = "none"
    if given.get("warm_start") == "none" and preset == "default":
        given = {**FROM_TFI, **given}
    base = cls.read(method=method, preset=preset)
    values = {**asdict(base), **(PAPER if preset == "paper" else {})}
    return cls.read(**{**values, **cls.OVER_PRESET, **given})
