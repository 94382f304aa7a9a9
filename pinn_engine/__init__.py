"""pinn-mesh: structured quadrilateral meshes from a physics-informed neural network."""

from .errors import FoldedCellsWarning

__all__ = ["FoldedCellsWarning"]
__version__ = "0.1.0"
