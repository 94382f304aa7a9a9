"""The linear systems of the 3D Picard steps, solved inexactly: flexible GMRES preconditioned
by an algebraic multigrid V-cycle (pyamg), one hierarchy for the three coordinates and reused
over the steps. A sparse LU of the 19-point 3D system fills in far more than in 2D (a minute
and 2.2 GiB at 41^3); the multigrid hierarchy grows like the nodes."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

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


class InexactSolve:
    """Inexact solves of the Picard steps' systems with a reused multigrid hierarchy."""

    def __init__(self) -> None:
        self.preconditioner, self.baseline = None, None

    def solve(self, mat: sp.csr_matrix, rhs: np.ndarray) -> np.ndarray:
        """The update ``x`` (columns as ``rhs``) with ``|mat x - rhs| <= FORCING |rhs|`` per
        column; ``mat`` has a positive diagonal, as the multigrid setup expects."""
        import pyamg  # imported where a system is solved (a box's TFI grid needs none)
        from pyamg.krylov import fgmres

        if self.preconditioner is None:
            hierarchy = pyamg.ruge_stuben_solver(mat, max_coarse=COARSEST, coarse_solver="splu")
            self.preconditioner, self.baseline = hierarchy.aspreconditioner(), None
        out = np.zeros_like(rhs)
        iterations = 0
        for col in range(rhs.shape[1]):
            residuals: list[float] = []
            out[:, col], _ = fgmres(
                mat,
                rhs[:, col],
                tol=FORCING,
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
