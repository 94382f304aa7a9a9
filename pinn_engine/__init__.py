"""pinn-mesh: structured quadrilateral meshes from a physics-informed neural network."""

from ._version import __version__
from .errors import FoldedCellsWarning, WallAngleWarning

__all__ = ["FoldedCellsWarning", "WallAngleWarning", "__version__"]
