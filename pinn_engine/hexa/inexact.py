"""The linear systems of the 3D Picard steps, solved inexactly: GMRES preconditioned by
algebraic multigrid (pyamg), one hierarchy for the three coordinates and reused over the
steps. A sparse LU of the 19-point 3D system fills in far more than in 2D (65 s and 2.7 GB
at 41^3); the multigrid hierarchy grows like the nodes."""

from __future__ import annotations

import numpy as np
import pyamg
import scipy.sparse as sp
from scipy.sparse.linalg import gmres

# inexact Picard: each update solves its system to this fraction of its defect only, since
# the next step's coefficients change the system by about as much (measured: 0.1 keeps the
# Picard steps of an exact solve, 12 on the bump box at 41^3)
FORCING = 0.1
# GMRES's restart length and the most restarts; the AMG-preconditioned solves take 2 to 5
# iterations, so neither binds unless the hierarchy has gone stale
RESTART, MAX_RESTARTS = 30, 10
# the hierarchy is rebuilt when a step needs more than this many times the GMRES iterations
# of the step right after the last build (the coefficients have moved too far from its own)
STALE = 2.0


class InexactSolve:
    """Inexact solves of the Picard steps' systems with a reused multigrid hierarchy."""

    def __init__(self) -> None:
        self.preconditioner, self.baseline = None, None

    def solve(self, mat: sp.csr_matrix, rhs: np.ndarray) -> np.ndarray:
        """The update ``x`` (columns as ``rhs``) with ``|mat x - rhs| <= FORCING |rhs|`` per
        column; ``mat`` has a positive diagonal, as the multigrid setup expects."""
        if self.preconditioner is None:
            self.preconditioner = pyamg.ruge_stuben_solver(mat).aspreconditioner()
            self.baseline = None
        out = np.zeros_like(rhs)
        count = [0]

        def tick(_residual: float) -> None:
            count[0] += 1

        for col in range(rhs.shape[1]):
            out[:, col], _ = gmres(
                mat,
                rhs[:, col],
                rtol=FORCING,
                restart=RESTART,
                maxiter=MAX_RESTARTS,
                M=self.preconditioner,
                callback=tick,
                callback_type="pr_norm",
            )
        if self.baseline is None:
            self.baseline = count[0]
        elif count[0] > STALE * max(self.baseline, rhs.shape[1]):
            self.preconditioner = None
        return out
