"""The Winslow equations (the paper's eq. 7) on a member's grid, linearised and solved.

With alpha, beta, gamma frozen at a grid, Winslow's equations are linear in the interior
nodes. A four-sided family freezes them once, at the members' mean grid, and factorises
that system once (:class:`FrozenWinslow`); a step from a member's grid solves it for the
correction that cancels the member's own Winslow residual there (a chord step of Newton's
method). From the mean grid's interior on the member's boundary nodes one step gives the
family's linearised elliptic grid, a linear map of the boundary nodes; from the network's
grid the steps contract towards the member's own Winslow grid."""

from __future__ import annotations

import numpy as np

from pinn_engine.classical.elliptic import stencil_matrix, winslow_residual

# A family's grids solve the Winslow equations where one step from each moves no node by
# more than this share of its extent (the elliptic solver stops at 1e-12; a quality-optimised
# or trained grid moves by 1e-4 or more)
WINSLOW_TOL = 1e-8


class FrozenWinslow:
    """The Winslow system with its coefficients frozen at ``reference`` (nj, ni, 2), its
    sparse LU factorised once."""

    def __init__(self, reference: np.ndarray) -> None:
        from scipy.sparse.linalg import splu

        mat, _ = stencil_matrix(np.asarray(reference, dtype=float))
        self.lu = splu(mat, permc_spec="MMD_AT_PLUS_A")

    def advance(self, grid: np.ndarray) -> np.ndarray:
        """One chord step from ``grid`` (its boundary nodes kept)."""
        residual = winslow_residual(grid).reshape(-1, 2)
        out = np.array(grid, dtype=float)
        out[1:-1, 1:-1] -= self.lu.solve(residual).reshape(out[1:-1, 1:-1].shape)
        return out

    def step(self, grid: np.ndarray) -> tuple[np.ndarray, float]:
        """:meth:`advance` and its largest node move in units of the shortest grid edge at
        that node: the defect of a family of Winslow grids."""
        out = self.advance(grid)
        move = np.linalg.norm(out - grid, axis=-1)
        return out, float((move / shortest_edges(grid)).max())


def shortest_edges(grid: np.ndarray) -> np.ndarray:
    """The shortest grid edge at each node (nj, ni)."""
    edges = np.full(grid.shape[:2], np.inf)
    for axis in (0, 1):
        length = np.linalg.norm(np.diff(grid, axis=axis), axis=-1)
        before = [slice(None), slice(None)]
        after = [slice(None), slice(None)]
        before[axis], after[axis] = slice(None, -1), slice(1, None)
        edges[tuple(before)] = np.minimum(edges[tuple(before)], length)
        edges[tuple(after)] = np.minimum(edges[tuple(after)], length)
    return np.maximum(edges, 1e-300)


def solves_winslow(grids: list[np.ndarray]) -> bool:
    """Whether every grid of ``grids`` solves the Winslow equations (to ``WINSLOW_TOL``):
    a step with the system frozen at the grid itself leaves it where it is."""
    for grid in grids:
        extent = float(np.ptp(grid.reshape(-1, 2), axis=0).max())
        step = FrozenWinslow(grid).advance(grid)
        if np.abs(step - grid).max() > WINSLOW_TOL * extent:
            return False
    return True
