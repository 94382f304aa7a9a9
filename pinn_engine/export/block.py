"""What every writer gets: the grid's nodes, its patch names and the extrusion, if any."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .patches import groups
from .topology import layers


@dataclass(frozen=True)
class Block:
    """One structured block: ``points`` (nj, ni, 3) in the user's units, the four patch
    names (bottom, right, top, left) and the extrusion thickness (None: 2D)."""

    points: np.ndarray
    names: tuple[str, ...]
    thickness: float | None = None

    @property
    def ni(self) -> int:
        return self.points.shape[1]

    @property
    def nj(self) -> int:
        return self.points.shape[0]

    def layers(self) -> np.ndarray:
        """Nodes as (nk, nj, ni, 3): nk = 1 in 2D, 2 when extruded."""
        return layers(self.points, self.thickness)

    def patches(self) -> dict[str, list[str]]:
        """Patch name -> its sides, in the order of first appearance."""
        return groups(self.names)
