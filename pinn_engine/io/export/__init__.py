"""Solver-ready output (SPEC 8): one grid, the formats CFD solvers read, named patches.

``write(grid, path)`` picks the format from the extension of ``path`` (or ``fmt``). A 2D
grid has the four patches bottom, right, top and left; a hexahedral grid (SPEC 11: nk > 1)
has imin ... kmax, is written in 3D as it is (hexahedra in SU2 and Gmsh) and never extruded:

=========  =========================================================  ===========
format     what                                                       extrudes
=========  =========================================================  ===========
vts        VTK XML structured grid (default)                          no
vtk        VTK legacy structured grid                                 no
xyz        PLOT3D, multi-grid, whole, double precision                ``extrude=``
cgns       CGNS/HDF5, one structured zone, a ``BC_t`` per side        ``extrude=``
su2        SU2, quadrilaterals, a ``MARKER_TAG`` per patch            no
msh        Gmsh 4.1, physical groups per patch and ``fluid``          ``extrude=``
openfoam   ``DIR/constant/polyMesh`` (one cell in z, frontAndBack)    always
=========  =========================================================  ===========

Every writer is atomic: a file is written under a temporary name beside its target and
renamed over it when complete; an OpenFOAM case is built in a temporary directory. A
failure leaves the target as it was. Everything here needs numpy and VTK only, except
CGNS (``h5py``), so that the ParaView plugin offers the same writers.
"""

from __future__ import annotations

import math
import os
import shutil
import tempfile
from collections.abc import Callable, Mapping, Sequence
from importlib import import_module
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from pinn_engine.errors import InputError
from pinn_engine.geometry.plane import Plane
from pinn_engine.io.atomic import atomic_path, check_writable, umask, write_text_atomic
from pinn_engine.io.export.block import Block, Box
from pinn_engine.io.export.multiblock import blocks_of
from pinn_engine.io.export.patches import (
    BOX_SIDES,
    FIELD,
    SIDES,
    add_to_grid,
    of_grid,
    parse_patch_options,
    patch_names,
    patch_specs,
)
from pinn_engine.io.export.registry import FORMATS as _REGISTERED
from pinn_engine.io.export.registry import Format
from pinn_engine.io.export.topology import mean_edge, side_nodes

if TYPE_CHECKING:  # VTK is imported where a grid is read: a blockMeshDict's case needs none
    from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet, vtkStructuredGrid


def formats() -> dict[str, Format]:
    """Every export format by key (``FORMATS``), their modules imported on the first call
    (``registered.py``)."""
    import_module(f"{__name__}.registered")
    return _REGISTERED


def __getattr__(name: str) -> object:
    """``FORMATS``: :func:`formats`, so that importing the package registers nothing it does
    not write (PEP 562)."""
    if name == "FORMATS":
        return formats()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def output_format(
    path: str | os.PathLike, fmt: str | None = None, extrude: float | None = None
) -> Format:
    """The format for ``path`` (its extension, or ``fmt``); checks ``extrude``, that
    ``path`` can be written and, for CGNS, that h5py is there, so that a route can refuse
    before meshing."""
    path = Path(path)
    if fmt is not None:
        found = formats().get(str(fmt).strip().lower())
        if found is None:
            raise InputError(f"unknown format {fmt!r}; use {{output}}", str(path))
    else:
        by_suffix = {f.suffix: f for f in formats().values() if f.suffix}
        found = by_suffix.get(path.suffix.lower())
        if found is None:
            raise InputError(
                f"unknown output format {path.suffix or '(no extension)'!r}; use {{output}}",
                str(path),
            )
    if found.suffix and path.is_dir():
        raise InputError("is a directory; give a file name ({output})", str(path))
    if not found.suffix and path.exists() and not path.is_dir():
        raise InputError("exists and is not a directory; an OpenFOAM case is a folder", str(path))
    if extrude is not None:
        if not found.extrudes:
            extruding = [f.suffix or f.name for f in formats().values() if f.extrudes]
            raise InputError(
                f"{found.description} is 2D only; drop {{extrude}} (it applies "
                f"to {', '.join(extruding[:-1])} and {extruding[-1]})",
                str(path),
            )
        if not (math.isfinite(extrude) and extrude > 0):
            raise InputError(
                f"extrusion thickness {extrude}: must be a number > 0 ({{extrude}})", str(path)
            )
    check_writable(path)
    if found.check is not None:
        found.check()
    return found


def _xyz(grid: vtkStructuredGrid) -> np.ndarray:
    """The points of ``grid`` (n, 3), as float64."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    return vtk_to_numpy(grid.GetPoints().GetData()).astype(np.float64)


def _extent(grid: vtkStructuredGrid) -> tuple[int, int, int]:
    """Nodes (ni, nj, nk) of a grid that has points."""
    if grid is None or grid.GetPoints() is None or grid.GetNumberOfPoints() == 0:
        raise InputError("the grid is empty; mesh the boundary first", "grid")
    ext = grid.GetExtent()
    return tuple(ext[2 * a + 1] - ext[2 * a] + 1 for a in range(3))


def is_box(grid: vtkStructuredGrid) -> bool:
    """Whether ``grid`` is a hexahedral grid (SPEC 11: more than one node along k)."""
    return _extent(grid)[2] > 1


def box_points(grid: vtkStructuredGrid) -> np.ndarray:
    """The nodes (nk, nj, ni, 3) of a hexahedral grid, checked right-handed in (i, j, k)
    (SPEC 11): the writers orient faces and cells by it."""
    ni, nj, nk = _extent(grid)
    if min(ni, nj, nk) < 2:
        raise InputError(f"a hexahedral grid needs 2 nodes or more, got ({ni}, {nj}, {nk})", "grid")
    xyz = _xyz(grid).reshape(nk, nj, ni, 3)
    di = xyz[:-1, :-1, 1:] - xyz[:-1, :-1, :-1]
    dj = xyz[:-1, 1:, :-1] - xyz[:-1, :-1, :-1]
    dk = xyz[1:, :-1, :-1] - xyz[:-1, :-1, :-1]
    if float(np.sum(np.cross(di, dj) * dk)) <= 0:
        raise InputError(
            "the grid is not right-handed in (i, j, k) (SPEC 11): its cell volumes are "
            "negative; reverse its i, j or k direction first",
            "grid",
        )
    return xyz


def grid_points(grid: vtkStructuredGrid) -> tuple[np.ndarray, np.ndarray]:
    """The nodes of a 2D structured grid (ni, nj, 1) as an array (nj, ni, 3), and the unit
    normal about which its boundary runs counter-clockwise along i, then j (SPEC 3): +z for
    a grid in a plane z = const, whose boundary must then run counter-clockwise in x-y."""
    ni, nj, nk = _extent(grid)
    if nk != 1 or min(ni, nj) < 2:
        raise InputError(
            f"expected a 2D structured grid of (ni, nj, 1) nodes, got ({ni}, {nj}, {nk})", "grid"
        )
    pts = _xyz(grid).reshape(nj, ni, 3)
    ring = pts.reshape(-1, 3)[np.concatenate([side_nodes(ni, nj, s)[:-1] for s in SIDES])]
    plane = Plane.fit(pts.reshape(-1, 3), "grid")
    area = 0.5 * np.cross(ring, np.roll(ring, -1, axis=0)).sum(axis=0)  # vector area
    if plane.is_horizontal:
        if area[2] <= 0:  # clockwise or flat
            raise InputError(
                "the grid's boundary does not run counter-clockwise in the x-y "
                "plane along i, then j (SPEC 3); the writers orient cells and "
                "patches by it: reverse its i or j direction first",
                "grid",
            )
        return pts, np.array([0.0, 0.0, 1.0])
    return pts, area / np.linalg.norm(area)


def body_topology(grid: vtkStructuredGrid) -> str | None:
    """ "o" or "c" for an O- or C-grid around a body (field data ``Topology``), else None."""
    arr = grid.GetFieldData().GetAbstractArray("Topology") if grid is not None else None
    if arr is None or arr.GetNumberOfValues() != 1:
        return None
    value = str(arr.GetValue(0)).lower()
    return value if value in ("o", "c") else None


def write(
    grid: vtkStructuredGrid,
    path: str | os.PathLike,
    fmt: str | None = None,
    *,
    patches: Mapping[str, str] | Sequence[str] | str | None = None,
    extrude: float | None = None,
) -> Path:
    """Write ``grid`` to ``path`` in the format of its extension (or ``fmt``); a
    multi-block grid (``vtkMultiBlockDataSet``) by :func:`write_blocks` (or as ``.vtm``).

    ``patches``: the patch names of the grid's sides (see :func:`patches.patch_names`:
    bottom, right, top, left; imin ... kmax for a hexahedral grid); None keeps the grid's
    ``PatchNames`` (or the sides' names). ``extrude``: one cell of this thickness in z for
    a 2D grid (PLOT3D, CGNS, Gmsh, OpenFOAM; OpenFOAM defaults to the grid's mean edge
    length). Returns the path written; raises ``InputError`` (one line) for bad arguments
    and ``OSError`` when the file system refuses.
    """
    from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet, vtkStructuredGrid

    path = Path(path)
    if isinstance(grid, vtkMultiBlockDataSet):
        if patches is not None:
            raise InputError(
                "a multi-block grid's patches are named when it is meshed ({pieces}); "
                "drop patches here",
                str(path),
            )
        if fmt is None and path.suffix.lower() == ".vtm":
            from pinn_engine.io.export.vtm import write_vtm  # vtm imports vtkgrid, which this

            return write_vtm(grid, path)
        return write_blocks(grid, path, fmt, extrude=extrude)
    if grid is not None and not isinstance(grid, vtkStructuredGrid):
        kind = type(grid).__name__
        raise InputError(f"writes the grids pinn-mesh makes, not a {kind}", str(path))
    found = output_format(path, fmt, extrude)
    box = is_box(grid)
    sides = BOX_SIDES if box else SIDES
    names, types = of_grid(grid, sides) if patches is None else patch_specs(patches, sides=sides)
    topology = None if box else body_topology(grid)
    if box:
        if extrude is not None:
            raise InputError("a hexahedral grid is 3D already: drop --extrude", str(path))
        xyz = box_points(grid)
    elif topology:
        points, normal, n_wake = _body_points(grid, topology, path)
    else:
        (points, normal), n_wake = grid_points(grid), 0
    if found.grid is not None:
        copy = vtkStructuredGrid()
        copy.ShallowCopy(grid)
        add_to_grid(copy, names, types)
        found.grid(copy, path)
        return path
    if box:
        return _written(found, path, lambda to: found.box(Box(xyz, names, types), to))
    if extrude is None and found.solid:
        extrude = mean_edge(points)
    block = Block(points, names, extrude, normal, topology, n_wake, types)
    return _written(found, path, lambda to: found.block(block, to))


def blocks_format(path: str | os.PathLike, fmt: str | None, extrude: float | None) -> Format:
    """The export format of a multi-block grid (SPEC 10) for ``path`` (or ``fmt``),
    refused (one line) before meshing where it does not apply."""
    found = output_format(path, fmt, extrude)
    if found.blocks is None:
        named = [f.suffix or f"--format {f.key}" for f in formats().values() if f.blocks]
        raise InputError(
            f"a multi-block grid is written as .vtm, {', '.join(named[:-1])} or {named[-1]}, "
            f"not as {found.description}",
            str(path),
        )
    if extrude is not None and not found.blocks_extrude:
        raise InputError(
            f"a multi-block grid is written to {found.name} in 2D in this build; drop {{extrude}}",
            str(path),
        )
    return found


def write_blocks(
    dataset: vtkMultiBlockDataSet,
    path: str | os.PathLike,
    fmt: str | None = None,
    *,
    extrude: float | None = None,
) -> Path:
    """Write a multi-block grid (``vtm.multiblock_dataset``) to ``path`` in the format of
    its extension (or ``fmt``); ``extrude``: one cell of this thickness in z (PLOT3D, CGNS,
    OpenFOAM; OpenFOAM's default: the mean edge length). Atomic, as every writer."""
    path = Path(path)
    found = blocks_format(path, fmt, extrude)
    blocks = blocks_of(dataset)
    return _written(found, path, lambda to: found.blocks(blocks, to, extrude))


def _written(found: Format, path: Path, write_to: Callable[[Path], None]) -> Path:
    """``path`` written atomically by ``write_to``: a temporary file renamed over it, or
    for a folder format an OpenFOAM case whose new polyMesh ``write_to`` fills."""
    if not found.suffix:
        return write_case(path, write_to)
    with atomic_path(path, suffix=found.suffix) as tmp:
        write_to(tmp)
    return path


def _body_points(grid: vtkStructuredGrid, topology: str, path: Path):
    """The nodes (nj, ni, 3) of an O- or C-grid, its extrusion normal (the O-grid's cells are
    clockwise in (i, j), SPEC 9) and its wake node count."""
    points = _xyz(grid)
    ext = grid.GetExtent()
    points = points.reshape(ext[3] - ext[2] + 1, ext[1] - ext[0] + 1, 3)
    if np.ptp(points[..., 2]) > 1e-12 * max(1.0, float(np.ptp(points))):
        raise InputError("an O- or C-grid must lie in a plane z = const to be written", str(path))
    wake = grid.GetFieldData().GetArray("WakeNodes")
    n_wake = int(wake.GetValue(0)) if wake is not None else 0
    return points, np.array([0.0, 0.0, -1.0 if topology == "o" else 1.0]), n_wake


def write_case(case: Path, write_mesh: Callable[[Path], None]) -> Path:
    """An OpenFOAM case whose ``constant/polyMesh`` ``write_mesh(folder)`` writes. A new
    case is built in a temporary folder and renamed; in an existing case only
    ``constant/polyMesh`` is replaced (built beside it, then swapped) and missing case
    files are added."""
    from pinn_engine.io.export.openfoam import case_files

    title = case.name or "case"
    files = case_files(title)
    if not case.exists():
        case.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{title}.", suffix=".part", dir=case.parent))
        try:
            mesh = tmp / "constant" / "polyMesh"
            mesh.mkdir(parents=True)
            write_mesh(mesh)
            for rel, text in files.items():
                (tmp / rel).parent.mkdir(parents=True, exist_ok=True)
                (tmp / rel).write_text(text)
            os.chmod(tmp, 0o777 & ~umask())
            os.rename(tmp, case)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
        return case
    constant = case / "constant"
    constant.mkdir(exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=".polyMesh.", suffix=".part", dir=constant))
    target, old, moved = constant / "polyMesh", None, False
    try:
        write_mesh(tmp)
        os.chmod(tmp, 0o777 & ~umask())
        if target.exists():
            old = Path(tempfile.mkdtemp(prefix=".polyMesh.", suffix=".old", dir=constant))
            os.rename(target, old / "polyMesh")
            moved = True
        os.rename(tmp, target)
        moved = False
    finally:
        if moved:  # put the previous mesh back
            os.rename(old / "polyMesh", target)
        shutil.rmtree(tmp, ignore_errors=True)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
    for rel, text in files.items():
        if not (case / rel).exists():
            write_text_atomic(case / rel, text)
    return case


__all__ = [
    "BOX_SIDES",
    "FIELD",
    "FORMATS",
    "SIDES",
    "Block",
    "Box",
    "Format",
    "blocks_format",
    "box_points",
    "formats",
    "grid_points",
    "is_box",
    "output_format",
    "parse_patch_options",
    "patch_names",
    "patch_specs",
    "write",
    "write_blocks",
    "write_case",
]
