"""Volume grids (ni, nj, nk, 3) from their six boundary faces: 3D transfinite interpolation
and the 3D Winslow equations, solved by Picard steps with frozen coefficients (as the 2D ones)
whose linear systems are solved inexactly by an AMG-preconditioned Krylov method."""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from pinn_engine.blas import one_thread
from pinn_engine.hexa.controls import parameter_controls
from pinn_engine.hexa.inexact import InexactSolve


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
    return cofactor_terms(
        [[np.einsum("...k,...k->...", d[a], d[b]) for b in range(3)] for a in range(3)]
    )


def cofactor_terms(m) -> dict[tuple[int, int], np.ndarray]:
    """Cofactors of the metric tensor m (3 x 3 of arrays or numbers), by (a, b), a <= b."""
    return {
        (0, 0): m[1][1] * m[2][2] - m[1][2] ** 2,
        (1, 1): m[0][0] * m[2][2] - m[0][2] ** 2,
        (2, 2): m[0][0] * m[1][1] - m[0][1] ** 2,
        (0, 1): m[0][2] * m[1][2] - m[0][1] * m[2][2],
        (0, 2): m[0][1] * m[1][2] - m[0][2] * m[1][1],
        (1, 2): m[0][1] * m[0][2] - m[0][0] * m[1][2],
    }


# a residual within this many machine epsilons of the sum of its terms' sizes is round-off
ROUND_OFF = 64
# the 19 offsets of the stencil (none along all three axes at once), lexicographic
_OFFSETS = [o for o in itertools.product((-1, 0, 1), repeat=3) if np.count_nonzero(o) < 3]


def _stencil(
    c: dict[tuple[int, int], np.ndarray], controls: list[np.ndarray] | None = None
) -> dict[tuple[int, int, int], np.ndarray]:
    """19-point weights of the frozen-coefficient Winslow operator, by offset: the diagonal
    terms C_mm along one axis, the mixed ones 0.5 s_m s_n C_mn along two; with ``controls``
    (P_m at interior nodes) the terms ``sum_m P_m x_{xi_m}`` are added."""
    weights = {}
    for off in _OFFSETS:
        axes = [a for a in range(3) if off[a]]
        if not axes:
            weights[off] = -2.0 * (c[(0, 0)] + c[(1, 1)] + c[(2, 2)])
        elif len(axes) == 1:
            m = axes[0]
            weights[off] = c[(m, m)] + (0.0 if controls is None else 0.5 * off[m] * controls[m])
        else:
            m, n = axes
            weights[off] = 0.5 * off[m] * off[n] * c[(m, n)]
    return weights


def _apply(weights: dict[tuple[int, int, int], np.ndarray], g: np.ndarray) -> np.ndarray:
    """The 19-point operator of ``weights`` applied to ``g`` at the interior nodes, shape
    ((ni-2) (nj-2) (nk-2), 3)."""
    shape = g.shape[:3]
    out = np.zeros((*(n - 2 for n in shape), 3))
    for off, w in weights.items():
        out += w[..., None] * g[tuple(slice(1 + o, n - 1 + o) for o, n in zip(off, shape))]
    return out.reshape(-1, 3)


def _weights(g: np.ndarray, params: np.ndarray | None) -> dict[tuple[int, int, int], np.ndarray]:
    """The stencil frozen at ``g``, with the control terms of node ``params`` (ni, nj, nk, 3)
    whose distribution the grid keeps (:func:`controls.parameter_controls`) when given."""
    c = _cofactors(g)
    return _stencil(c, None if params is None else parameter_controls(c, params))


def winslow_residual(g: np.ndarray, params: np.ndarray | None = None) -> np.ndarray:
    """The Winslow operator with coefficients frozen at ``g`` (and ``params``' control
    terms) applied to ``g``, at the interior nodes, shape ((ni-2) (nj-2) (nk-2), 3): zero on
    a Winslow grid."""
    return _apply(_weights(g, params), g)


@dataclass
class InteriorStencil:
    """The CSR pattern of the operator over the interior nodes, built once per shape: which of
    the 19 neighbours of each node are interior. Taken in ``_OFFSETS``' (lexicographic) order,
    a row's neighbours are in column order, so no sort is needed."""

    inner: np.ndarray  # (interior nodes, 19) bool
    indices: np.ndarray
    indptr: np.ndarray

    @classmethod
    def of(cls, shape: tuple[int, int, int]) -> InteriorStencil:
        strides = np.array([shape[1] * shape[2], shape[2], 1])
        idx = np.indices(shape).reshape(3, -1).T
        inner = np.stack(
            [((idx + off >= 0) & (idx + off < shape)).all(axis=1) for off in _OFFSETS], axis=1
        )
        cols = np.arange(idx.shape[0])[:, None] + (np.array(_OFFSETS) @ strides)[None, :]
        indptr = np.concatenate([[0], np.cumsum(inner.sum(axis=1))])
        return cls(inner, cols[inner].astype(np.int32), indptr.astype(np.int32))

    def system(
        self, g: np.ndarray, params: np.ndarray | None = None
    ) -> tuple[sp.csr_matrix, np.ndarray]:
        """Minus the operator with coefficients frozen at ``g`` (and ``params``' control
        terms) over the interior nodes (its diagonal is positive, as algebraic multigrid
        expects) and the Winslow residual of ``g``: the Picard update solves ``matrix @
        update = residual``."""
        w = _weights(g, params)
        return self.matrix(w), _apply(w, g)

    def matrix(self, w: dict[tuple[int, int, int], np.ndarray]) -> sp.csr_matrix:
        """Minus the operator of the stencil weights ``w`` over the interior nodes."""
        data = -np.stack([w[off].reshape(-1) for off in _OFFSETS], axis=1)[self.inner]
        n = self.indptr.size - 1
        return sp.csr_matrix((data, self.indices, self.indptr), shape=(n, n))


def round_off(
    w: dict[tuple[int, int, int], np.ndarray], g: np.ndarray, residual: np.ndarray
) -> bool:
    """Whether the ``residual`` of ``g`` under the weights ``w`` is round-off of its terms
    (a box's TFI grid, for one): no Picard step can improve it."""
    size = _apply({off: np.abs(v) for off, v in w.items()}, np.abs(g))
    return bool((np.abs(residual) <= ROUND_OFF * np.finfo(float).eps * size).all())


def winslow(
    start: np.ndarray,
    tol: float = 1e-9,
    max_iterations: int = 200,
    params: np.ndarray | None = None,
) -> tuple[np.ndarray, int]:
    """3D Winslow grid by Picard iteration from ``start`` (its faces are kept): each step
    solves the frozen-coefficient system for the update inexactly (:class:`InexactSolve`), on
    one BLAS thread (GMRES's vector operations gain nothing from OpenBLAS's spinning threads:
    at 41^3 they nearly doubled the CPU time for no wall time). ``params``: node parameters
    whose distribution the grid keeps (control terms). Stops when no node moves more than
    ``tol`` times the grid's extent, or before the first step where the start's residual is
    round-off (:func:`round_off`); returns the grid and the number of steps."""
    g = np.array(start, dtype=float)
    if min(g.shape[:3]) < 3:
        return g, 0
    extent = float(np.ptp(g.reshape(-1, 3), axis=0).max())
    inner_shape = tuple(n - 2 for n in g.shape[:3])
    pattern = InteriorStencil.of(inner_shape)
    solver = InexactSolve()
    with one_thread():
        for it in range(1, max_iterations + 1):
            w = _weights(g, params)
            residual = _apply(w, g)
            if it == 1 and round_off(w, g, residual):
                return g, 0
            step = solver.solve(pattern.matrix(w), residual)
            g[1:-1, 1:-1, 1:-1] += step.reshape(*inner_shape, 3)
            if float(np.abs(step).max()) <= tol * extent:
                return g, it
    return g, max_iterations
