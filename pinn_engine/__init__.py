"""pinn-mesh: structured quadrilateral meshes from a physics-informed neural network.

``pinn_engine.report(grid)`` reads a grid's report as a dict and ``pinn_engine.save(grid,
path, patches=...)`` writes a grid for a CFD solver and ``pinn_engine.read_airfoil(path)``
reads an airfoil ``.dat`` file and ``pinn_engine.read_blockmeshdict(path)`` meshes an
OpenFOAM blockMeshDict's blocks (each imported on first use: they need pyvista); grids come
from ``PolyData.pinn_mesh(...)``. ``pinn_engine.fit_family(boundaries, size=...)`` fits one
model on a family of shapes (SPEC 16) whose ``mesh(boundary)`` meshes a new member in a
forward pass; ``load_family(path)`` reads a saved one. ``__version__`` is read on first use
too (the installed package's metadata: about 80 ms of a run's start that most runs never use).
"""

from pinn_engine.errors import (
    CrossingCutWarning,
    FamilyFallbackWarning,
    FoldedCellsWarning,
    InputError,
    JetKernelsWarning,
    KeywordError,
    MissingExtraError,
    PinnMeshError,
    TrainingStoppedWarning,
    WallAngleWarning,
)
from pinn_engine.kinds import registered as _registered  # noqa: F401  each kind's settings
from pinn_engine.lazy import lazy_names
from pinn_engine.routes import names as _names  # noqa: F401  the routes' words for errors

# the version, and the public functions of the pyvista route by their name there
_LAZY = {
    "__version__": "pinn_engine._version",
    "read_airfoil": "pinn_engine.routes.pyvista_accessor:read_airfoil",
    "read_blockmeshdict": "pinn_engine.routes.pyvista_accessor:read_blockmeshdict",
    "report": "pinn_engine.routes.pyvista_accessor:report",
    "save": "pinn_engine.routes.pyvista_accessor:save_mesh",
    "fit_family": "pinn_engine.batch.family:fit_family",
    "load_family": "pinn_engine.batch.family:load_family",
    "FamilyMesher": "pinn_engine.batch.family:FamilyMesher",
}

__all__ = [
    "CrossingCutWarning",
    "FamilyFallbackWarning",
    "FamilyMesher",
    "FoldedCellsWarning",
    "InputError",
    "JetKernelsWarning",
    "KeywordError",
    "MissingExtraError",
    "PinnMeshError",
    "TrainingStoppedWarning",
    "WallAngleWarning",
    "__version__",
    "fit_family",
    "load_family",
    "read_airfoil",
    "read_blockmeshdict",
    "report",
    "save",
]
__getattr__, __dir__ = lazy_names(__name__, _LAZY)
