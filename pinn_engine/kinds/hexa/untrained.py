"""A six-faced block's map where its network is not trained (``kinds.untrained.cannot_win``):
the best start (3D Winslow or TFI), the map a trained model has with its output layer at zero."""

from __future__ import annotations

import os
from dataclasses import dataclass, field

import numpy as np

from pinn_engine.hexa.field import LatticeField
from pinn_engine.kinds.hexa.start import Start
from pinn_engine.kinds.untrained import start_info
from pinn_engine.settings import Settings


@dataclass
class VolumeStartModel:
    """A six-faced block's map where its network is not trained: the 3D TFI of the face
    grids plus the start's correction (a spline through it where the grid is finer than the
    start's lattice), the network's part zero."""

    correction: LatticeField
    settings: Settings
    info: dict
    surface_key: str
    history: dict = field(default_factory=dict)

    @classmethod
    def of(cls, start: Start, settings: Settings, surface_key: str, reason: str, seconds: float):
        """The map of ``start`` (the best start of the surface of ``surface_key``, solved in
        ``seconds``) and what the report says about it: not trained, and why (``reason``)."""
        info = start_info(start.name, reason, {"lattice": list(start.grid.shape[:3])}, seconds)
        return cls(LatticeField(start.grid - start.tfi), settings, info, surface_key)

    def grid(self, tfi: np.ndarray) -> np.ndarray:
        """The grid (ni, nj, nk, 3) whose faces are those of ``tfi`` (the 3D TFI of the face
        grids at the wanted size)."""
        return tfi + self.correction.at_nodes(tfi.shape[:3])

    def save(self, path: str | os.PathLike) -> None:
        """Saved as the trained model it equals: the seeded network, its output layer zero."""
        from pinn_engine.kinds.hexa.problem import untrained_model

        untrained_model(self.correction, self.settings, self.info, self.surface_key).save(path)
