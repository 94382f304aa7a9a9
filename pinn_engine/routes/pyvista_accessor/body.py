"""The body an O- or C-grid is made around (SPEC 9), from any of the forms ``pinn_mesh``
takes with ``topology``: PolyData or points, a file path, or None with ``naca``."""

from __future__ import annotations

import os

import numpy as np
from vtkmodules.vtkCommonDataModel import vtkPolyData

from pinn_engine.errors import InputError
from pinn_engine.routes.airfoil_algorithm import body_polydata
from pinn_engine.routes.pyvista_accessor.inputs import as_polydata, ring_polydata
from pinn_engine.settings import Settings


def body_input(body, settings: Settings, farfield_given: bool) -> vtkPolyData:
    """Port 0 of the algorithm for a body: its curve, the curve and far field of a ``.dat``
    file or of a file with two closed polylines, or empty PolyData with ``naca`` (the
    algorithm makes the section itself)."""
    if settings.naca:
        if body is not None:
            raise InputError("give either a body or naca=, not both")
        return vtkPolyData()
    if body is None:
        raise InputError("give a body (PolyData, points or a .dat path) or naca=")
    if isinstance(body, str | os.PathLike):
        from pinn_engine.job import geometry_from_files

        geometry = geometry_from_files(settings, body, farfield_given=farfield_given)
        return body_polydata(geometry.body.surface, geometry.body.sharp, geometry.far.polyline)
    if isinstance(body, np.ndarray | list | tuple):
        return ring_polydata(body, closed=False)
    return as_polydata(body, closed=False, what="body")
