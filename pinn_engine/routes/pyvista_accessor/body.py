"""The body an O- or C-grid is made around (SPEC 9), from any of the forms ``pinn_mesh``
takes with ``topology``: PolyData or points, a file path, or None (or an empty PolyData)
with ``naca``; and ``read_airfoil``, the public reader of airfoil files."""

from __future__ import annotations

import os

import numpy as np
import pyvista as pv
from vtkmodules.vtkCommonDataModel import vtkPolyData

from pinn_engine.errors import InputError
from pinn_engine.routes.airfoil_algorithm import body_polydata
from pinn_engine.routes.pyvista_accessor.inputs import as_polydata, ring_polydata
from pinn_engine.routes.pyvista_accessor.running import public, pyvista_words
from pinn_engine.settings import Settings


def body_input(body, settings: Settings, farfield_given: bool) -> vtkPolyData:
    """Port 0 of the algorithm for a body: its curve, the curve and far field of a ``.dat``
    file or of a file with two closed polylines, or empty PolyData with ``naca`` (the
    algorithm makes the section itself)."""
    if settings.naca:
        empty = isinstance(body, vtkPolyData) and body.GetNumberOfPoints() == 0
        if body is not None and not empty:
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


@public("pinn_engine.read_airfoil")
def read_airfoil(path: str | os.PathLike | None = None, *, naca: str | None = None) -> pv.PolyData:
    """An airfoil as the ``pyvista.PolyData`` ``pinn_mesh(topology="o")`` meshes around:
    read from a Selig or Lednicer ``.dat`` file (pyvista's own ``pv.read`` takes ``.dat``
    for Tecplot), or the NACA 4-digit section ``naca`` of chord 1.

    One polyline in Selig order (counter-clockwise from the trailing edge), closed for a
    sharp trailing edge, open for a blunt one, as the ParaView plugin's Airfoil reader and
    source give. Raises ``pinn_engine.InputError`` (one line) for a file that is not one.

    >>> body = pinn_engine.read_airfoil("example_data/naca0012.dat")
    >>> grid = body.pinn_mesh(topology="o", size=(129, 33))
    >>> grid = pv.PolyData().pinn_mesh(naca="0012", topology="c")  # no body to read
    """
    from pinn_engine.bodies.airfoil import load_body

    with pyvista_words():
        if (path is None) == (naca is None):
            raise InputError("give either an airfoil file or naca=, one of them")
        body = load_body(path, naca=None if naca is None else str(naca))
    return pv.wrap(body_polydata(body.surface, body.sharp))
