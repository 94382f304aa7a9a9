"""pinn-mesh: structured quadrilateral meshes from a physics-informed neural network.

``pinn_engine.report(grid)`` reads a grid's report as a dict and ``pinn_engine.save(grid,
path, patches=...)`` writes a grid for a CFD solver (both imported on first use: they need
pyvista); grids come from ``PolyData.pinn_mesh(...)``. ``__version__`` is read on first use
too (the installed package's metadata: about 80 ms of a run's start that most runs never use).
"""

from importlib import import_module

from pinn_engine.errors import (
    CrossingCutWarning,
    FoldedCellsWarning,
    InputError,
    PinnMeshError,
    TrainingStoppedWarning,
    WallAngleWarning,
)

# the public functions of the pyvista route, by their name there
_PYVISTA = {"report": "report", "save": "save_mesh"}
_ROUTE = "pinn_engine.routes.pyvista_accessor"

__all__ = [
    "CrossingCutWarning",
    "FoldedCellsWarning",
    "InputError",
    "PinnMeshError",
    "TrainingStoppedWarning",
    "WallAngleWarning",
    "__version__",
    *_PYVISTA,
]


def __getattr__(name: str):
    if name == "__version__":
        return import_module("pinn_engine._version").__version__
    if name in _PYVISTA:
        return getattr(import_module(_ROUTE), _PYVISTA[name])
    raise AttributeError(f"module 'pinn_engine' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_PYVISTA, "__version__"})
