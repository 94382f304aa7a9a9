"""The linear systems of the 3D Picard steps, solved inexactly: flexible GMRES preconditioned
by an algebraic multigrid V-cycle (pyamg), one hierarchy for the three coordinates and reused
over the steps. A sparse LU of the 19-point 3D system fills in far more than in 2D (a minute
and 2.2 GiB at 41^3); the multigrid hierarchy grows like the nodes."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import LinearOperator

# inexact Picard: each update solves its system to this fraction of its defect only, since
# the next step's coefficients change the system by about as much (measured on the bump box
# at 41^3: 0.3 keeps the 12 Picard steps of 0.1 with half the V-cycles; 0.5 took 16)
FORCING = 0.3
# the most (flexible, unrestarted) GMRES iterations per solve; one or two V-cycles meet
# FORCING, so this binds only where the hierarchy has gone stale
MAX_ITERATIONS = 30
# the hierarchy is rebuilt when a step needs more than this many times the iterations of the
# step right after the last build (the coefficients have moved too far from its own)
STALE = 2.0
# the coarsest level's size: solved by a sparse LU, which is cheaper there than more levels
# (each a Python-level pass of the V-cycle)
COARSEST = 500


# plain aggregation's smoothing: a forward Gauss-Seidel sweep before the coarse correction
# and a backward one after (half the sweeps of the symmetric default; as many V-cycles)
FORWARD = ("gauss_seidel", {"sweep": "forward"})
BACKWARD = ("gauss_seidel", {"sweep": "backward"})


def classical(mat: sp.csr_matrix):
    """Ruge-Stuben's hierarchy of ``mat``: strong V-cycles, a costly set-up."""
    import pyamg  # imported where a system is solved (a box's TFI grid needs none)

    return pyamg.ruge_stuben_solver(mat, max_coarse=COARSEST, coarse_solver="splu")


def plain_aggregation(mat: sp.csr_matrix):
    """The unsmoothed aggregation hierarchy of ``mat``: a set-up about ten times cheaper
    than :func:`classical`'s (no Galerkin product with a smoothed, denser interpolation) and
    cheaper V-cycles (operator complexity near 1), each cutting the defect less."""
    import pyamg

    return pyamg.smoothed_aggregation_solver(
        mat,
        smooth=None,
        max_coarse=COARSEST,
        coarse_solver="splu",
        presmoother=FORWARD,
        postsmoother=BACKWARD,
    )


def v_cycle(hierarchy) -> LinearOperator:
    """One V-cycle of a pyamg ``hierarchy`` from a zero start, as a preconditioner: the
    cycle of pyamg's ``aspreconditioner``, without the residual norms that its ``solve``
    computes before and after the cycle (two products with the matrix a cycle, which no
    preconditioner reads: a third of a plain-aggregation V-cycle's time)."""
    levels = hierarchy.levels

    def cycle(lvl: int, b: np.ndarray) -> np.ndarray:
        mat = levels[lvl].A
        if lvl == len(levels) - 1:  # a single level: the coarse solve alone
            return hierarchy.coarse_solver(mat, b)
        x = np.zeros_like(b)
        levels[lvl].presmoother(mat, x, b)
        coarse_b = levels[lvl].R @ (b - mat @ x)
        coarse_x = np.zeros_like(coarse_b)
        if lvl == len(levels) - 2:
            coarse_x[:] = hierarchy.coarse_solver(levels[-1].A, coarse_b)
        else:
            coarse_x[:] = cycle(lvl + 1, coarse_b)
        x += levels[lvl].P @ coarse_x
        levels[lvl].postsmoother(mat, x, b)
        return x

    mat = levels[0].A
    return LinearOperator(mat.shape, lambda b: cycle(0, np.ravel(b)), dtype=mat.dtype)


class InexactSolve:
    """Inexact solves of the Picard steps' systems with a reused multigrid hierarchy
    (``hierarchy``: how it is built) to ``forcing`` of each defect."""

    def __init__(self, hierarchy=classical, forcing: float = FORCING) -> None:
        self.hierarchy, self.forcing = hierarchy, forcing
        self.preconditioner, self.baseline = None, None

    def solve(self, mat: sp.csr_matrix, rhs: np.ndarray) -> np.ndarray:
        """The update ``x`` (columns as ``rhs``) with ``|mat x - rhs| <= forcing |rhs|`` per
        column; ``mat`` has a positive diagonal, as the multigrid setup expects."""
        from pyamg.krylov import fgmres

        if self.preconditioner is None:
            self.preconditioner, self.baseline = v_cycle(self.hierarchy(mat)), None
        out = np.zeros_like(rhs)
        iterations = 0
        for col in range(rhs.shape[1]):
            residuals: list[float] = []
            out[:, col], _ = fgmres(
                mat,
                rhs[:, col],
                tol=self.forcing,
                maxiter=min(MAX_ITERATIONS, mat.shape[0]),  # pyamg warns above the unknowns
                M=self.preconditioner,
                residuals=residuals,
            )
            iterations += len(residuals) - 1
        if self.baseline is None:
            self.baseline = iterations
        elif iterations > STALE * max(self.baseline, rhs.shape[1]):
            self.preconditioner = None
        return out
