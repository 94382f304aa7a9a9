"""The 3D Winslow solve: the inexact AMG-preconditioned Picard steps reach
the grid that exact sparse solves of the same steps reach, and each inexact solve meets its
forcing tolerance."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import ROOT
from scipy.sparse.linalg import spsolve

from pinn_engine.hexa import inexact, volume
from pinn_engine.kinds.hexa.mesh import mesh_surface
from pinn_engine.settings import make_settings

DATA = ROOT / "example_data"
SIZE = (15, 13, 11)  # small for the direct solves, yet a hierarchy of 3 multigrid levels
TOL = 1e-9  # winslow's default Picard tolerance (of the extent)


class _DirectSolve:
    """Exact sparse solves of the Picard steps' systems (the reference)."""

    def solve(self, mat, rhs: np.ndarray) -> np.ndarray:
        return spsolve(mat.tocsc(), rhs)


def _tfi(name: str) -> np.ndarray:
    return mesh_surface(str(DATA / name), make_settings("tfi", size=SIZE)).grid


@pytest.mark.parametrize("name", ["hexa_bump_box.vtp", "hexa_bend.vtp"])
def test_inexact_solve_converges_to_the_direct_solves_grid(monkeypatch, name):
    start = _tfi(name)
    extent = float(np.ptp(start.reshape(-1, 3), axis=0).max())
    fast, _ = volume.winslow(start, tol=TOL)
    monkeypatch.setattr(volume, "InexactSolve", _DirectSolve)
    direct, _ = volume.winslow(start, tol=TOL)
    assert np.abs(direct - start).max() > 1e-3 * extent  # Winslow moves the TFI nodes
    assert np.abs(fast - direct).max() < TOL * extent


def test_each_inexact_solve_meets_the_forcing_tolerance():
    assert np.prod(np.subtract(SIZE, 2)) > inexact.COARSEST  # a hierarchy, not one sparse LU
    g = _tfi("hexa_bend.vtp")
    mat, rhs = volume.InteriorStencil.of(tuple(n - 2 for n in SIZE)).system(g)
    x = inexact.InexactSolve().solve(mat, rhs)
    defect = np.linalg.norm(mat @ x - rhs, axis=0)
    assert (defect <= inexact.FORCING * np.linalg.norm(rhs, axis=0)).all()
    assert (defect > 1e-6 * np.linalg.norm(rhs, axis=0)).all()  # inexact: no wasted work
