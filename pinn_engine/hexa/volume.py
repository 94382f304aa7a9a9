"""Volume grids (ni, nj, nk, 3) from their six boundary faces: 3D transfinite interpolation
and the 3D Winslow equations, solved like the 2D ones (Picard steps, frozen coefficients,
sparse LU)."""

from __future__ import annotations

import itertools

import numpy as np
import scipy.sparse as sp

from pinn_engine.classical.elliptic import ReusedLU
from pinn_engine.hexa.controls import parameter_controls


def _lerp(g: np.ndarray, axis: int, params: np.ndarray | None = None) -> np.ndarray:
    """Linear interpolation of ``g`` along ``axis`` between its first and last slices, at
    the node parameters ``params[..., axis]`` (default: uniform)."""
    n = g.shape[axis]
    t = np.linspace(0.0, 1.0, n).reshape([-1 if a == axis else 1 for a in range(g.ndim)])
    if params is not None:
        t = params[..., axis : axis + 1]
    first = np.take(g, [0], axis=axis)
    last = np.take(g, [n - 1], axis=axis)
    return (1.0 - t) * first + t * last


def tfi(boundary: np.ndarray, params: np.ndarray | None = None) -> np.ndarray:
    """3D transfinite interpolation (Boolean sum of the three linear projectors) of the face
    nodes of ``boundary``; its interior values are ignored. ``params`` (ni, nj, nk, 3): each
    node's parameters along i, j, k (a spacing's distribution; default uniform)."""
    out = np.zeros_like(boundary, dtype=float)
    for count in (1, 2, 3):
        for axes in itertools.combinations(range(3), count):
            g = boundary
            for axis in axes:
                g = _lerp(g, axis, params)
            out += (-1) ** (count + 1) * g
    return out


def _cofactors(g: np.ndarray) -> dict[tuple[int, int], np.ndarray]:
    """Cofactors C_mn of the metric tensor at interior nodes (central differences); the
    Winslow equations are sum_mn C_mn x_{xi_m xi_n} = 0."""
    d = []
    for m in range(3):
        plus = tuple(slice(2, None) if a == m else slice(1, -1) for a in range(3))
        minus = tuple(slice(None, -2) if a == m else slice(1, -1) for a in range(3))
        d.append(0.5 * (g[plus] - g[minus]))
    m = [[np.einsum("...k,...k->...", d[a], d[b]) for b in range(3)] for a in range(3)]
    return {
        (0, 0): m[1][1] * m[2][2] - m[1][2] ** 2,
        (1, 1): m[0][0] * m[2][2] - m[0][2] ** 2,
        (2, 2): m[0][0] * m[1][1] - m[0][1] ** 2,
        (0, 1): m[0][2] * m[1][2] - m[0][1] * m[2][2],
        (0, 2): m[0][1] * m[1][2] - m[0][2] * m[1][1],
        (1, 2): m[0][1] * m[0][2] - m[0][0] * m[1][2],
    }


def _stencil(
    c: dict[tuple[int, int], np.ndarray], controls: list[np.ndarray] | None = None
) -> dict[tuple[int, int, int], np.ndarray]:
    """19-point weights of the frozen-coefficient Winslow operator, by offset; with
    ``controls`` (P_m at interior nodes) the terms ``sum_m P_m x_{xi_m}`` are added."""
    weights = {(0, 0, 0): -2.0 * (c[(0, 0)] + c[(1, 1)] + c[(2, 2)])}
    for m in range(3):
        for s in (1, -1):
            off = [0, 0, 0]
            off[m] = s
            weights[tuple(off)] = c[(m, m)] + (0.0 if controls is None else 0.5 * s * controls[m])
    for m, n in ((0, 1), (0, 2), (1, 2)):
        for sm, sn in itertools.product((1, -1), repeat=2):
            off = [0, 0, 0]
            off[m], off[n] = sm, sn
            weights[tuple(off)] = 0.5 * sm * sn * c[(m, n)]
    return weights


def stencil_matrix(
    g: np.ndarray, params: np.ndarray | None = None
) -> tuple[sp.csc_matrix, np.ndarray]:
    """The Winslow system over the interior nodes with coefficients frozen at ``g``; the
    boundary nodes' terms go to the right-hand side. With node ``params`` (ni, nj, nk, 3)
    their distribution's control terms are added (:func:`controls.parameter_controls`)."""
    ni, nj, nk = g.shape[:3]
    shape = (ni - 2, nj - 2, nk - 2)
    idx = np.indices(shape).reshape(3, -1).T + 1
    row = np.arange(idx.shape[0])
    rows, cols, vals = [], [], []
    rhs = np.zeros((row.size, 3))
    c = _cofactors(g)
    controls = None if params is None else parameter_controls(c, params)
    for off, w in _stencil(c, controls).items():
        w = w.reshape(-1)
        nb = idx + np.array(off)
        inner = ((nb > 0) & (nb < np.array([ni, nj, nk]) - 1)).all(axis=1)
        rows.append(row[inner])
        cols.append(np.ravel_multi_index(tuple((nb[inner] - 1).T), shape))
        vals.append(w[inner])
        edge = ~inner
        far = nb[edge]
        np.subtract.at(rhs, row[edge], w[edge][:, None] * g[far[:, 0], far[:, 1], far[:, 2]])
    mat = sp.csc_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
        shape=(row.size, row.size),
    )
    return mat, rhs


def winslow(
    start: np.ndarray,
    tol: float = 1e-9,
    max_iterations: int = 200,
    params: np.ndarray | None = None,
) -> tuple[np.ndarray, int]:
    """3D Winslow grid by Picard iteration from ``start`` (its faces are kept): each step
    solves the frozen-coefficient system by defect correction with a reused sparse LU.
    ``params``: node parameters whose distribution the grid keeps (control terms).
    Stops when no node moves more than ``tol`` times the grid's extent; returns the grid
    and the number of steps."""
    g = np.array(start, dtype=float)
    if min(g.shape[:3]) < 3:
        return g, 0
    extent = float(np.ptp(g.reshape(-1, 3), axis=0).max())
    solver = ReusedLU()
    inner_shape = tuple(n - 2 for n in g.shape[:3]) + (3,)
    for it in range(1, max_iterations + 1):
        mat, rhs = stencil_matrix(g, params)
        inner = g[1:-1, 1:-1, 1:-1].reshape(-1, 3)
        step, change = solver.solve(mat, rhs - mat @ inner)
        g[1:-1, 1:-1, 1:-1] = (inner + step).reshape(inner_shape)
        if change <= tol * extent:
            return g, it
    return g, max_iterations
