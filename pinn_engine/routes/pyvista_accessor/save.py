"""A grid made by pinn-mesh's pyvista functions written for a CFD solver: ``save_mesh``."""

from __future__ import annotations

import os

from pinn_engine.routes.pyvista_accessor.running import public, pyvista_words


@public("pinn_engine.save")
def save_mesh(grid, path, format: str | None = None, *, patches=None, extrude: float | None = None):
    """Write a grid pinn-mesh made (any domain kind) for a CFD solver; returns the path
    written. ``pinn_engine.save`` is this function.

    The format follows the extension of ``path``: ``.vts``, ``.vtk``, ``.xyz`` (PLOT3D),
    ``.cgns``, ``.su2``, ``.msh`` (Gmsh 4.1); ``format="openfoam"`` writes the case folder
    ``path`` (``constant/polyMesh``). A multi-block grid (a ``pyvista.MultiBlock`` from
    ``blocks=``) goes to ``.vtm``, ``.xyz``, ``.cgns``, ``.su2``, ``.msh`` or OpenFOAM, a
    zone or a part of the mesh a block. ``patches`` renames the boundary patches of a
    four-sided, body or hexahedral grid (default: the grid's ``PatchNames``; a multi-block
    grid's are named when meshing); ``extrude=T`` makes PLOT3D, CGNS and Gmsh outputs one
    cell of thickness T in z (OpenFOAM always is). Atomic: on failure nothing is left
    behind. Raises ``pinn_engine.errors.InputError`` (one line) for bad arguments.

    The arguments may also come in meshio's order, ``save(path, grid)`` (as
    ``meshio.write`` and ``pv.save_meshio`` take them): a path is never a grid, so either
    order means one thing, and both readings of pyvista's world work.

    >>> grid = square.pinn_mesh(size=(21, 11), method="tfi", patches={"bottom": "wall"})
    >>> pinn_engine.save(grid, "out/square.su2")
    >>> pinn_engine.save("out/square.cgns", grid, patches={"top": "lid:wall"})
    >>> pinn_engine.save(grid, "out/square_case", format="openfoam", extrude=0.1)
    """
    from pinn_engine.io.export import write

    if isinstance(grid, str | os.PathLike) and not isinstance(path, str | os.PathLike):
        grid, path = path, grid  # meshio's order
    with pyvista_words():
        return write(grid, path, format, patches=patches, extrude=extrude)
