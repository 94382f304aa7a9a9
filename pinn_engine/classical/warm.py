"""The start a map builds in: a smooth correction field from the TFI base to a start grid.

The start grid S on a lattice of ni x nj nodes (the converged elliptic grid by default,
:mod:`pinn_engine.starts`) differs from the polyline TFI T on the same boundary nodes by
D = S - T, which is zero on the boundary. A bicubic spline through D (zero along the four
sides, since it interpolates zeros there) is added to the TFI base of the hard-boundary map,
so that with the network's output layer at zero the map *is* the start grid at the lattice
nodes, and a smooth interpolant of it between them.
"""

from __future__ import annotations

import functools

import numpy as np

from pinn_engine.classical.tfi import node_params

# (d_eta, d_xi) orders of the jet channels V, XI, ETA, XIXI, XIETA, ETAETA (jet/layers.py)
JET_ORDERS = ((0, 0), (0, 1), (1, 0), (0, 2), (1, 1), (2, 0))


def _at_least_4(d: np.ndarray, axis: int) -> np.ndarray:
    """``d`` with nodes added by linear interpolation between its nodes along ``axis`` until
    there are at least 4 (a bicubic spline needs them); the given nodes keep their values."""
    n = d.shape[axis]
    if n >= 4:
        return d
    fine = (n - 1) * (2 if n == 3 else 3) + 1
    t, t_fine = np.linspace(0, 1, n), np.linspace(0, 1, fine)
    return np.apply_along_axis(lambda v: np.interp(t_fine, t, v), axis, d)


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

    @functools.cached_property
    def _splines(self) -> list:
        """The bicubic splines of the two coordinates, built at their first use: a start that
        is only asked for its own lattice's nodes (an untrained map at the lattice's size)
        needs none, and imports no ``scipy.interpolate``."""
        from scipy.interpolate import RectBivariateSpline

        if self.nodes is not None and min(self.correction.shape[:2]) >= 4:
            return [
                RectBivariateSpline(self.nodes[1], self.nodes[0], self.correction[..., k], s=0)
                for k in range(2)
            ]
        d = _at_least_4(_at_least_4(self.correction, 0), 1)
        eta, xi = node_params(d.shape[0]), node_params(d.shape[1])
        return [RectBivariateSpline(eta, xi, d[..., k], s=0) for k in range(2)]

    def jet(self, x: np.ndarray) -> np.ndarray:
        """Jet (6, B, 2) of the correction at points ``x`` (B, 2) = (xi, eta)."""
        xi, eta = x[:, 0], x[:, 1]
        jet = np.stack(
            [
                np.stack([s.ev(eta, xi, dx=a, dy=b) for s in self._splines], axis=-1)
                for a, b in JET_ORDERS
            ]
        )
        return jet

    def at(self, x: np.ndarray) -> np.ndarray:
        """The correction (B, 2) at points ``x`` (B, 2) = (xi, eta)."""
        return np.stack([s.ev(x[:, 1], x[:, 0]) for s in self._splines], axis=-1)

    def grid(self, ni: int, nj: int, rows: slice = slice(None)) -> np.ndarray:
        """The correction at the nodes of an ``ni`` x ``nj`` grid (only ``rows`` if given);
        on the lattice's own uniform nodes, its values there (the splines interpolate them)."""
        if self.nodes is None and self.correction.shape[:2] == (nj, ni):
            return self.correction[rows].copy()
        xi, eta = node_params(ni), node_params(nj)[rows]
        return np.stack([s(eta, xi) for s in self._splines], axis=-1)
