"""The elliptic warm start of the default PINN: the map starts as the converged Winslow grid.

The converged elliptic grid E on a lattice of ni x nj nodes differs from the polyline TFI T
on the same boundary nodes by D = E - T, which is zero on the boundary. A bicubic spline
through D (zero along the four sides, since it interpolates zeros there) is added to the TFI
base of the hard-boundary map, so that with the network's output layer at zero the map *is*
the elliptic grid at the lattice nodes, and a smooth interpolant of it between them. Training
on the Winslow and auxiliary-line losses then starts where the classical method ends, not at
TFI: on
shapes with sharp features the PINN from TFI stalls halfway or folds (issue 11), the warm
start does not, and it needs tens of L-BFGS iterations instead of thousands of Adam epochs.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.interpolate import RectBivariateSpline

from .boundary_fit import ArcLengthFit
from .elliptic import controlled_solve, winslow_solve
from .errors import TrainingError
from .geometry import Boundary
from .orthogonal import orthogonal_grid
from .tfi import node_params, tfi_at, tfi_grid

# The warm start's elliptic solve grows faster than linearly with the nodes (measured on the
# V notch, 2 busy cores: 1 s at 161 x 81, 16 s at 321 x 161, 106 s at 641 x 321); above this
# many nodes it runs on a coarser lattice of the same shape, and the network is evaluated finer.
MAX_LATTICE_NODES = 161 * 81
# (d_eta, d_xi) orders of the jet channels V, XI, ETA, XIXI, XIETA, ETAETA (jet/layers.py)
_ORDERS = ((0, 0), (0, 1), (1, 0), (0, 2), (1, 1), (2, 0))


def lattice_for(ni: int, nj: int) -> tuple[int, int]:
    """The warm start's lattice for an ``ni`` x ``nj`` grid: the grid itself up to about
    ``MAX_LATTICE_NODES`` nodes, else a coarser one with the same ratio of cells per side."""
    if ni * nj <= MAX_LATTICE_NODES:
        return ni, nj
    scale = math.sqrt(MAX_LATTICE_NODES / (ni * nj))
    return max(2, int((ni - 1) * scale) + 1), max(2, int((nj - 1) * scale) + 1)


def _at_least_4(d: np.ndarray, axis: int) -> np.ndarray:
    """``d`` with nodes added by linear interpolation between its nodes along ``axis`` until
    there are at least 4 (a bicubic spline needs them); the given nodes keep their values."""
    n = d.shape[axis]
    if n >= 4:
        return d
    fine = (n - 1) * (2 if n == 3 else 3) + 1
    t, t_fine = np.linspace(0, 1, n), np.linspace(0, 1, fine)
    return np.apply_along_axis(lambda v: np.interp(t_fine, t, v), axis, d)


def _finite(grid: np.ndarray) -> np.ndarray:
    if not np.isfinite(grid).all():
        raise TrainingError(
            "the elliptic grid of the warm start is not finite; train "
            "from TFI instead (warm start none)"
        )
    return grid


class WarmStart:
    """The correction ``D`` (nj, ni, 2) from TFI to the elliptic grid, as a smooth field."""

    def __init__(
        self, correction: np.ndarray, nodes: tuple | None = None, start: str = "elliptic"
    ) -> None:
        """``nodes``: the (xi, eta) parameters of the lattice's columns and rows when they
        are not uniform (a boundary-layer lattice, spacing.py)."""
        self.correction = np.asarray(correction, dtype=float)
        self.start = start  # the grid it starts from: "elliptic", or under --objective quality
        # "tfi" (zero correction), a blend, ... (quality_start.quality_start)
        self.nodes = None if nodes is None else tuple(np.asarray(n, dtype=float) for n in nodes)
        if self.nodes is not None and min(self.correction.shape[:2]) >= 4:
            self._splines = [
                RectBivariateSpline(self.nodes[1], self.nodes[0], self.correction[..., k], s=0)
                for k in range(2)
            ]
            return
        d = _at_least_4(_at_least_4(self.correction, 0), 1)
        eta, xi = node_params(d.shape[0]), node_params(d.shape[1])
        self._splines = [RectBivariateSpline(eta, xi, d[..., k], s=0) for k in range(2)]

    @classmethod
    def elliptic(cls, boundary: Boundary, ni: int, nj: int) -> tuple[WarmStart, np.ndarray]:
        """The warm start from the converged elliptic grid on ``ni`` x ``nj`` nodes; also
        returns that grid (working frame), the reference the training is checked against."""
        base = tfi_grid(ArcLengthFit(boundary).sample, ni, nj)
        grid = _finite(winslow_solve(base)[0])
        return cls(grid - base), grid

    @classmethod
    def orthogonal(
        cls,
        boundary: Boundary,
        ni: int,
        nj: int,
        sides: tuple[str, ...],
        params: np.ndarray | None = None,
        heights: dict[str, float] | None = None,
    ) -> tuple[WarmStart, np.ndarray]:
        """The warm start of ``--orthogonal`` (SPEC 7): the elliptic grid with its first rows
        on the normals of ``sides`` (orthogonal.py), and that grid (the guard's reference).

        Under a spacing, ``params`` (nj, ni, 2) are its node parameters (spacing.py; each
        grid line has its own stretching). The grid's nodes then sit at the rectilinear
        lattice of their mean columns and rows (:attr:`nodes`, where the map is evaluated at
        this size): the boundary nodes are there, the interior follows ``params`` through
        the control functions, and the first rows are ``heights`` from the spaced orthogonal
        sides. A spline on a rectilinear lattice keeps the map smooth between the nodes."""
        if params is None:
            base = tfi_grid(ArcLengthFit(boundary).sample, ni, nj)
            grid = orthogonal_grid(_finite(winslow_solve(base)[0]), sides)
            return cls(_finite(grid) - base, start="orthogonal"), grid
        nodes = params[..., 0].mean(axis=0), params[..., 1].mean(axis=1)
        base = tfi_at(boundary)(np.stack(np.meshgrid(*nodes), axis=-1))
        grid = _finite(controlled_solve(base, params)[0])
        grid = _finite(orthogonal_grid(grid, sides, params, heights))
        return cls(grid - base, nodes, "orthogonal"), grid

    def jet(self, x: np.ndarray) -> np.ndarray:
        """Jet (6, B, 2) of the correction at points ``x`` (B, 2) = (xi, eta)."""
        xi, eta = x[:, 0], x[:, 1]
        jet = np.stack(
            [
                np.stack([s.ev(eta, xi, dx=a, dy=b) for s in self._splines], axis=-1)
                for a, b in _ORDERS
            ]
        )
        return jet

    def at(self, x: np.ndarray) -> np.ndarray:
        """The correction (B, 2) at points ``x`` (B, 2) = (xi, eta)."""
        return np.stack([s.ev(x[:, 1], x[:, 0]) for s in self._splines], axis=-1)

    def grid(self, ni: int, nj: int, rows: slice = slice(None)) -> np.ndarray:
        """The correction at the nodes of an ``ni`` x ``nj`` grid (only ``rows`` if given)."""
        xi, eta = node_params(ni), node_params(nj)[rows]
        return np.stack([s(eta, xi) for s in self._splines], axis=-1)
