"""pinn-mesh: structured quadrilateral meshes from a physics-informed neural network."""

from ._version import __version__
from .errors import FoldedCellsWarning

__all__ = ["FoldedCellsWarning", "__version__"]
