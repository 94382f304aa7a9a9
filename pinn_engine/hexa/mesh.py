"""A hexahedral grid of a six-faced surface, from file to vtkStructuredGrid (SPEC 11); the
solver formats write it through :func:`pinn_engine.io.export.write`."""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonCore import vtkPoints, vtkStringArray
from vtkmodules.vtkCommonDataModel import vtkPolyData, vtkStructuredGrid

from pinn_engine.errors import InputError
from pinn_engine.hexa import quality, volume
from pinn_engine.hexa.block import cube_corners
from pinn_engine.hexa.facegrid import face_grid
from pinn_engine.hexa.surface import Surface, Topology, find_topology, surface_of
from pinn_engine.io import fileio
from pinn_engine.io.export.patches import BOX_SIDES, add_to_grid, patch_specs

METHODS = ("tfi", "elliptic")  # the methods of this build for six-faced domains
HEXA_METHOD = "elliptic"  # the default while 3D has no pinn: the converged Winslow grid
HEXA_SIZE = (21, 21, 21)  # SPEC 11's default nodes along i, j and k
MIN_NODES = 3  # fewer nodes along a direction leave no interior to solve for


@dataclass
class HexResult:
    """The grid (ni, nj, nk, 3), its cell arrays and the run's seconds."""

    grid: np.ndarray
    cells: dict[str, np.ndarray]
    seconds: float
    iterations: int


def boundary_grid(
    surface: Surface, topology: Topology, size: tuple[int, int, int], source: str
) -> np.ndarray:
    """An (ni, nj, nk, 3) array whose six faces hold the face grids (interior zero)."""
    cube = cube_corners(surface, topology, source)
    g = np.zeros((*size, 3))
    for axis in range(3):
        a, b = (x for x in range(3) if x != axis)
        for value in (0, 1):

            def corner(ta: int, tb: int, a=a, b=b, axis=axis, value=value) -> int:
                c = [0, 0, 0]
                c[axis], c[a], c[b] = value, ta, tb
                return cube[tuple(c)]

            ring = {corner(0, 0), corner(1, 0), corner(0, 1), corner(1, 1)}
            face = next(f for f, cs in enumerate(topology.face_corners) if set(cs) == ring)
            sides = {
                "a0": topology.edges[(corner(0, 0), corner(1, 0))],
                "a1": topology.edges[(corner(0, 1), corner(1, 1))],
                "b0": topology.edges[(corner(0, 0), corner(0, 1))],
                "b1": topology.edges[(corner(1, 0), corner(1, 1))],
            }
            at = [slice(None)] * 3
            at[axis] = 0 if value == 0 else -1
            g[tuple(at)] = face_grid(
                surface, topology.face_triangles[face], sides, (size[a], size[b])
            )
    return g


def size_problem(size: tuple[int, ...]) -> str | None:
    """Why ``size`` is not a grid size of a six-faced domain (each route names its own
    setting before it), or None."""
    if len(size) != len(HEXA_SIZE):
        return "a six-faced surface takes three sizes (nodes along i, j and k)"
    if min(size) < MIN_NODES:
        return f"each needs at least {MIN_NODES} nodes"
    return None


def refuse(size: tuple[int, ...], method: str) -> None:
    """An :class:`InputError` for a method or size this build cannot mesh with."""
    if method not in METHODS:
        raise InputError(
            f"--method {method}: six-faced 3D domains are meshed by {' or '.join(METHODS)} "
            "in this build"
        )
    problem = size_problem(size)
    if problem:
        raise InputError(f"--size {' '.join(map(str, size))}: {problem}")


def mesh_surface(
    path: str,
    size: tuple[int, int, int],
    method: str,
    progress: Callable[[str, float], None] | None = None,
) -> HexResult:
    """Read ``path`` (an ``.stl``'s faces are found at its sharp edges), check its topology,
    build the face grids and the volume grid."""
    refuse(size, method)
    data = fileio.read_polydata(Path(path))
    stl = str(path).lower().endswith(".stl")
    return mesh_polydata(data, size, method, path, progress, sharp_edges=stl)


def mesh_polydata(
    data: vtkPolyData,
    size: tuple[int, int, int],
    method: str,
    source: str,
    progress: Callable[[str, float], None] | None = None,
    sharp_edges: bool = False,
) -> HexResult:
    """The hexahedral grid of a surface in memory (a polydata with a FaceId cell array, or
    with ``sharp_edges`` faces found at its sharp edges; the filter's and pyvista's input),
    ``source`` naming it in messages; ``progress(phase, fraction)`` is told each phase as it
    starts."""
    refuse(size, method)
    tell = progress or (lambda phase, fraction: None)
    start = time.perf_counter()
    tell("face grids", 0.0)
    surface = surface_of(data, source, sharp_edges)
    topology = find_topology(surface, source)
    g = volume.tfi(boundary_grid(surface, topology, size, source))
    iterations = 0
    if method == "elliptic":
        tell("3D Winslow", 0.3)
        g, iterations = volume.winslow(g)
    tell("quality", 0.9)
    cells = cell_arrays(g)
    return HexResult(g, cells, time.perf_counter() - start, iterations)


def structured_grid(g: np.ndarray) -> vtkStructuredGrid:
    """A vtkStructuredGrid of the (ni, nj, nk, 3) array (i fastest, as VTK's); plain VTK,
    for ParaView's Python."""
    grid = vtkStructuredGrid()
    grid.SetDimensions(*g.shape[:3])
    points = vtkPoints()
    xyz = np.ascontiguousarray(g.transpose(2, 1, 0, 3).reshape(-1, 3), dtype=float)
    points.SetData(numpy_to_vtk(xyz, deep=True))
    grid.SetPoints(points)
    return grid


def cell_arrays(g: np.ndarray) -> dict[str, np.ndarray]:
    """SPEC 11's cell arrays of a grid."""
    largest, smallest = quality.included_angles(g)
    return {
        "MaxIncludedAngle": largest,
        "MinIncludedAngle": smallest,
        "ScaledJacobian": quality.scaled_jacobian(structured_grid(g)),
        "Folded": quality.folded(g),
    }


def figures(cells: dict[str, np.ndarray]) -> dict[str, float]:
    """The grid's summary figures: folded cells, min ScaledJacobian, mean and worst
    MaxIncludedAngle, worst MinIncludedAngle."""
    return {
        "folded_cells": int(cells["Folded"].sum()),
        "min_scaled_jacobian": float(cells["ScaledJacobian"].min()),
        "mean_max_angle": float(cells["MaxIncludedAngle"].mean()),
        "worst_max_angle": float(cells["MaxIncludedAngle"].max()),
        "worst_min_angle": float(cells["MinIncludedAngle"].min()),
    }


def report(result: HexResult, method: str) -> dict:
    """What the grid's field data ``Report`` holds: method, size, cells, seconds, Picard
    steps and :func:`figures` as ``quality``."""
    return {
        "method": method,
        "size": list(result.grid.shape[:3]),
        "cells": int(result.cells["Folded"].size),
        "seconds": result.seconds,
        "iterations": result.iterations,
        "quality": figures(result.cells),
    }


def hexa_grid(result: HexResult, method: str) -> vtkStructuredGrid:
    """The grid with SPEC 11's cell arrays (active scalars MaxIncludedAngle) and field
    data: ``Method``, ``Report`` (JSON, :func:`report`), each figure of its ``quality`` as
    a number, and the default patches imin ... kmax (SPEC 8's ``PatchNames``, ``PatchTypes``;
    the writers rename them). What every route hands over."""
    grid = structured_grid(result.grid)
    for name, values in result.cells.items():
        array = numpy_to_vtk(np.ascontiguousarray(values), deep=True)
        array.SetName(name)
        grid.GetCellData().AddArray(array)
    grid.GetCellData().SetActiveScalars("MaxIncludedAngle")
    fd = grid.GetFieldData()
    run = report(result, method)
    add_to_grid(grid, *patch_specs(None, sides=BOX_SIDES))
    for name, texts in (("Method", [method]), ("Report", [json.dumps(run)])):
        array = vtkStringArray()
        array.SetName(name)
        for text in texts:
            array.InsertNextValue(text)
        fd.AddArray(array)
    for name, value in run["quality"].items():
        array = numpy_to_vtk(np.array([value], dtype=float), deep=True)
        array.SetName(name)
        fd.AddArray(array)
    return grid


def write_vts(result: HexResult, out, method: str) -> None:
    """The grid of :func:`hexa_grid` as a .vts file (complete or absent)."""
    fileio.write_vts(hexa_grid(result, method), out)


def summary(result: HexResult, method: str) -> str:
    """One line: cells, folds, min ScaledJacobian, mean/worst MaxIncludedAngle, time."""
    ni, nj, nk = result.grid.shape[:3]
    c = result.cells
    return (
        f"{method} {ni}x{nj}x{nk} hexahedral grid, {c['Folded'].size} cells in "
        f"{result.seconds:.2f} s: {int(c['Folded'].sum())} folded, min ScaledJacobian "
        f"{c['ScaledJacobian'].min():.3f}, mean MaxIncludedAngle "
        f"{c['MaxIncludedAngle'].mean():.2f} deg, worst {c['MaxIncludedAngle'].max():.2f} deg"
        + (f" ({result.iterations} Picard steps)" if result.iterations else "")
    )
