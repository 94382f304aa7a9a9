"""pinn-mesh for pyvista: ``pinn_mesh(boundary, ...)`` and the ``PolyData.pinn_mesh`` accessor.

With pinn-mesh installed (pyvista 0.48+ finds the accessor through the ``pyvista.accessors``
entry point; no import needed)::

    import pyvista as pv

    boundary = pv.read("example_data/fig2.vtp")      # one closed polyline, four corners
    lines = pv.read("example_data/fig2_aux.vtp")     # optional auxiliary polylines
    grid = boundary.pinn_mesh(aux=lines, size=(41, 21))
    grid.plot(scalars="MaxIncludedAngle", show_edges=True, cpos="xy")

    finer = boundary.pinn_mesh(aux=lines, size=(161, 81))   # made for 161 x 81
    again = boundary.pinn_mesh(aux=lines, size=(41, 21))    # the first grid, from the cache

The accessor keeps the networks it trained for that boundary, so calling it again with
settings it has seen only re-evaluates the network. The default PINN starts from the
elliptic grid of ``size`` (``lattice``): a network trained at another size is evaluated at
the new one and kept where that size's own guard passes (``report(grid)["resized"]``),
else the new size trains anew; ``lattice=(41, 21)`` evaluates the network trained for
41 x 21 at any ``size``, unchecked. ``boundary.pinn_mesh.trainings``
counts the trainings and ``boundary.pinn_mesh.clear()`` forgets them. ``pinn_mesh(boundary,
...)`` is the same as a plain function (no cache unless you pass one).

A grid with folded cells is still returned, with a ``pinn_engine.FoldedCellsWarning`` (a
``UserWarning``) that gives the count and a hint; ``warnings.simplefilter("error",
FoldedCellsWarning)`` turns it into an exception.

A multi-block domain (SPEC 10) is meshed by giving its block edges: ``blocks = boundary.
pinn_mesh(blocks=edges, cell_size=0.1)`` (or :func:`pinn_mesh_blocks`) returns a
``pyvista.MultiBlock`` of structured grids ``block0``, ``block1``, ...

A six-faced 3D domain (SPEC 11), a closed surface with a ``FaceId`` cell array, is meshed the
same way: ``grid = surface.pinn_mesh(size=(21, 21, 21))`` (or :func:`pinn_mesh_hexa`)
returns its hexahedral ``pyvista.StructuredGrid``.

``pinn_engine.report(grid)`` (:func:`report`) reads a grid's report as a dict,
``pinn_engine.save(grid, "x.su2", patches=...)`` (:func:`save_mesh`) writes it for a solver
and ``pinn_engine.read_airfoil("naca0012.dat")`` (:func:`read_airfoil`) reads an airfoil.

The package: ``inputs`` (curves and surfaces in any of their forms as PolyData), ``running``
(a VTK algorithm run in pyvista's words: errors, output, progress bar, warnings at the
caller's line), one module a domain kind (``four_sided`` with ``body``, ``multiblock``,
``hexa``, ``dictionary``), ``report`` and ``save`` (``save_mesh``), and ``accessor``
(``PolyData.pinn_mesh``, registered when this package is imported).
"""

from pinn_engine.errors import FoldedCellsWarning
from pinn_engine.routes.pyvista_accessor.accessor import PinnMeshAccessor
from pinn_engine.routes.pyvista_accessor.body import read_airfoil
from pinn_engine.routes.pyvista_accessor.dictionary import read_blockmeshdict
from pinn_engine.routes.pyvista_accessor.four_sided import pinn_mesh
from pinn_engine.routes.pyvista_accessor.hexa import pinn_mesh_hexa
from pinn_engine.routes.pyvista_accessor.multiblock import pinn_mesh_blocks
from pinn_engine.routes.pyvista_accessor.report import report
from pinn_engine.routes.pyvista_accessor.save import save_mesh

__all__ = [
    "FoldedCellsWarning",
    "PinnMeshAccessor",
    "pinn_mesh",
    "pinn_mesh_blocks",
    "pinn_mesh_hexa",
    "read_airfoil",
    "read_blockmeshdict",
    "report",
    "save_mesh",
]
