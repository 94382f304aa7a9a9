"""What every writer gets: the grid's nodes, its patch names and the extrusion, if any (a 2D
grid's :class:`Block`), or a hexahedral grid's nodes and six patch names (:class:`Box`)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pinn_engine.io.export.patches import BOX_SIDES, groups, type_of
from pinn_engine.io.export.topology import layers


@dataclass(frozen=True)
class Block:
    """One structured block: ``points`` (nj, ni, 3) in the user's units, the four patch
    names (bottom, right, top, left), the extrusion thickness (None: 2D) and the unit
    normal it extrudes along (+z for a grid in a plane z = const)."""

    points: np.ndarray
    names: tuple[str, ...]
    thickness: float | None = None
    normal: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))
    topology: str | None = None  # "o" or "c": an O- or C-grid around a body (bodies.py)
    n_wake: int = 0  # the C-grid's lower trailing-edge node index
    types: tuple[str, ...] | None = None  # each side's patch type (patchnames.TYPES)

    @property
    def ni(self) -> int:
        return self.points.shape[1]

    @property
    def nj(self) -> int:
        return self.points.shape[0]

    def layers(self) -> np.ndarray:
        """Nodes as (nk, nj, ni, 3): nk = 1 in 2D, 2 when extruded."""
        return layers(self.points, self.thickness, self.normal)

    def patches(self) -> dict[str, list[str]]:
        """Patch name -> its sides, in the order of first appearance."""
        return groups(self.names)

    def patch_type(self, name: str) -> str:
        """The type (``patchnames.TYPES``) of the patch ``name``: given, or by its name."""
        return type_of(self.names, self.types, name)


@dataclass(frozen=True)
class Box:
    """One hexahedral block (SPEC 11): ``xyz`` (nk, nj, ni, 3), right-handed in (i, j, k)
    (positive cell volumes), and the patch names and types of its six sides (imin, imax,
    jmin, jmax, kmin, kmax)."""

    xyz: np.ndarray
    names: tuple[str, ...]
    types: tuple[str, ...]

    @property
    def shape(self) -> tuple[int, int, int]:
        """Nodes along i, j and k."""
        nk, nj, ni = self.xyz.shape[:3]
        return ni, nj, nk

    def patches(self) -> dict[str, list[str]]:
        """Patch name -> its sides, in the order of first appearance."""
        return groups(self.names, BOX_SIDES)

    def patch_type(self, name: str) -> str:
        """The type (``patchnames.TYPES``) of the patch ``name``."""
        return type_of(self.names, self.types, name)
