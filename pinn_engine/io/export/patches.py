"""Boundary patch names of a grid's sides (SPEC 8), VTK and numpy only.

A 2D grid has four sides (bottom, right, top, left), a hexahedral grid six (imin ... kmax,
SPEC 11). A grid carries its patch names as the field-data string array ``PatchNames`` (in
its sides' order) and its structured indices as the point arrays ``i``, ``j`` (and ``k``).
Sides with the same name form one patch.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence

import numpy as np

from pinn_engine.errors import InputError
from pinn_engine.patchnames import FACE_PREFIX, SIDE_FIX, checked_name, default_type, split_type
from pinn_engine.settings import BOX_SIDES

SIDES = ("bottom", "right", "top", "left")
COUNT_WORDS = {len(SIDES): "four", len(BOX_SIDES): "six"}  # side counts as messages say them
# the route token (errors.ROUTE_WORDS) naming where the patches of that many sides are named
PATCH_FIX = {len(SIDES): SIDE_FIX, len(BOX_SIDES): "{face_patch}"}
FIELD = "PatchNames"
TYPES_FIELD = "PatchTypes"  # the boundary condition kind of each side, as PatchNames


def _checked_typed(item: str, fix: str) -> str:
    """``NAME`` or ``NAME:TYPE``, both parts checked; returned as given."""
    name, kind = split_type(item, fix)
    checked_name(name, fix)
    return item if kind is None else f"{name}:{kind}"


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
    items: Sequence[str] | None,
    default: Sequence[str] | None = None,
    sides: Sequence[str] = SIDES,
    aliases: Mapping[str, str] | None = None,
) -> tuple[str, ...]:
    """Patch names of ``sides`` from ``SIDE=NAME`` items (the command line's ``--patch``);
    sides not named keep ``default``'s (the sides' own names when None). ``aliases``: other
    names of sides (a hexahedral grid's ``faceN``, the input's own faces)."""
    names = dict(zip(sides, default or sides))
    aliases = aliases or {}
    fix = PATCH_FIX[len(sides)]
    for item in items or ():
        side, sep, name = item.partition("=")
        side = side.strip().lower()
        side = aliases.get(side, side)
        if not sep or side not in names:
            known = ", ".join([*sides, *aliases])
            raise InputError(f"patch {item!r}: expected SIDE=NAME with SIDE one of {known} ({fix})")
        names[side] = _checked_typed(name.strip(), fix)
    return tuple(names[s] for s in sides)


def patch_names(
    patches: Mapping[str, str] | Sequence[str] | str | None,
    default: Sequence[str] | None = None,
    sides: Sequence[str] = SIDES,
    aliases: Mapping[str, str] | None = None,
) -> tuple[str, ...]:
    """The patch names of ``sides`` (bottom, right, top, left; or imin ... kmax) from any
    of the routes' forms.

    ``None``: ``default`` (None: the sides' names; a body grid's: wall, seam or outflow,
    far field); a mapping ``{"bottom": "wall", ...}`` (sides not named keep their default);
    a sequence of one name a side or of ``SIDE=NAME`` items (``--patch``); or a string of
    such names or items separated by spaces or commas (the ParaView panel's field).
    ``aliases``: other names of sides in ``SIDE=NAME`` items (:func:`parse_patch_options`).
    """
    default = tuple(default or sides)
    if patches is None:
        return default
    if isinstance(patches, str):
        items = [t for t in re.split(r"[\s,;]+", patches) if t]
        if not items:
            return default
        if all("=" in t for t in items):
            return parse_patch_options(items, default, sides, aliases)
        patches = items
    if isinstance(patches, Mapping):
        items = [f"{k}={v}" for k, v in patches.items()]
        return parse_patch_options(items, default, sides, aliases)
    names = [str(n).strip() for n in patches]
    if names and all("=" in n for n in names):  # the command line's --patch items
        return parse_patch_options(names, default, sides, aliases)
    if len(names) != len(sides) or any("=" in n for n in names):
        raise InputError(
            f"patch names {' '.join(names)!r}: give {COUNT_WORDS[len(sides)]} names "
            f"({', '.join(sides)}) or SIDE=NAME items ({PATCH_FIX[len(sides)]})"
        )
    return tuple(_checked_typed(n, PATCH_FIX[len(sides)]) for n in names)


def patch_specs(
    patches: Mapping[str, str] | Sequence[str] | str | None,
    default: Sequence[str] | None = None,
    sides: Sequence[str] = SIDES,
    aliases: Mapping[str, str] | None = None,
) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The patch names of ``sides`` and their types from any of the routes' forms, where
    each name may carry ``:TYPE`` (one of ``TYPES``; default: wall for a patch named wall,
    else patch). Sides of one name must agree on its type; ``aliases`` as
    :func:`patch_names`."""
    typed = [split_type(item) for item in patch_names(patches, default, sides, aliases)]
    given: dict[str, str] = {}
    for name, kind in typed:
        if kind is not None and given.setdefault(name, kind) != kind:
            raise InputError(f"patch {name!r} is given two types, {given[name]} and {kind}")
    names = tuple(name for name, _ in typed)
    return names, tuple(given.get(name, default_type(name)) for name in names)


def groups(names: Sequence[str], sides: Sequence[str] = SIDES) -> dict[str, list[str]]:
    """Patch name -> its sides, in the order the names first appear."""
    out: dict[str, list[str]] = {}
    for side, name in zip(sides, names):
        out.setdefault(name, []).append(side)
    return out


def type_of(names: Sequence[str], types: Sequence[str] | None, name: str) -> str:
    """The type (``TYPES``) of the patch ``name`` among sides named ``names``: given in
    ``types`` (one a side), or by its name."""
    types = types or [default_type(n) for n in names]
    return dict(zip(names, types)).get(name, default_type(name))


def add_to_grid(grid, names: Sequence[str], types: Sequence[str] | None = None) -> None:
    """Put ``PatchNames`` and ``PatchTypes`` (field data; types default by name) and the
    point arrays ``i``, ``j`` (and ``k`` on a 3D grid) on ``grid``."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonCore import vtkStringArray

    fd = grid.GetFieldData()
    types = types if types is not None else [default_type(n) for n in names]
    for field, values in ((FIELD, names), (TYPES_FIELD, types)):
        fd.RemoveArray(field)
        arr = vtkStringArray()
        arr.SetName(field)
        for value in values:
            arr.InsertNextValue(value)
        fd.AddArray(arr)
    ext = grid.GetExtent()
    ni, nj, nk = (ext[2 * a + 1] - ext[2 * a] + 1 for a in range(3))
    kk, jj, ii = np.mgrid[0:nk, 0:nj, 0:ni]
    for key, values in (("i", ii), ("j", jj), ("k", kk))[: 3 if nk > 1 else 2]:
        data = numpy_to_vtk(np.ascontiguousarray(values.ravel(), dtype=np.int32), deep=True)
        data.SetName(key)
        grid.GetPointData().AddArray(data)


def of_grid(grid, sides: Sequence[str] = SIDES) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The patch names and types a grid carries for ``sides``, or the defaults."""
    fd = grid.GetFieldData()
    arr, kinds = fd.GetAbstractArray(FIELD), fd.GetAbstractArray(TYPES_FIELD)
    n = len(sides)
    if arr is None or arr.GetNumberOfValues() != n:
        return patch_specs(None, sides=sides)
    names = [arr.GetValue(k) for k in range(n)]
    if kinds is not None and kinds.GetNumberOfValues() == n:
        names = [f"{name}:{kinds.GetValue(k)}" for k, name in enumerate(names)]
    return patch_specs(names, sides=sides)


def named_patches(
    patches: Mapping[str, str] | Sequence[str] | str | None, faces: dict[str, int]
) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The names and types of imin ... kmax from any route's patch setting, ``SIDE=NAME``
    items naming a side as imin ... kmax or as ``faceN``, the face whose FaceId is N
    (``faces``: :func:`face_names`)."""
    aliases = {f"{FACE_PREFIX}{face}": side for side, face in sorted(faces.items(), key=by_face)}
    return patch_specs(patches, sides=BOX_SIDES, aliases=aliases)


def by_face(item: tuple[str, int]) -> int:
    """The FaceId of a (side, FaceId) item: faces are listed in FaceId order."""
    return item[1]
