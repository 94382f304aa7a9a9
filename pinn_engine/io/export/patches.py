"""Boundary patch names of a grid's four sides (SPEC 8), VTK and numpy only.

A grid carries its patch names as the field-data string array ``PatchNames`` (bottom,
right, top, left order) and its structured indices as the point arrays ``i`` and ``j``.
Sides with the same name form one patch.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonCore import vtkStringArray

from pinn_engine.errors import InputError

SIDES = ("bottom", "right", "top", "left")
DEFAULT = SIDES
NAME = re.compile(r"^[A-Za-z0-9_-]{1,32}$")
FIELD = "PatchNames"
FRONT_AND_BACK = "frontAndBack"  # the two ends of an extruded output


def _checked(name: str) -> str:
    if not NAME.match(name):
        raise InputError(
            f"patch name {name!r}: use 1 to 32 letters, digits, '_' or '-' ({{patch}})"
        )
    if name.lower() == FRONT_AND_BACK.lower():
        raise InputError(
            f"patch name {name!r} is reserved for the two ends of extruded "
            "outputs; choose another ({patch})"
        )
    return name


def body_patch_names(topology: str) -> tuple[str, str, str, str]:
    """PatchNames (bottom, right, top, left) of a body grid: the O-grid's left and right
    sides are the seam, the C-grid's are the outflow; the C-grid's bottom side holds the
    wall and the wake cut (field data ``Topology`` and ``WakeNodes`` tell them apart)."""
    return (
        ("wall", "seam", "farfield", "seam")
        if topology == "o"
        else ("wall", "outflow", "farfield", "outflow")
    )


def parse_patch_options(
    items: Sequence[str] | None, default: Sequence[str] = DEFAULT
) -> tuple[str, ...]:
    """Patch names from ``SIDE=NAME`` items (the command line's ``--patch``); sides not
    named keep ``default``'s."""
    names = dict(zip(SIDES, default))
    for item in items or ():
        side, sep, name = item.partition("=")
        side = side.strip().lower()
        if not sep or side not in names:
            raise InputError(
                f"patch {item!r}: expected SIDE=NAME with SIDE one of "
                f"{', '.join(SIDES)} ({{patch}})"
            )
        names[side] = _checked(name.strip())
    return tuple(names[s] for s in SIDES)


def patch_names(
    patches: Mapping[str, str] | Sequence[str] | str | None, default: Sequence[str] = DEFAULT
) -> tuple[str, ...]:
    """The four patch names (bottom, right, top, left) from any of the routes' forms.

    ``None``: ``default`` (bottom, right, top, left; a body grid's: wall, seam or outflow,
    far field); a mapping ``{"bottom": "wall", ...}`` (sides not named keep their default);
    a sequence of four names or of ``SIDE=NAME`` items (``--patch``); or a string of four
    names or ``SIDE=NAME`` items separated by spaces or commas (the ParaView panel's field).
    """
    if patches is None:
        return tuple(default)
    if isinstance(patches, str):
        items = [t for t in re.split(r"[\s,;]+", patches) if t]
        if not items:
            return tuple(default)
        if all("=" in t for t in items):
            return parse_patch_options(items, default)
        patches = items
    if isinstance(patches, Mapping):
        return parse_patch_options([f"{k}={v}" for k, v in patches.items()], default)
    names = [str(n).strip() for n in patches]
    if names and all("=" in n for n in names):  # the command line's --patch items
        return parse_patch_options(names, default)
    if len(names) != 4 or any("=" in n for n in names):
        raise InputError(
            f"patch names {' '.join(names)!r}: give four names (bottom, right, "
            "top, left) or SIDE=NAME items ({patch})"
        )
    return tuple(_checked(n) for n in names)


def groups(names: Sequence[str]) -> dict[str, list[str]]:
    """Patch name -> its sides, in the order the names first appear."""
    out: dict[str, list[str]] = {}
    for side, name in zip(SIDES, names):
        out.setdefault(name, []).append(side)
    return out


def add_to_grid(grid, names: Sequence[str]) -> None:
    """Put ``PatchNames`` (field data) and the point arrays ``i``, ``j`` on ``grid``."""
    fd = grid.GetFieldData()
    fd.RemoveArray(FIELD)
    arr = vtkStringArray()
    arr.SetName(FIELD)
    for name in names:
        arr.InsertNextValue(name)
    fd.AddArray(arr)
    ext = grid.GetExtent()
    ni, nj = ext[1] - ext[0] + 1, ext[3] - ext[2] + 1
    jj, ii = np.mgrid[0:nj, 0:ni]
    for key, values in (("i", ii), ("j", jj)):
        data = numpy_to_vtk(np.ascontiguousarray(values.ravel(), dtype=np.int32), deep=True)
        data.SetName(key)
        grid.GetPointData().AddArray(data)


def of_grid(grid) -> tuple[str, ...]:
    """The patch names a grid carries, or the defaults."""
    arr = grid.GetFieldData().GetAbstractArray(FIELD)
    if arr is None or arr.GetNumberOfValues() != 4:
        return DEFAULT
    return patch_names([arr.GetValue(k) for k in range(4)])
