"""Structured grids of the six faces, on the input triangles (SPEC 11).

Each face is mapped to the unit square by Floater's mean-value coordinates (a harmonic-like
map that is one-to-one for a convex target), its sides on the square's sides by arc length;
a grid of the square (a tensor grid, or the nodes of a spacing's distribution) is carried
back by the barycentric coordinates of the mapped triangle that holds each node, so every
node lies on an input triangle.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

from pinn_engine.geometry.boundary import arc_lengths
from pinn_engine.hexa.surface import Surface

LOCATE_BATCH = 4_000_000  # query-triangle pairs per batch: bounds the memory of the search
DEGENERATE = 1e-300  # a mapped triangle with |det| below this holds no node


def arc_fractions(points: np.ndarray) -> np.ndarray:
    """Normalised cumulative arc length along a polyline (0 at its start, 1 at its end)."""
    s = arc_lengths(points)
    return s / s[-1]


def edge_nodes(points: np.ndarray, fractions: np.ndarray) -> np.ndarray:
    """Nodes at arc-length ``fractions`` (0 to 1) along a polyline (on its segments)."""
    t = arc_fractions(points)
    return np.stack([np.interp(fractions, t, points[:, d]) for d in range(3)], axis=1)


def _mean_value_weights(points: np.ndarray, tris: np.ndarray) -> sp.csr_matrix:
    """Floater's mean-value weights w_ij = (tan(a/2) + tan(b/2)) / |x_j - x_i|, the angles
    at x_i of the two triangles by the edge ij (one-to-one maps of a disk to a convex set)."""
    rows, cols, vals = [], [], []
    for r in range(3):
        i, j, k = tris[:, r], tris[:, (r + 1) % 3], tris[:, (r + 2) % 3]
        eij, eik = points[j] - points[i], points[k] - points[i]
        lij, lik = np.linalg.norm(eij, axis=1), np.linalg.norm(eik, axis=1)
        cos = np.clip(np.einsum("ij,ij->i", eij, eik) / (lij * lik), -1.0, 1.0)
        half = np.tan(0.5 * np.arccos(cos))
        rows += [i, i]
        cols += [j, k]
        vals += [half / lij, half / lik]
    n = len(points)
    return sp.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)
    )


def square_map(points: np.ndarray, tris: np.ndarray, fixed: dict[int, np.ndarray]) -> np.ndarray:
    """(u, v) of every point of a face: ``fixed`` boundary points keep theirs, the others
    are the mean-value average of their neighbours (one sparse solve)."""
    w = _mean_value_weights(points, tris)
    n = len(points)
    known = np.zeros(n, dtype=bool)
    uv = np.zeros((n, 2))
    for p, value in fixed.items():
        known[p], uv[p] = True, value
    free = np.flatnonzero(~known)
    lap = sp.diags(np.asarray(w.sum(axis=1)).ravel()) - w
    a = lap[free][:, free].tocsc()
    rhs = -lap[free][:, np.flatnonzero(known)] @ uv[known]
    uv[free] = spsolve(a, rhs).reshape(-1, 2)
    return uv


def carry_back(
    uv: np.ndarray, tris: np.ndarray, points: np.ndarray, queries: np.ndarray
) -> np.ndarray:
    """3D points of ``queries`` (m, 2) in the square, by the barycentric coordinates of the
    mapped triangle holding each (the one whose smallest coordinate is largest, clipped)."""
    p0 = uv[tris[:, 0]]
    e1, e2 = uv[tris[:, 1]] - p0, uv[tris[:, 2]] - p0
    det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    ok = np.abs(det) > DEGENERATE
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    out = np.empty((len(queries), 3))
    batch = max(1, LOCATE_BATCH // len(tris))
    for start in range(0, len(queries), batch):
        q = queries[start : start + batch, None, :] - p0[None]
        l1 = (q[..., 0] * e2[:, 1] - q[..., 1] * e2[:, 0]) * inv
        l2 = (e1[:, 0] * q[..., 1] - e1[:, 1] * q[..., 0]) * inv
        worst = np.where(ok, np.minimum(np.minimum(l1, l2), 1.0 - l1 - l2), -np.inf)
        best = worst.argmax(axis=1)
        rows = np.arange(len(best))
        lam = np.clip(
            np.stack([1 - l1[rows, best] - l2[rows, best], l1[rows, best], l2[rows, best]], axis=1),
            0.0,
            None,
        )
        lam /= lam.sum(axis=1, keepdims=True)
        out[start : start + batch] = np.einsum("qc,qcd->qd", lam, points[tris[best]])
    return out


class FaceMap:
    """One face's map to the unit square, built once and evaluated at node parameters.

    ``sides`` holds the input point paths of the face's four sides in grid order: ``a0``
    (b = 0, along a), ``a1`` (b = 1), ``b0`` (a = 0, along b), ``b1`` (a = 1).
    """

    def __init__(
        self, surface: Surface, triangles: np.ndarray, sides: dict[str, np.ndarray]
    ) -> None:
        tris_global = surface.triangles[triangles]
        used, local = np.unique(tris_global, return_inverse=True)
        self.tris = local.reshape(-1, 3)
        self.points = surface.points[used]
        self.sides = {name: surface.points[path] for name, path in sides.items()}
        index = {p: n for n, p in enumerate(used.tolist())}
        fixed: dict[int, np.ndarray] = {}
        for name, path in sides.items():
            t = arc_fractions(surface.points[path])
            const = 0.0 if name.endswith("0") else 1.0
            uv = np.stack([t, np.full_like(t, const)], axis=1)
            for p, value in zip(path, uv if name[0] == "a" else uv[:, ::-1], strict=True):
                fixed[index[p]] = value
        self.uv = square_map(self.points, self.tris, fixed)

    def grid(self, params: np.ndarray) -> np.ndarray:
        """Grid (na, nb, 3) of the face whose node (a, b) sits at ``params[a, b]`` (u, v) of
        the square; side nodes at those arc-length fractions of the sides."""
        na, nb = params.shape[:2]
        grid = np.empty((na, nb, 3))
        grid[:, 0] = edge_nodes(self.sides["a0"], params[:, 0, 0])
        grid[:, -1] = edge_nodes(self.sides["a1"], params[:, -1, 0])
        grid[0, :] = edge_nodes(self.sides["b0"], params[0, :, 1])
        grid[-1, :] = edge_nodes(self.sides["b1"], params[-1, :, 1])
        queries = params[1:-1, 1:-1].reshape(-1, 2)
        inner = carry_back(self.uv, self.tris, self.points, queries)
        grid[1:-1, 1:-1] = inner.reshape(na - 2, nb - 2, 3)
        return grid
