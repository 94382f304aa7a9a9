"""Where spacing and orthogonal grid lines apply, as the routes write them: a 2D domain's
sides, a six-faced domain's patches (``SIDE=H`` and ``PATCH=H`` items, lists of names)."""

from __future__ import annotations

import math
import re

from pinn_engine.errors import InputError, SettingsError
from pinn_engine.patchnames import FACE_PREFIX
from pinn_engine.settings.limits import BOX_SIDES

SIDE_NAMES = ("bottom", "right", "top", "left")


def parse_sides(value) -> tuple[str, ...]:
    """Sides from "bottom,left", a list of names or None, in SIDE_NAMES order, checked."""
    if value is None or value == "":
        return ()
    names = value.split(",") if isinstance(value, str) else list(value)
    names = [str(n).strip().lower() for n in names if str(n).strip()]
    bad = [n for n in names if n not in SIDE_NAMES]
    if bad:
        raise SettingsError(f"unknown side {bad[0]!r}; use {', '.join(SIDE_NAMES)}")
    return tuple(s for s in SIDE_NAMES if s in names)


def parse_spacing(value) -> tuple[tuple[str, float], ...]:
    """First-edge spacings from a dict {side: H}, pairs, "side=H" strings (one or a list, or
    "bottom=1e-3,top=0.01"), checked: H a finite positive number, each side at most once."""
    if value is None or value == "" or (hasattr(value, "__len__") and len(value) == 0):
        return ()
    if isinstance(value, dict):
        items = list(value.items())
    else:
        parts = value.split(",") if isinstance(value, str) else list(value)
        items = []
        for part in parts:
            if isinstance(part, str):
                side, sep, h = part.partition("=")
                if not sep:
                    raise SettingsError(f"spacing {part!r}: write SIDE=H, e.g. bottom=0.001")
                items.append((side, h))
            else:
                side, h = part
                items.append((side, h))
    out = {}
    for side, h in items:
        side = str(side).strip().lower()
        if side not in SIDE_NAMES:
            raise SettingsError(f"spacing: unknown side {side!r}; use {', '.join(SIDE_NAMES)}")
        if side in out:
            raise SettingsError(f"spacing: side {side} given twice")
        try:
            h = float(h)
        except (TypeError, ValueError):
            raise SettingsError(f"spacing {side}={h!r}: H must be a number") from None
        if not (0 < h < float("inf")):
            raise SettingsError(f"spacing {side}={h}: H must be a finite length > 0")
        out[side] = h
    return tuple((s, out[s]) for s in SIDE_NAMES if s in out)


# a six-faced domain's patch as --spacing and --orthogonal name it: a side, or faceN (the
# input face whose FaceId is N, resolved to its side once the surface is read)
HEXA_PATCH = re.compile(rf"^({'|'.join(BOX_SIDES)}|{FACE_PREFIX}[0-9]+)$")
HEXA_PATCH_NAMES = ", ".join(BOX_SIDES) + " or faceN"


def parse_patch_spacing(items) -> tuple[tuple[str, float], ...]:
    """A six-faced domain's ``PATCH=H`` items (or (PATCH, H) pairs), checked, in the route's
    words: the first edge H > 0 leaving each patch imin ... kmax (or faceN) given."""
    names = HEXA_PATCH_NAMES
    out: dict[str, float] = {}
    for part in items.items() if hasattr(items, "items") else items or ():
        item = part if isinstance(part, str) else f"{part[0]}={part[1]}"
        name, sep, value = item.partition("=")
        name = name.strip().lower()
        try:
            h = float(value)
        except ValueError:
            h = math.nan
        if not sep or not HEXA_PATCH.match(name) or not (math.isfinite(h) and h > 0):
            raise InputError(f"{{spacing}} {item}: write PATCH=H with H > 0, PATCH one of {names}")
        if out.setdefault(name, h) != h:
            raise InputError(f"{{spacing}} {item}: patch {name} is given two spacings")
    return tuple(out.items())


def parse_patch_walls(items) -> tuple[str, ...]:
    """A six-faced domain's orthogonal patches from ``PATCH[,PATCH...]`` items (imin ...
    kmax or faceN), checked."""
    names = HEXA_PATCH_NAMES
    walls = []
    for item in ([items] if items else []) if isinstance(items, str) else items or ():
        for name in item.split(","):
            name = name.strip().lower()
            if not HEXA_PATCH.match(name):
                raise InputError(f"{{orthogonal}} {item}: unknown patch {name!r}; use {names}")
            walls.append(name)
    return tuple(dict.fromkeys(walls))
