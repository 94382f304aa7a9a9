"""Every export format, registered (``registry.py``) by importing its module, in this order:
``--format``'s choices. Imported on the first use of ``io.export.FORMATS``, and by the batch
workers' server before it forks them."""

# isort: off
from pinn_engine.io.export import vtkfiles, plot3d, cgns, su2, gmsh, openfoam  # noqa: F401

# isort: on
