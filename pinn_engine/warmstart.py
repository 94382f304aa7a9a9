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
from scipy.interpolate import CubicSpline, RectBivariateSpline

from .boundary_fit import ArcLengthFit
from .elliptic import safe_controlled_solve, winslow_solve
from .errors import TrainingError
from .geometry import Boundary
from .tfi import node_params, tfi_grid

# The warm start's elliptic solve grows faster than linearly with the nodes (measured on the
# V notch, 2 busy cores: 1 s at 161 x 81, 16 s at 321 x 161, 106 s at 641 x 321); above this
# many nodes it runs on a coarser lattice of the same shape, and the network is evaluated finer.
MAX_LATTICE_NODES = 161 * 81
# Orthogonal sides (SPEC 7): samples of the turn of the leaving derivative along a side, and
# the width (in the side's parameter) over which it tapers to zero at the corners.
WALL_SAMPLES = 401
WALL_TAPER = 0.03
# The wall term fades out at the opposite side, or half way when that side has one too.
OPPOSITE = {"bottom": "top", "top": "bottom", "left": "right", "right": "left"}
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


class WarmStart:
    """The correction ``D`` (nj, ni, 2) from TFI to the elliptic grid, as a smooth field."""

    def __init__(
        self, correction: np.ndarray, nodes: tuple | None = None, start: str = "elliptic"
    ) -> None:
        """``nodes``: the (xi, eta) parameters of the lattice's columns and rows when they
        are not uniform (a boundary-layer lattice, spacing.py)."""
        self.correction = np.asarray(correction, dtype=float)
        self.start = start  # the grid it starts from: "elliptic", or under --objective quality
        # "tfi" (zero correction), a blend of the two, or "optimized" (training._quality_start)
        self.nodes = None if nodes is None else tuple(np.asarray(n, dtype=float) for n in nodes)
        self.walls: dict[str, np.ndarray] = {}  # side -> turn of the leaving derivative
        self._wall_splines: dict[str, CubicSpline] = {}
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
    def elliptic(
        cls, boundary: Boundary, ni: int, nj: int, orthogonal: tuple[str, ...] = ()
    ) -> tuple[WarmStart, np.ndarray]:
        """The warm start from the converged elliptic grid on ``ni`` x ``nj`` nodes (with
        Hilgenstock's orthogonality control at the ``orthogonal`` sides); also returns that
        grid (working frame), the reference the training is checked against."""
        base = tfi_grid(ArcLengthFit(boundary).sample, ni, nj)
        grid = (
            safe_controlled_solve(base, None, orthogonal)[0]
            if orthogonal
            else winslow_solve(base)[0]
        )
        if not np.isfinite(grid).all():
            raise TrainingError(
                "the elliptic grid of the warm start is not finite; train "
                "from TFI instead (warm start none)"
            )
        return cls(grid - base), grid

    @classmethod
    def elliptic_layer(
        cls, boundary: Boundary, params: np.ndarray, orthogonal: tuple[str, ...] = ()
    ) -> WarmStart:
        """The warm start under a spacing (SPEC 7): the elliptic grid with control functions
        on the rectilinear lattice of the mean column and row parameters of ``params``
        (nj, ni, 2), so that the map is resolved, and orthogonal, at the first edges."""
        from .tfi import tfi_at

        xi, eta = params[..., 0].mean(axis=0), params[..., 1].mean(axis=1)
        lattice = np.stack(np.meshgrid(xi, eta), axis=-1)
        base = tfi_at(boundary)(lattice)
        grid = safe_controlled_solve(base, lattice, orthogonal)[0]
        if not np.isfinite(grid).all():
            raise TrainingError(
                "the elliptic grid of the warm start is not finite; train "
                "from TFI instead (warm start none)"
            )
        return cls(grid - base, (xi, eta))

    def orthogonalise(
        self, base_jet, sides: tuple[str, ...], tangents=None, steps: dict[str, float] | None = None
    ) -> None:
        """Turn the map's derivative leaving each of ``sides`` normal to the side (SPEC 7):
        adds ``w(n) phi(a)``, n the distance across the side and a along it, with
        ``w = n (1 - n / R)^2`` up to R (1, or 1/2 when the opposite side has a term too),
        then 0 (zero on the side, slope 1 there, C1 to zero at R) and ``phi`` minus the
        tangential part of the leaving derivative of ``base_jet`` (the map without this
        term), tapered to zero at the corners. The boundary is unchanged, and so is the
        derivative leaving the opposite side; the network then only has to keep it.
        ``tangents(side, t)``: the side's tangents to be normal to (default: the map's).
        ``steps[side]``: turn the first grid edge, from the side to the point this parameter
        distance inside, rather than the derivative (default: the derivative)."""
        t = np.linspace(0.0, 1.0, WALL_SAMPLES)
        taper = np.tanh(t / WALL_TAPER) * np.tanh((1 - t) / WALL_TAPER)
        for side in sides:
            along_xi = side in ("bottom", "top")
            fixed = np.full_like(t, 0.0 if side in ("bottom", "left") else 1.0)
            x = np.column_stack([t, fixed] if along_xi else [fixed, t])
            jet = base_jet(x)
            tangent, leave = (jet[1], jet[2]) if along_xi else (jet[2], jet[1])
            h = 0.0 if steps is None else steps[side]
            if h > 0:  # the chord to the first row, over w(h)
                inner = x.copy()
                inner[:, 1 if along_xi else 0] += h if side in ("bottom", "left") else -h
                reach = 0.5 if OPPOSITE[side] in sides else 1.0
                leave = (
                    (base_jet(inner)[0] - jet[0])
                    * (1 if side in ("bottom", "left") else -1)
                    / (h * (1 - h / reach) ** 2)
                )
            if tangents is not None:
                tangent = tangents(side, t)
            tau = tangent / np.linalg.norm(tangent, axis=1, keepdims=True)
            phi = -np.einsum("ij,ij->i", leave, tau)[:, None] * tau * taper[:, None]
            self.set_wall(side, phi)

    def scale_walls(self, factor: float) -> None:
        """Scale the wall terms (0 removes them)."""
        for side in list(self.walls):
            if factor:
                self.set_wall(side, self.walls[side] * factor)
            else:
                del self.walls[side], self._wall_splines[side]

    def set_wall(self, side: str, phi: np.ndarray) -> None:
        self.walls[side] = np.asarray(phi, dtype=float)
        t = np.linspace(0.0, 1.0, len(self.walls[side]))
        self._wall_splines[side] = CubicSpline(t, self.walls[side])

    def _wall_jet(self, x: np.ndarray, order: int) -> np.ndarray:
        """Jet (6, B, 2) (or values (1, B, 2) for ``order`` 0) of the wall terms."""
        out = np.zeros((6 if order else 1, len(x), 2))
        for side, spline in self._wall_splines.items():
            along_xi = side in ("bottom", "top")
            a, n = (x[:, 0], x[:, 1]) if along_xi else (x[:, 1], x[:, 0])
            m = n if side in ("bottom", "left") else 1 - n  # distance from the side
            reach = 0.5 if OPPOSITE[side] in self._wall_splines else 1.0
            inside = m < reach
            r = np.where(inside, 1 - m / reach, 0.0)  # w = m r^2: C1 to zero at the reach
            w = m * r * r
            w1 = np.where(inside, r * r - 2 * m * r / reach, 0.0)
            w2 = np.where(inside, -4 * r / reach + 2 * m / reach**2, 0.0)
            if side in ("top", "right"):  # d/dn = -d/dm: w(n) = -m r^2 turns x_n like w(m)
                w, w2 = -w, -w2
            f, f1, f2 = (spline(a, k) for k in range(3))
            w, w1, w2 = w[:, None], w1[:, None], w2[:, None]
            if not order:
                out[0] += w * f
            elif along_xi:  # channels V, XI, ETA, XIXI, XIETA, ETAETA
                out += np.stack([w * f, w * f1, w1 * f, w * f2, w1 * f1, w2 * f])
            else:
                out += np.stack([w * f, w1 * f, w * f1, w2 * f, w1 * f1, w * f2])
        return out

    def jet(self, x: np.ndarray) -> np.ndarray:
        """Jet (6, B, 2) of the correction at points ``x`` (B, 2) = (xi, eta)."""
        xi, eta = x[:, 0], x[:, 1]
        jet = np.stack(
            [
                np.stack([s.ev(eta, xi, dx=a, dy=b) for s in self._splines], axis=-1)
                for a, b in _ORDERS
            ]
        )
        return jet + self._wall_jet(x, 2) if self.walls else jet

    def at(self, x: np.ndarray) -> np.ndarray:
        """The correction (B, 2) at points ``x`` (B, 2) = (xi, eta)."""
        out = np.stack([s.ev(x[:, 1], x[:, 0]) for s in self._splines], axis=-1)
        return out + self._wall_jet(x, 0)[0] if self.walls else out

    def grid(self, ni: int, nj: int, rows: slice = slice(None)) -> np.ndarray:
        """The correction at the nodes of an ``ni`` x ``nj`` grid (only ``rows`` if given)."""
        xi, eta = node_params(ni), node_params(nj)[rows]
        out = np.stack([s(eta, xi) for s in self._splines], axis=-1)
        if self.walls:
            pts = np.stack(np.meshgrid(xi, eta), axis=-1).reshape(-1, 2)
            out = out + self._wall_jet(pts, 0)[0].reshape(out.shape)
        return out
