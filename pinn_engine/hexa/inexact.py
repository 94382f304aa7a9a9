"""The linear systems of the 3D Picard steps, solved inexactly: GMRES (pyamg's flexible one
for the single block, a lean right-preconditioned one for a dictionary's blocks)
preconditioned by an algebraic multigrid V-cycle (pyamg), the hierarchy reused over the
steps. A sparse LU of the 19-point 3D system fills in far more than in 2D (a minute
and 2.2 GiB at 41^3); the multigrid hierarchy grows like the nodes. A 2D system (a slab's
face) is preconditioned by its own sparse LU instead (:func:`direct`)."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import LinearOperator

# inexact Picard: each update solves its system to this fraction of its defect only, since
# the next step's coefficients change the system by about as much (measured on the bump box
# at 41^3: 0.3 keeps the 12 Picard steps of 0.1 with half the V-cycles; 0.5 took 16)
FORCING = 0.3
# the most (flexible, unrestarted) GMRES iterations per solve; one or two V-cycles meet
# FORCING, so this binds only where the preconditioner has gone stale
MAX_ITERATIONS = 30
# the preconditioner is rebuilt when a step needs more than this many times the iterations of the
# step right after the last build (the coefficients have moved too far from its own)
STALE = 2.0
# the coarsest level's size: solved by a sparse LU, which is cheaper there than more levels
# (each a Python-level pass of the V-cycle)
COARSEST = 500


# a sparse LU's pivot: the diagonal entry unless it is below this share of its column's
# largest (SuperLU's threshold pivoting; a Picard system's diagonal dominates its row): on
# backwardFacingStep2D's face half the fill and CPU of partial pivoting (1.0)
PIVOT = 0.1


# plain aggregation's smoothing: a forward Gauss-Seidel sweep before the coarse correction
# and a backward one after (half the sweeps of the symmetric default; as many V-cycles)
FORWARD = ("gauss_seidel", {"sweep": "forward"})
BACKWARD = ("gauss_seidel", {"sweep": "backward"})


def classical(mat: sp.csr_matrix) -> LinearOperator:
    """The V-cycle of Ruge-Stuben's hierarchy of ``mat``: strong V-cycles, a costly set-up."""
    import pyamg  # imported where a 3D system is solved (a box's TFI grid needs none)

    return v_cycle(pyamg.ruge_stuben_solver(mat, max_coarse=COARSEST, coarse_solver="splu"))


def plain_aggregation(mat: sp.csr_matrix) -> LinearOperator:
    """The V-cycle of the unsmoothed aggregation hierarchy of ``mat``: a set-up about ten
    times cheaper than :func:`classical`'s (no Galerkin product with a smoothed, denser
    interpolation) and cheaper V-cycles (operator complexity near 1), each cutting the
    defect less."""
    import pyamg

    hierarchy = pyamg.smoothed_aggregation_solver(
        mat,
        smooth=None,
        # the aggregates from the matrix itself: pyamg's symmetric strength at its theta of 0
        # keeps every entry, so the same hierarchy, without a pass over the matrix (over a
        # quarter of a set-up's time on DFG 3D)
        strength=None,
        max_coarse=COARSEST,
        coarse_solver="splu",
        presmoother=FORWARD,
        postsmoother=BACKWARD,
    )
    # pyamg leaves the coarse operators and the transfers as 1 x 1 block (BSR) matrices,
    # whose Gauss-Seidel sweeps and products cost far more an entry than CSR's
    for level in hierarchy.levels:
        level.A = level.A.tocsr()
        for transfer in ("P", "R"):
            if hasattr(level, transfer):
                setattr(level, transfer, getattr(level, transfer).tocsr())
    return v_cycle(hierarchy)


def direct(mat: sp.csr_matrix) -> LinearOperator:
    """The sparse LU of a 2D system ``mat`` (its fill grows like n log n; minimum degree on
    its symmetric pattern) as the preconditioner: one GMRES iteration while it is the
    step's own matrix, a few on the next steps' (backwardFacingStep2D's stretched cells
    took plain aggregation 11 to 30 iterations a solve)."""
    from scipy.sparse.linalg import splu

    lu = splu(
        mat.tocsc(),
        permc_spec="MMD_AT_PLUS_A",
        diag_pivot_thresh=PIVOT,
        options={"SymmetricMode": True},
    )
    return LinearOperator(mat.shape, lu.solve, dtype=mat.dtype)


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


def flexible(mat, rhs: np.ndarray, forcing: float, most: int, preconditioner):
    """pyamg's flexible GMRES: the update and its iterations (Householder reflections)."""
    from pyamg.krylov import fgmres

    residuals: list[float] = []
    x, _ = fgmres(mat, rhs, tol=forcing, maxiter=most, M=preconditioner, residuals=residuals)
    return x, len(residuals) - 1


def gmres(mat, rhs: np.ndarray, forcing: float, most: int, preconditioner):
    """GMRES preconditioned on the right (the defect measured is the system's own, as in
    :func:`flexible`), its basis by modified Gram-Schmidt, grown one vector an iteration:
    the update and its iterations. A fixed V-cycle needs no flexible method, and pyamg's
    allocates two bases of ``most`` vectors a solve and orthogonalises by Householder
    reflections: DFG 3D's Winslow solve (24 solves of 90 000 nodes) takes 3.55 s of CPU
    with it, 3.04 s with this one."""
    size = float(np.linalg.norm(rhs))
    if size == 0.0:
        return np.zeros_like(rhs), 0
    basis, steps = [rhs / size], []
    hessenberg = np.zeros((most + 1, most))
    for k in range(most):
        steps.append(preconditioner @ basis[k])
        w = mat @ steps[k]
        for i, v in enumerate(basis):
            hessenberg[i, k] = w @ v
            w -= hessenberg[i, k] * v
        hessenberg[k + 1, k] = np.linalg.norm(w)
        h = hessenberg[: k + 2, : k + 1]
        target = np.zeros(k + 2)
        target[0] = size
        y = np.linalg.lstsq(h, target, rcond=None)[0]
        if np.linalg.norm(h @ y - target) <= forcing * size or hessenberg[k + 1, k] == 0.0:
            break
        basis.append(w / hessenberg[k + 1, k])
    x = y[0] * steps[0]
    for weight, step in zip(y[1:], steps[1:]):
        x += weight * step
    return x, len(steps)


class InexactSolve:
    """Inexact solves of the Picard steps' systems with a reused preconditioner (``build``:
    how it is made of a matrix, :func:`classical`, :func:`plain_aggregation` or
    :func:`direct`), by the Krylov method ``krylov`` (:func:`flexible` or :func:`gmres`) to
    ``forcing`` of each defect."""

    def __init__(self, build=classical, forcing: float = FORCING, krylov=flexible) -> None:
        self.build, self.forcing, self.krylov = build, forcing, krylov
        self.preconditioner, self.baseline = None, None

    def solve(self, mat: sp.csr_matrix, rhs: np.ndarray) -> np.ndarray:
        """The update ``x`` (columns as ``rhs``) with ``|mat x - rhs| <= forcing |rhs|`` per
        column; ``mat`` has a positive diagonal, as the multigrid setup expects."""
        if self.preconditioner is None:
            self.preconditioner, self.baseline = self.build(mat), None
        out = np.zeros_like(rhs)
        iterations = 0
        most = min(MAX_ITERATIONS, mat.shape[0])  # pyamg warns above the unknowns
        for col in range(rhs.shape[1]):
            out[:, col], done = self.krylov(
                mat, rhs[:, col], self.forcing, most, self.preconditioner
            )
            iterations += done
        if self.baseline is None:
            self.baseline = iterations
        elif iterations > STALE * max(self.baseline, rhs.shape[1]):
            self.preconditioner = None
        return out
