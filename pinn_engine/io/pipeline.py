"""From files or VTK inputs to boundary, auxiliary lines and grid (CLI, filter, pyvista)."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkPolyData, vtkStructuredGrid

from pinn_engine.bodies.airfoil import body_from_points, circle, polyline_farfield, xy_blocks
from pinn_engine.errors import InputError
from pinn_engine.geometry.auxlines import AuxLine, map_lines
from pinn_engine.geometry.boundary import Boundary
from pinn_engine.io.fileio import (
    RawLine,
    aux_lines_of,
    boundary_points,
    polylines_of,
    read_aux_lines,
    read_boundary_points,
    read_polydata,
)
from pinn_engine.io.vtkgrid import structured_grid
from pinn_engine.result import MeshResult


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
        from pinn_engine.io.export.patches import body_patch_names

        patches = body_patch_names(topology["kind"])
    return structured_grid(
        np.asarray(result.points),
        result.report,
        result.history,
        result.cells or None,
        patches,
        result.points3d,
    )


def body_from_polydata(poly: vtkPolyData, radius: float, source: str = "boundary input"):
    """The body (and far field) of a filter's input: one polyline is the body (closed:
    sharp trailing edge; open: blunt), with a far-field circle of ``radius`` chords; two
    closed polylines are the body inside the far field."""
    if poly is None or poly.GetNumberOfPoints() == 0:
        raise InputError("is empty; connect an airfoil (the Airfoil source or a .dat file)", source)
    xyz = vtk_to_numpy(poly.GetPoints().GetData()).astype(float)
    curves = []
    for ids, closed in polylines_of(poly, source):
        pts = xyz[ids, :2]
        if closed and not np.array_equal(pts[0], pts[-1]):
            pts = np.concatenate([pts, pts[:1]])
        curves.append(pts)
    if len(curves) == 1:
        body = body_from_points(curves[0], source)
        return body, circle(body, radius)
    if len(curves) == 2:
        size = [float(np.ptp(c, axis=0).max()) for c in curves]
        inner, outer = (curves[0], curves[1]) if size[0] < size[1] else (curves[1], curves[0])
        body = body_from_points(inner, source)
        return body, polyline_farfield(outer, body, source)
    raise InputError(
        f"holds {len(curves)} polylines; connect one airfoil curve (with Far "
        "Field Radius) or two closed polylines (body inside far field)",
        source,
    )


def read_body_and_farfield(path: str | os.PathLike):
    """The body and far field (``bodies.airfoil``'s Body, FarField) of a file with two closed
    polylines, the body inside the far field. ``.vtp``/``.vtk``: two polyline cells;
    ``.csv``/``.txt``: two blocks of ``x,y`` rows separated by a blank line."""
    source = str(path)
    suffix = Path(path).suffix.lower()

    if suffix in (".vtp", ".vtk"):
        lines = [pts for pts, _ in polylines_of(read_polydata(Path(path)), source)]
    else:
        try:
            text = Path(path).read_text(errors="replace")
        except OSError as exc:
            raise InputError(f"cannot read the file ({exc.strerror or exc})", source) from None
        lines = [np.array(b) for b in xy_blocks(text, source)[0]]
    if len(lines) != 2:
        raise InputError(
            f"holds {len(lines)} polylines; give two closed polylines (the body "
            "inside the far field) or one body with --farfield R",
            source,
        )
    ext = [float(np.ptp(np.asarray(p)[:, :2], axis=0).max()) for p in lines]
    inner, outer = (lines[0], lines[1]) if ext[0] < ext[1] else (lines[1], lines[0])
    body = body_from_points(np.asarray(inner)[:, :2], source)
    return body, polyline_farfield(outer, body, source)
