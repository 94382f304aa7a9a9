"""A meshing result, the same for every block kind and route: grid, report, history, cells."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pinn_engine.geometry.plane import Plane


@dataclass
class MeshResult:
    """A grid (nj, ni, 2) in the user's in-plane coordinates (x, y for a boundary in a plane
    z = const), with what a user needs to judge it; ``points3d`` in the user's 3D frame."""

    points: np.ndarray
    report: dict
    history: dict[str, list[float]] = field(default_factory=dict)
    cells: dict[str, np.ndarray] = field(default_factory=dict)
    plane: Plane = field(default_factory=Plane.horizontal)

    @property
    def points3d(self) -> np.ndarray:
        """The grid (nj, ni, 3) in the user's 3D frame (the boundary's plane)."""
        return self.plane.lift(self.points)

    @property
    def quality(self) -> dict:
        return self.report["quality"]
