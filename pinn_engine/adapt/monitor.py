"""The monitor of SPEC 14, ``M = sqrt(1 + beta^2 |grad f|^2 / max |grad f|^2)``, of a field
sampled at a grid's nodes, and the equidistribution it asks for."""

from __future__ import annotations

import numpy as np

# Passes of averaging (nodes to cells and back) of |grad f| before the monitor is formed: one
# noisy cell's gradient is spread over its neighbours, a front a few cells wide is kept
SMOOTHING_PASSES = 2


def cell_gradient_vectors(points: np.ndarray, cells: np.ndarray, f: np.ndarray) -> np.ndarray:
    """grad f (m, 2) at each cell's centre (the bilinear map's Jacobian there), cells (m, 4)
    counter-clockwise."""
    p, v = points[cells], f[cells]
    x_xi = 0.5 * (p[:, 1] - p[:, 0] + p[:, 2] - p[:, 3])
    x_eta = 0.5 * (p[:, 3] - p[:, 0] + p[:, 2] - p[:, 1])
    f_xi = 0.5 * (v[:, 1] - v[:, 0] + v[:, 2] - v[:, 3])
    f_eta = 0.5 * (v[:, 3] - v[:, 0] + v[:, 2] - v[:, 1])
    jac = x_xi[:, 0] * x_eta[:, 1] - x_xi[:, 1] * x_eta[:, 0]
    jac = np.where(np.abs(jac) > 1e-300, jac, 1e-300)
    gx = (f_xi * x_eta[:, 1] - f_eta * x_xi[:, 1]) / jac
    gy = (-f_xi * x_eta[:, 0] + f_eta * x_xi[:, 0]) / jac
    return np.column_stack([gx, gy])


def cell_gradients(points: np.ndarray, cells: np.ndarray, f: np.ndarray) -> np.ndarray:
    """|grad f| at each cell's centre."""
    g = cell_gradient_vectors(points, cells, f)
    return np.hypot(g[:, 0], g[:, 1])


def to_nodes(cells: np.ndarray, values: np.ndarray, n: int) -> np.ndarray:
    """The mean of each node's cells' ``values``."""
    total = np.bincount(cells.ravel(), np.repeat(values, 4), minlength=n)
    return total / np.maximum(np.bincount(cells.ravel(), minlength=n), 1)


def gradient_size(
    points: np.ndarray, cells: np.ndarray, f: np.ndarray, passes: int = SMOOTHING_PASSES
) -> np.ndarray:
    """|grad f| at the nodes, smoothed by ``passes``."""
    g = to_nodes(cells, cell_gradients(points, cells, f), len(points))
    for _ in range(passes):
        g = to_nodes(cells, g[cells].mean(axis=1), len(points))
    return g


def monitor_values(
    gradient: np.ndarray, strength: float | np.ndarray, largest: float
) -> np.ndarray:
    """SPEC 14's monitor of the node gradients, ``largest`` the max |grad f| it is scaled by."""
    if largest <= 0.0:
        return np.ones_like(gradient)
    return np.sqrt(1.0 + (strength * gradient / largest) ** 2)


def cell_areas(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Each cell's area (half the cross product of its diagonals)."""
    p = points[cells]
    d1, d2 = p[:, 2] - p[:, 0], p[:, 3] - p[:, 1]
    return 0.5 * np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])


def equidistribution(points: np.ndarray, cells: np.ndarray, m: np.ndarray) -> float:
    """The coefficient of variation of M times cell area over the cells (0: M is
    equidistributed), M at a cell the mean of its nodes'."""
    w = m[cells].mean(axis=1) * cell_areas(points, cells)
    return float(w.std() / w.mean()) if w.mean() > 0 else 0.0
