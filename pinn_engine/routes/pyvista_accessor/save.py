"""A grid made by pinn-mesh's pyvista functions written for a CFD solver: ``save_mesh``."""

from __future__ import annotations

from pinn_engine.routes.pyvista_accessor.running import pyvista_words


def save_mesh(grid, path, format: str | None = None, *, patches=None, extrude: float | None = None):
    """Write a grid pinn-mesh made (any domain kind) for a CFD solver; returns the path
    written. ``pinn_engine.save`` is this function.

    The format follows the extension of ``path``: ``.vts``, ``.vtk``, ``.xyz`` (PLOT3D),
    ``.cgns``, ``.su2``, ``.msh`` (Gmsh 4.1); ``format="openfoam"`` writes the case folder
    ``path`` (``constant/polyMesh``). ``patches`` renames the boundary patches (default: the
    grid's ``PatchNames``); ``extrude=T`` makes PLOT3D, CGNS and Gmsh outputs one cell of
    thickness T in z (OpenFOAM always is). Atomic: on failure nothing is left behind.
    Raises ``pinn_engine.errors.InputError`` (one line) for bad arguments.

    >>> grid = square.pinn_mesh(size=(21, 11), method="tfi", patches={"bottom": "wall"})
    >>> pinn_engine.save(grid, "out/square.su2")
    >>> pinn_engine.save(grid, "out/square.cgns", patches={"top": "lid:wall"})
    >>> pinn_engine.save(grid, "out/square_case", format="openfoam", extrude=0.1)
    """
    from pinn_engine.io.export import write

    with pyvista_words():
        return write(grid, path, format, patches=patches, extrude=extrude)
