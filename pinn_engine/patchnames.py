"""The rules of a patch's name and type (SPEC 8): pure Python, so that every layer that
names patches (the four-sided routes, multi-block pieces, the exports) checks them alike."""

from __future__ import annotations

import re

from pinn_engine.errors import InputError

FACE_PREFIX = "face"  # faceN names the input face whose FaceId is N (SPEC 11's --patch)
SIDE_FIX = "{patch}"  # the route token (errors.ROUTE_WORDS) where a grid's side names are set
NAME = re.compile(r"^[A-Za-z0-9_-]{1,32}$")
FRONT_AND_BACK = "frontAndBack"  # the two ends of an extruded output
# A patch's type (``NAME:TYPE``), as each format writes it: OpenFOAM's patch type, CGNS's
# BCType. "patch" is the untyped default (OpenFOAM's generic patch, CGNS user-defined).
TYPES = {
    "wall": ("wall", "BCWall"),
    "inflow": ("patch", "BCInflow"),
    "outflow": ("patch", "BCOutflow"),
    "farfield": ("patch", "BCFarfield"),
    "symmetry": ("symmetryPlane", "BCSymmetryPlane"),
    "patch": ("patch", "BCTypeUserDefined"),
}


def default_type(name: str) -> str:
    """A patch named ``wall`` (a body's wall, or a side the user calls so) is a wall."""
    return "wall" if name.lower() == "wall" else "patch"


def split_type(item: str, fix: str = SIDE_FIX) -> tuple[str, str | None]:
    """``NAME`` or ``NAME:TYPE`` -> (name, type or None), the type checked (``fix``: the
    route token an error names)."""
    name, sep, kind = item.partition(":")
    if not sep:
        return name.strip(), None
    kind = kind.strip().lower()
    if kind not in TYPES:
        raise InputError(f"patch type {kind!r} of {name.strip()!r}: use {', '.join(TYPES)} ({fix})")
    return name.strip(), kind


def checked_name(name: str, fix: str = SIDE_FIX) -> str:
    """``name`` if it is a valid patch name, else a one-line error naming ``fix``."""
    if not NAME.match(name):
        raise InputError(f"patch name {name!r}: use 1 to 32 letters, digits, '_' or '-' ({fix})")
    if name.lower() == FRONT_AND_BACK.lower():
        raise InputError(
            f"patch name {name!r} is reserved for the two ends of extruded "
            f"outputs; choose another ({fix})"
        )
    return name
