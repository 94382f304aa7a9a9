"""pinn-mesh: structured quadrilateral meshes from a physics-informed neural network."""

from pinn_engine._version import __version__
from pinn_engine.errors import FoldedCellsWarning, TrainingStoppedWarning, WallAngleWarning

__all__ = ["FoldedCellsWarning", "TrainingStoppedWarning", "WallAngleWarning", "__version__"]
