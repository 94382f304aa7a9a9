"""The elliptic (Winslow) grid generator, the paper's "PDE method" (paper eq. 7 and 8).

Both solvers take a grid (nj, ni, 2) whose boundary nodes are fixed and return a new grid
whose interior satisfies the discrete Winslow equations in index space (the equations are
invariant to the spacing of xi and eta, so index space is exact, not an approximation).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from pinn_engine.quality import folded_cells

if TYPE_CHECKING:  # SciPy's sparse solver is imported where it solves: the body grids use
    import scipy.sparse as sp  # this module's Winslow coefficients alone


def winslow_coefficients(
    x_xi: np.ndarray, x_eta: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """alpha, beta, gamma of paper eq. 8 from the first derivatives (..., 2): the one
    definition of every 2D Winslow solver (this module's, the body grids', multi-block's)."""
    alpha = np.einsum("...k,...k->...", x_eta, x_eta)
    beta = np.einsum("...k,...k->...", x_xi, x_eta)
    gamma = np.einsum("...k,...k->...", x_xi, x_xi)
    return alpha, beta, gamma


def winslow_operator(
    x_xi: np.ndarray,
    x_eta: np.ndarray,
    x_xixi: np.ndarray,
    x_etaeta: np.ndarray,
    x_xieta: np.ndarray,
) -> np.ndarray:
    """alpha x_xixi - 2 beta x_xieta + gamma x_etaeta (paper eq. 7) from the derivatives
    (..., 2), however they were differenced (plain here, periodic in xi for O-grids)."""
    a, b, c = (v[..., None] for v in winslow_coefficients(x_xi, x_eta))
    return a * x_xixi - 2 * b * x_xieta + c * x_etaeta


def _first(g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """x_xi and x_eta at interior nodes, central differences."""
    return 0.5 * (g[1:-1, 2:] - g[1:-1, :-2]), 0.5 * (g[2:, 1:-1] - g[:-2, 1:-1])


def _coefficients(g: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """alpha, beta, gamma at interior nodes, central differences."""
    return winslow_coefficients(*_first(g))


def winslow_residual(g: np.ndarray) -> np.ndarray:
    """Discrete Winslow residual (paper eq. 7) at interior nodes, shape (nj-2, ni-2, 2)."""
    g_xixi = g[1:-1, 2:] - 2 * g[1:-1, 1:-1] + g[1:-1, :-2]
    g_etaeta = g[2:, 1:-1] - 2 * g[1:-1, 1:-1] + g[:-2, 1:-1]
    g_xieta = 0.25 * (g[2:, 2:] - g[:-2, 2:] - g[2:, :-2] + g[:-2, :-2])
    return winslow_operator(*_first(g), g_xixi, g_etaeta, g_xieta)


def winslow_sweeps(
    grid: np.ndarray, iterations: int = 1000, zero_interior: bool = True
) -> np.ndarray:
    """The paper's PDE run: point-Jacobi sweeps from an interior initialised to 0."""
    g = np.array(grid, dtype=float)
    if zero_interior:
        g[1:-1, 1:-1] = 0.0
    for _ in range(iterations):
        a, b, c = (v[..., None] for v in _coefficients(g))
        cross = 0.25 * (g[2:, 2:] - g[:-2, 2:] - g[2:, :-2] + g[:-2, :-2])
        num = a * (g[1:-1, 2:] + g[1:-1, :-2]) + c * (g[2:, 1:-1] + g[:-2, 1:-1]) - 2 * b * cross
        den = 2 * (a + c)
        ok = den > 0  # nodes whose neighbours are all still 0 wait for the front to arrive
        g[1:-1, 1:-1] = np.where(ok, num / np.where(ok, den, 1.0), g[1:-1, 1:-1])
    return g


def stencil_matrix(
    g: np.ndarray, cp: np.ndarray | None = None, cq: np.ndarray | None = None
) -> tuple[sp.csc_matrix, np.ndarray]:
    """Linear system of the Winslow equations with alpha, beta, gamma frozen at ``g``; with
    ``cp``, ``cq`` (interior nodes) the control terms ``cp x_xi + cq x_eta`` are added."""
    import scipy.sparse as sp

    nj, ni = g.shape[:2]
    a, b, c = _coefficients(g)
    # 9-point stencil weights, offsets (dj, di)
    weights = {
        (0, 0): -2 * (a + c),
        (0, 1): a,
        (0, -1): a,
        (1, 0): c,
        (-1, 0): c,
        (1, 1): -0.5 * b,
        (-1, -1): -0.5 * b,
        (1, -1): 0.5 * b,
        (-1, 1): 0.5 * b,
    }
    if cp is not None:
        weights[(0, 1)], weights[(0, -1)] = a + 0.5 * cp, a - 0.5 * cp
        weights[(1, 0)], weights[(-1, 0)] = c + 0.5 * cq, c - 0.5 * cq
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
    mat = sp.csc_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)
    )
    return mat, rhs


class ReusedLU:
    """Defect correction with a sparse LU factorisation that is reused while it still halves
    the update and refreshed otherwise (the factorisation dominates the cost on large grids)."""

    def __init__(self) -> None:
        self.lu, self.previous = None, np.inf

    def solve(self, mat, defect: np.ndarray) -> tuple[np.ndarray, float]:
        """The update for ``defect`` and its largest component."""
        from scipy.sparse.linalg import splu

        if self.lu is None:
            self.lu = splu(mat, permc_spec="MMD_AT_PLUS_A")
        step = self.lu.solve(defect)
        change = float(np.abs(step).max())
        if change > 0.5 * self.previous:  # the stale factorisation stopped paying: refresh it
            self.lu = splu(mat, permc_spec="MMD_AT_PLUS_A")
            step = self.lu.solve(defect)
            change = float(np.abs(step).max())
        self.previous = change
        return step, change


def winslow_solve(
    grid: np.ndarray,
    tol: float = 1e-12,
    max_iterations: int = 500,
    initial: np.ndarray | None = None,
) -> tuple[np.ndarray, int]:
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
    solver = ReusedLU()
    for it in range(1, max_iterations + 1):
        mat, rhs = stencil_matrix(g)
        inner = g[1:-1, 1:-1].reshape(-1, 2)
        step, change = solver.solve(mat, rhs - mat @ inner)
        g[1:-1, 1:-1] = (inner + step).reshape(g.shape[0] - 2, g.shape[1] - 2, 2)
        if change <= tol * extent:
            return g, it
    return g, max_iterations


def parameter_controls(g: np.ndarray, params: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Control terms that keep a node distribution (Spekreijse 1995, "Elliptic grid
    generation based on Laplace equations and algebraic transformations", J. Comput. Phys.
    118): the grid is x(s, t) with s, t harmonic in x, the nodes at parameters
    ``params`` (nj, ni, 2) = (s, t). With alpha, beta, gamma of ``g``, the Winslow equations in
    index space gain ``cp x_xi + cq x_eta`` with (cp, cq) = -T^-1 (L s, L t), T the Jacobian
    of (s, t) in index space and L = alpha d_xixi - 2 beta d_xieta + gamma d_etaeta."""
    a, b, c = _coefficients(g)
    out = []
    for k in (0, 1):
        p = params[..., k]
        d_xi = 0.5 * (p[1:-1, 2:] - p[1:-1, :-2])
        d_eta = 0.5 * (p[2:, 1:-1] - p[:-2, 1:-1])
        d_xixi = p[1:-1, 2:] - 2 * p[1:-1, 1:-1] + p[1:-1, :-2]
        d_etaeta = p[2:, 1:-1] - 2 * p[1:-1, 1:-1] + p[:-2, 1:-1]
        d_xieta = 0.25 * (p[2:, 2:] - p[:-2, 2:] - p[2:, :-2] + p[:-2, :-2])
        out.append((d_xi, d_eta, a * d_xixi - 2 * b * d_xieta + c * d_etaeta))
    (s_xi, s_eta, ls), (t_xi, t_eta, lt) = out
    det = s_xi * t_eta - s_eta * t_xi
    det = np.where(np.abs(det) > 1e-300, det, 1e-300)
    cp = -(t_eta * ls - s_eta * lt) / det
    cq = -(-t_xi * ls + s_xi * lt) / det
    return cp, cq


def wall_cosines(g: np.ndarray) -> dict[str, np.ndarray]:
    """Cosine of the angle between each side's tangent and the first grid edge leaving it,
    at the side's nodes 1..n-2 (the sign says towards which end the grid line leans)."""

    def cos(side, inner):
        tangent = side[2:] - side[:-2]
        leave = inner[1:-1] - side[1:-1]
        return np.einsum("ij,ij->i", tangent, leave) / np.maximum(
            np.linalg.norm(tangent, axis=1) * np.linalg.norm(leave, axis=1), 1e-300
        )

    return {
        "bottom": cos(g[0], g[1]),
        "top": cos(g[-1], g[-2]),
        "left": cos(g[:, 0], g[:, 1]),
        "right": cos(g[:, -1], g[:, -2]),
    }


# Hilgenstock's orthogonality control: relaxation of the wall control per iteration and its
# decay per index away from the wall (measured on the bump channel and the V notch).
HILGENSTOCK_RELAX = 0.5
HILGENSTOCK_DECAY = 0.3


def controlled_solve(
    grid: np.ndarray,
    params: np.ndarray | None = None,
    orthogonal: tuple[str, ...] = (),
    tol: float = 1e-9,
    max_iterations: int = 2000,
    initial: np.ndarray | None = None,
    angle_tol: float = 0.5,
    control: dict | None = None,
) -> tuple[np.ndarray, int]:
    """Elliptic grid with control functions: Winslow in the parameter space of ``params``
    (the node distribution is kept, :func:`parameter_controls`), and with orthogonality at
    the ``orthogonal`` sides by Hilgenstock's control (Hilgenstock 1988, "A fast method for
    the elliptic generation of three-dimensional grids with full boundary control"): each
    Picard iteration moves a wall's control function by the cosine of the angle at each of
    its nodes, and the control decays exponentially into the interior. Boundary nodes are
    those of ``grid``; iterates until nodes move less than ``tol`` of the extent and every
    wall angle is within ``angle_tol`` degrees of 90 (the two nodes at each corner aside).
    ``control``: a dict that keeps the wall controls between calls (a start for the next).
    """
    g = np.array(grid if initial is None else initial, dtype=float)
    g[0], g[-1], g[:, 0], g[:, -1] = grid[0], grid[-1], grid[:, 0], grid[:, -1]
    nj, ni = g.shape[:2]
    if min(nj, ni) < 3:
        return g, 0
    extent = float(np.ptp(g.reshape(-1, 2), axis=0).max())
    jj, ii = np.arange(1, nj - 1)[:, None], np.arange(1, ni - 1)[None, :]
    decay = {
        "bottom": np.exp(-HILGENSTOCK_DECAY * (jj - 1)),
        "top": np.exp(-HILGENSTOCK_DECAY * (nj - 2 - jj)),
        "left": np.exp(-HILGENSTOCK_DECAY * (ii - 1)),
        "right": np.exp(-HILGENSTOCK_DECAY * (ni - 2 - ii)),
    }
    control = {} if control is None else control
    for s in orthogonal:
        size = ni - 2 if s in ("bottom", "top") else nj - 2
        if control.get(s) is None or len(control[s]) != size:
            control[s] = np.zeros(size)
    limit = np.cos(np.radians(90.0 - angle_tol))
    solver = ReusedLU()
    for it in range(1, max_iterations + 1):
        a, _, c = _coefficients(g)
        if params is not None:
            cp, cq = parameter_controls(g, params)
        else:
            cp, cq = np.zeros_like(a), np.zeros_like(a)
        worst = 0.0
        if orthogonal:
            cosines = wall_cosines(g)
            for side in orthogonal:
                k = cosines[side]
                worst = max(worst, float(np.abs(k[1:-1]).max(initial=0.0)))
                control[side] -= HILGENSTOCK_RELAX * k
                if side in ("bottom", "top"):
                    cp = cp + a * control[side][None, :] * decay[side]
                else:
                    cq = cq + c * control[side][:, None] * decay[side]
        mat, rhs = stencil_matrix(g, cp, cq)
        inner = g[1:-1, 1:-1].reshape(-1, 2)
        step, change = solver.solve(mat, rhs - mat @ inner)
        g[1:-1, 1:-1] = (inner + step).reshape(nj - 2, ni - 2, 2)
        if change <= tol * extent and worst <= limit:
            return g, it
    return g, max_iterations


def safe_controlled_solve(
    grid: np.ndarray,
    params: np.ndarray | None,
    orthogonal: tuple[str, ...],
    max_iterations: int = 800,
    **kwargs,
) -> tuple[np.ndarray, int, bool]:
    """:func:`controlled_solve`, but where the orthogonality control does not converge or
    folds a cell, the solve without it (``orthogonal`` cannot always be had: at a sharp
    corner of a narrow notch the controls of facing walls fight). Returns (grid, iterations,
    whether the orthogonality control was kept)."""
    g, it = controlled_solve(grid, params, orthogonal, max_iterations=max_iterations, **kwargs)
    bad = it >= max_iterations or not np.isfinite(g).all() or folded_cells(g).any()
    if orthogonal and bad:
        plain, it2 = controlled_solve(grid, params, (), max_iterations=max_iterations)
        if np.isfinite(plain).all() and (
            not np.isfinite(g).all()
            or folded_cells(plain).sum() < folded_cells(g).sum()
            or it >= max_iterations
        ):
            return plain, it2, False
    return g, it, bool(orthogonal)
