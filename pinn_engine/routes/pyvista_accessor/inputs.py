"""The forms pyvista's functions take curves and surfaces in (PolyData, VTK data, arrays of
points, lists or a MultiBlock of them), as the PolyData the VTK algorithms read."""

from __future__ import annotations

import numpy as np
import pyvista as pv
from vtkmodules.vtkCommonDataModel import vtkDataSet, vtkPolyData
from vtkmodules.vtkFiltersGeometry import vtkDataSetSurfaceFilter

from pinn_engine.errors import InputError


def ring_polydata(points, closed: bool) -> pv.PolyData:
    """One polyline through an ``(n, 2)`` or ``(n, 3)`` array of points, back to the first
    point where ``closed``."""
    pts = np.asarray(points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] not in (2, 3) or len(pts) < 2:
        raise InputError(f"expected an (n, 2) or (n, 3) array of points, got shape {pts.shape}")
    if pts.shape[1] == 2:
        pts = np.column_stack([pts, np.zeros(len(pts))])
    ids = list(range(len(pts))) + ([0] if closed else [])
    return pv.PolyData(pts, lines=[len(ids), *ids])


def as_polydata(obj, closed: bool, what: str) -> vtkPolyData:
    """``obj`` (PolyData, an array of points or another pyvista dataset holding lines) as
    PolyData; an error names the argument ``what``."""
    if isinstance(obj, vtkPolyData):
        return obj
    if isinstance(obj, np.ndarray | list | tuple):
        return ring_polydata(obj, closed)
    if isinstance(obj, pv.MultiBlock):
        obj = obj.combine()
    if isinstance(obj, vtkDataSet):
        # another dataset holding lines, through VTK's surface filter (pyvista's
        # extract_surface warns that its default algorithm will change)
        surface = vtkDataSetSurfaceFilter()
        surface.SetInputData(obj)
        surface.Update()
        return pv.wrap(surface.GetOutput())
    raise InputError(
        f"{what}: expected a pyvista/VTK PolyData or an array of points, got {type(obj).__name__}"
    )


def polydata_list(lines, what: str) -> list[vtkPolyData]:
    """Open polylines (auxiliary lines or block edges) given as None, one PolyData, one
    array of points, or a list or MultiBlock of them, as a list of PolyData; an error names
    the argument ``what``."""
    if lines is None:
        return []
    if isinstance(lines, vtkPolyData):
        return [lines]
    if isinstance(lines, np.ndarray):  # one polyline as an (n, 2|3) array
        return [ring_polydata(lines, closed=False)]
    if isinstance(lines, pv.MultiBlock):
        lines = [block for block in lines if block is not None]
    if not isinstance(lines, list | tuple):
        raise InputError(
            f"{what}: expected a pyvista/VTK PolyData, an array of points or a list of them, "
            f"got {type(lines).__name__}"
        )
    return [as_polydata(a, closed=False, what=what) for a in lines]
