"""From files or VTK inputs to boundary, auxiliary lines and grid (CLI, filter, pyvista)."""

from __future__ import annotations

import os
from collections.abc import Sequence

import numpy as np
from vtkmodules.vtkCommonDataModel import vtkPolyData, vtkStructuredGrid

from .auxlines import AuxLine, map_lines
from .errors import InputError
from .fileio import (
    RawLine,
    aux_lines_of,
    boundary_points,
    polylines_of,
    read_aux_lines,
    read_boundary_points,
)
from .geometry import Boundary
from .mesher import MeshResult
from .vtkgrid import structured_grid


def load_boundary(path: str | os.PathLike, corners: Sequence[int] | None = None) -> Boundary:
    """Read and validate a boundary file (SPEC 1)."""
    pts = read_boundary_points(path)
    return Boundary.from_points(pts, tuple(corners) if corners else None, source=str(path))


def load_aux(paths: Sequence[str | os.PathLike], boundary: Boundary) -> list[AuxLine]:
    """Read and map the auxiliary lines of every file in ``paths`` (SPEC 2)."""
    raws: list[RawLine] = []
    for path in paths:
        raws.extend(read_aux_lines(path))
    return map_lines(raws, boundary)


def boundary_from_polydata(
    poly: vtkPolyData, corners: Sequence[int] | None = None, source: str = "boundary input"
) -> Boundary:
    """Validate the boundary held by a ``vtkPolyData`` (e.g. a filter's input port 0)."""
    pts = boundary_points(poly, source)
    return Boundary.from_points(pts, tuple(corners) if corners else None, source=source)


def split_inputs(polys: Sequence[vtkPolyData | None]) -> tuple[vtkPolyData, list[vtkPolyData]]:
    """The boundary and the auxiliary lines among inputs connected together: the one input
    holding a closed curve is the boundary, the others hold open auxiliary lines."""
    polys = [p for p in polys if p is not None and p.GetNumberOfPoints()]
    if not polys:
        raise InputError("is empty; connect a closed polyline", "boundary input")
    if len(polys) == 1:
        return polys[0], []
    closed = [p for p in polys if any(c for _, c in polylines_of(p, "input"))]
    if len(closed) != 1:
        raise InputError(
            f"{len(closed)} of the {len(polys)} connected inputs hold a closed "
            "curve; connect one closed boundary, and open polylines as auxiliary "
            "lines",
            "boundary input",
        )
    return closed[0], [p for p in polys if p is not closed[0]]


def aux_from_polydata(polys: Sequence[vtkPolyData], boundary: Boundary) -> list[AuxLine]:
    """Map the polylines of every ``vtkPolyData`` in ``polys`` as auxiliary lines."""
    raws: list[RawLine] = []
    for k, poly in enumerate(polys):
        if poly is not None and poly.GetNumberOfPoints():
            raws.extend(aux_lines_of(poly, f"auxiliary input {k}"))
    return map_lines(raws, boundary)


def to_vtk(result: MeshResult, patches=None) -> vtkStructuredGrid:
    """The output grid of SPEC 3 for a mesh result, with the patch names of SPEC 8."""
    topology = result.report.get("topology")
    if topology and patches is None:
        from .bodymesh import patch_names

        patches = patch_names(topology["kind"])
    return structured_grid(
        np.asarray(result.points),
        result.report,
        result.history,
        result.cells or None,
        patches,
        result.points3d,
    )
