"""The elliptic (Winslow) grid generator, the paper's "PDE method" (paper eq. 7 and 8).

Both solvers take a grid (nj, ni, 2) whose boundary nodes are fixed and return a new grid
whose interior satisfies the discrete Winslow equations in index space (the equations are
invariant to the spacing of xi and eta, so index space is exact, not an approximation).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu


def _coefficients(g: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """alpha, beta, gamma of paper eq. 8 at interior nodes, central differences."""
    g_xi = 0.5 * (g[1:-1, 2:] - g[1:-1, :-2])
    g_eta = 0.5 * (g[2:, 1:-1] - g[:-2, 1:-1])
    alpha = np.einsum("...k,...k->...", g_eta, g_eta)
    beta = np.einsum("...k,...k->...", g_xi, g_eta)
    gamma = np.einsum("...k,...k->...", g_xi, g_xi)
    return alpha, beta, gamma


def winslow_residual(g: np.ndarray) -> np.ndarray:
    """Discrete Winslow residual (paper eq. 7) at interior nodes, shape (nj-2, ni-2, 2)."""
    a, b, c = (v[..., None] for v in _coefficients(g))
    g_xixi = g[1:-1, 2:] - 2 * g[1:-1, 1:-1] + g[1:-1, :-2]
    g_etaeta = g[2:, 1:-1] - 2 * g[1:-1, 1:-1] + g[:-2, 1:-1]
    g_xieta = 0.25 * (g[2:, 2:] - g[:-2, 2:] - g[2:, :-2] + g[:-2, :-2])
    return a * g_xixi - 2 * b * g_xieta + c * g_etaeta


def winslow_sweeps(grid: np.ndarray, iterations: int = 1000, zero_interior: bool = True
                   ) -> np.ndarray:
    """The paper's PDE run: point-Jacobi sweeps from an interior initialised to 0."""
    g = np.array(grid, dtype=float)
    if zero_interior:
        g[1:-1, 1:-1] = 0.0
    for _ in range(iterations):
        a, b, c = (v[..., None] for v in _coefficients(g))
        cross = 0.25 * (g[2:, 2:] - g[:-2, 2:] - g[2:, :-2] + g[:-2, :-2])
        num = (a * (g[1:-1, 2:] + g[1:-1, :-2]) + c * (g[2:, 1:-1] + g[:-2, 1:-1])
               - 2 * b * cross)
        den = 2 * (a + c)
        ok = den > 0  # nodes whose neighbours are all still 0 wait for the front to arrive
        g[1:-1, 1:-1] = np.where(ok, num / np.where(ok, den, 1.0), g[1:-1, 1:-1])
    return g


def _stencil_matrix(g: np.ndarray) -> tuple[sp.csc_matrix, np.ndarray]:
    """Linear system of the Winslow equations with alpha, beta, gamma frozen at ``g``."""
    nj, ni = g.shape[:2]
    a, b, c = _coefficients(g)
    # 9-point stencil weights, offsets (dj, di)
    weights = {
        (0, 0): -2 * (a + c), (0, 1): a, (0, -1): a, (1, 0): c, (-1, 0): c,
        (1, 1): -0.5 * b, (-1, -1): -0.5 * b, (1, -1): 0.5 * b, (-1, 1): 0.5 * b,
    }
    jj, ii = np.meshgrid(np.arange(1, nj - 1), np.arange(1, ni - 1), indexing="ij")
    row = (jj - 1) * (ni - 2) + (ii - 1)
    rows, cols, vals = [], [], []
    rhs = np.zeros((row.size, 2))
    for (dj, di), w in weights.items():
        nj_, ni_ = jj + dj, ii + di
        inner = (nj_ > 0) & (nj_ < nj - 1) & (ni_ > 0) & (ni_ < ni - 1)
        rows.append(row[inner])
        cols.append(((nj_ - 1) * (ni - 2) + (ni_ - 1))[inner])
        vals.append(w[inner])
        edge = ~inner
        np.subtract.at(rhs, row[edge], w[edge][:, None] * g[nj_[edge], ni_[edge]])
    n = row.size
    mat = sp.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                        shape=(n, n))
    return mat, rhs


def winslow_solve(grid: np.ndarray, tol: float = 1e-12, max_iterations: int = 500,
                  initial: np.ndarray | None = None) -> tuple[np.ndarray, int]:
    """Converged Winslow grid by Picard iteration (coefficients frozen per step).

    Each step solves the frozen-coefficient system by defect correction with a sparse LU
    factorisation that is reused while it still halves the update, and refreshed otherwise:
    the factorisation dominates the cost on large grids. ``grid`` fixes the boundary nodes;
    the interior starts from ``initial`` (default: the interior of ``grid``, e.g. a TFI grid).
    Stops when no node moves more than ``tol`` times the grid's extent. Returns the grid and
    the number of iterations.
    """
    g = np.array(grid if initial is None else initial, dtype=float)
    g[0], g[-1], g[:, 0], g[:, -1] = grid[0], grid[-1], grid[:, 0], grid[:, -1]
    if min(g.shape[:2]) < 3:
        return g, 0
    extent = float(np.ptp(g.reshape(-1, 2), axis=0).max())
    lu, previous = None, np.inf
    for it in range(1, max_iterations + 1):
        mat, rhs = _stencil_matrix(g)
        inner = g[1:-1, 1:-1].reshape(-1, 2)
        defect = rhs - mat @ inner
        if lu is None:
            lu = splu(mat, permc_spec="MMD_AT_PLUS_A")
        step = lu.solve(defect)
        change = float(np.abs(step).max())
        if change > 0.5 * previous:  # the stale factorisation stopped paying: refresh it
            lu = splu(mat, permc_spec="MMD_AT_PLUS_A")
            step = lu.solve(defect)
            change = float(np.abs(step).max())
        previous = change
        g[1:-1, 1:-1] = (inner + step).reshape(g.shape[0] - 2, g.shape[1] - 2, 2)
        if change <= tol * extent:
            return g, it
    return g, max_iterations
