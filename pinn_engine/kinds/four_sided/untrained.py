"""A four-sided block's map where its network is not trained (``kinds.untrained.cannot_win``):
its start, the map a trained model has with its output layer at zero."""

from __future__ import annotations

import os
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pinn_engine.classical.tfi import tfi_at, tfi_grid
from pinn_engine.classical.warm import WarmStart
from pinn_engine.geometry.auxlines import AuxLine
from pinn_engine.geometry.boundary import Boundary
from pinn_engine.geometry.boundary_fit import ArcLengthFit
from pinn_engine.kinds.untrained import start_info
from pinn_engine.quality import guard_figures
from pinn_engine.settings import Settings
from pinn_engine.starts.quad_start import quad_start
from pinn_engine.starts.untangle import untangled_report
from pinn_engine.starts.warmstart import lattice_for


@dataclass
class StartModel:
    """A four-sided block's map where its network is not trained: the TFI base plus the
    start's correction, the network's part zero."""

    boundary: Boundary
    warm: WarmStart
    settings: Settings
    info: dict
    history: dict = field(default_factory=dict)

    @classmethod
    def of(cls, boundary: Boundary, aux: Sequence[AuxLine], settings: Settings, reason: str):
        """The start of ``boundary`` (working frame) on ``settings.lattice``, and what the
        report says about it: not trained, and why (``reason``)."""
        began = time.perf_counter()
        lattice = lattice_for(*settings.lattice)
        begin = quad_start(boundary, settings, lattice, aux)
        guard = {"lattice": list(lattice), "elliptic": guard_figures(begin.reference)}
        info = start_info(begin.warm.start, reason, guard, time.perf_counter() - began)
        if begin.winslow is not None:
            info["untangled"] = untangled_report(begin.winslow, begin.reference)
        return cls(boundary, begin.warm, settings, info)

    def grid(self, ni: int, nj: int, params: np.ndarray | None = None) -> np.ndarray:
        """Grid (nj, ni, 2) in the working frame: the start, between the lattice's nodes its
        spline; at node parameters ``params`` (nj, ni, 2) where given."""
        if params is None:
            return tfi_grid(ArcLengthFit(self.boundary).sample, ni, nj) + self.warm.grid(ni, nj)
        correction = self.warm.at(params.reshape(-1, 2)).reshape(params.shape)
        return tfi_at(self.boundary)(params) + correction

    def save(self, path: str | os.PathLike) -> Path:
        """Saved as the trained model it equals: the seeded network, its output layer zero."""
        from pinn_engine.kinds.four_sided.problem import untrained_model

        return untrained_model(self.boundary, self.warm, self.settings, self.info).save(path)
