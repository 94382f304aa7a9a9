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
from scipy.spatial import cKDTree

from pinn_engine.geometry.boundary import arc_lengths
from pinn_engine.hexa.surface import Surface

LOCATE_BATCH = 4_000_000  # query-triangle pairs per batch: bounds the memory of the search
DEGENERATE = 1e-300  # a mapped triangle with |det| below this holds no node
# The triangles searched for a point's closest point on the face: those of the nearest
# centroids (a face's triangles are of like size, so the closest lies among a few)
NEAREST_TRIANGLES = 8


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


def _bucketed(uv: np.ndarray, tris: np.ndarray, queries: np.ndarray) -> np.ndarray:
    """For each query (m, 2), the mapped triangles whose bounding box holds it (m, k), -1
    padded, ascending: a triangle that holds a query is among them. Boxes are filed in a
    square grid of about one cell a triangle over the queries' and triangles' extent."""
    corners = uv[tris]
    lo = np.minimum(corners.min(axis=1).min(axis=0), queries.min(axis=0))
    span = np.maximum(np.maximum(corners.max(axis=1).max(axis=0), queries.max(axis=0)) - lo, 1e-300)
    side = max(1, int(np.sqrt(len(tris))))

    def cell(x: np.ndarray) -> np.ndarray:
        return np.clip(((x - lo) / span * side).astype(int), 0, side - 1)

    first, last = cell(corners.min(axis=1)), cell(corners.max(axis=1))
    wide = last - first + 1
    counts = wide[:, 0] * wide[:, 1]
    tri = np.repeat(np.arange(len(tris)), counts)
    k = np.arange(len(tri)) - np.repeat(np.cumsum(counts) - counts, counts)
    x = first[tri, 0] + k % wide[tri, 0]
    y = first[tri, 1] + k // wide[tri, 0]
    order = np.argsort(y * side + x, kind="stable")  # by cell, triangles ascending within
    filed, tri = (y * side + x)[order], tri[order]
    starts = np.searchsorted(filed, np.arange(side * side + 1))
    at = cell(queries)
    q = at[:, 1] * side + at[:, 0]
    held = starts[q + 1] - starts[q]
    slot = starts[q][:, None] + np.arange(held.max(initial=0))[None, :]
    return np.where(slot < starts[q + 1][:, None], tri[np.minimum(slot, len(tri) - 1)], -1)


def carry_back(
    uv: np.ndarray, tris: np.ndarray, points: np.ndarray, queries: np.ndarray
) -> np.ndarray:
    """3D points of ``queries`` (m, 2) in the square, by the barycentric coordinates of the
    mapped triangle holding each (the one whose smallest coordinate is largest, clipped):
    searched among the triangles whose bounding box holds the query (:func:`_bucketed`),
    among all where none holds it (a query off the mapped square by round-off)."""
    p0 = uv[tris[:, 0]]
    e1, e2 = uv[tris[:, 1]] - p0, uv[tris[:, 2]] - p0
    det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    ok = np.abs(det) > DEGENERATE
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)

    def locate(q: np.ndarray, cand: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The best of the candidate triangles ``cand`` (m, k; -1 none) of queries ``q``:
        its index, its smallest barycentric coordinate and the coordinates l1, l2."""
        t = np.maximum(cand, 0)
        d = q[:, None, :] - p0[t]
        l1 = (d[..., 0] * e2[t, 1] - d[..., 1] * e2[t, 0]) * inv[t]
        l2 = (e1[t, 0] * d[..., 1] - e1[t, 1] * d[..., 0]) * inv[t]
        worst = np.where(
            ok[t] & (cand >= 0), np.minimum(np.minimum(l1, l2), 1.0 - l1 - l2), -np.inf
        )
        best = worst.argmax(axis=1)
        rows = np.arange(len(q))
        return t[rows, best], worst[rows, best], np.stack([l1[rows, best], l2[rows, best]], 1)

    found, worst, lam = locate(queries, _bucketed(uv, tris, queries))
    lost = np.flatnonzero(worst < 0.0)  # held by no candidate: the best of all triangles
    batch = max(1, LOCATE_BATCH // len(tris))
    for start in range(0, len(lost), batch):
        rows = lost[start : start + batch]
        every = np.broadcast_to(np.arange(len(tris)), (len(rows), len(tris)))
        found[rows], _, lam[rows] = locate(queries[rows], every)
    bary = np.clip(np.column_stack([1 - lam[:, 0] - lam[:, 1], lam]), 0.0, None)
    bary /= bary.sum(axis=1, keepdims=True)
    return np.einsum("qc,qcd->qd", bary, points[tris[found]])


def _closest_on_segments(q: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The closest points to ``q`` on the segments ``a``-``b`` (broadcast, ... x 3)."""
    ab = b - a
    t = np.einsum("...d,...d->...", q - a, ab) / np.maximum(
        np.einsum("...d,...d->...", ab, ab), DEGENERATE
    )
    return a + np.clip(t, 0.0, 1.0)[..., None] * ab


def closest_points(points: np.ndarray, tris: np.ndarray, queries: np.ndarray) -> np.ndarray:
    """The closest point to each of ``queries`` (m, 3) on the triangles ``tris`` of
    ``points``, searched among the ``NEAREST_TRIANGLES`` of nearest centroid: the point's
    projection on a triangle's plane where that falls inside it, else the closest point of
    its edges."""
    a, b, c = (points[tris[:, n]] for n in range(3))
    k = min(NEAREST_TRIANGLES, len(tris))
    _, near = cKDTree((a + b + c) / 3.0).query(queries, k=k)
    near = near.reshape(len(queries), k)
    a, b, c, q = a[near], b[near], c[near], queries[:, None, :]
    normal = np.cross(b - a, c - a)
    area = np.einsum("...d,...d->...", normal, normal)
    on_plane = (
        q
        - (np.einsum("...d,...d->...", q - a, normal) / np.maximum(area, DEGENERATE))[..., None]
        * normal
    )
    inside = area > DEGENERATE  # a sliver's plane is no plane: its edges answer for it
    for p0, p1 in ((a, b), (b, c), (c, a)):
        inside &= np.einsum("...d,...d->...", np.cross(p1 - p0, on_plane - p0), normal) >= 0.0
    edges = np.stack(
        [_closest_on_segments(q, p0, p1) for p0, p1 in ((a, b), (b, c), (c, a))], axis=-2
    )
    nearest_edge = np.take_along_axis(
        edges, np.linalg.norm(edges - q[..., None, :], axis=-1).argmin(-1)[..., None, None], -2
    )[..., 0, :]
    best = np.where(inside[..., None], on_plane, nearest_edge)
    pick = np.linalg.norm(best - q, axis=-1).argmin(axis=1)
    return best[np.arange(len(queries)), pick]


def corner_angles(grid: np.ndarray) -> np.ndarray:
    """The largest corner angle (degrees) of each quad of a face grid (na, nb, 3), and 180
    where the quad turns over against the face's mean normal (a fold)."""
    p00, p10, p11, p01 = grid[:-1, :-1], grid[1:, :-1], grid[1:, 1:], grid[:-1, 1:]
    ring = (p00, p10, p11, p01)
    cosines = []
    for n in range(4):
        u, w = ring[n - 1] - ring[n], ring[(n + 1) % 4] - ring[n]
        cosines.append(
            np.einsum("...d,...d->...", u, w)
            / np.maximum(np.linalg.norm(u, axis=-1) * np.linalg.norm(w, axis=-1), DEGENERATE)
        )
    worst = np.degrees(np.arccos(np.clip(np.min(cosines, axis=0), -1.0, 1.0)))
    normal = np.cross(p11 - p00, p01 - p10)
    facing = np.einsum("...d,d->...", normal, normal.sum(axis=(0, 1)))
    return np.where(facing > 0.0, worst, 180.0)


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
        transfinite = self._transfinite(grid, params)
        better = corner_angles(transfinite).max() < corner_angles(grid).max()
        return transfinite if better else grid

    def _transfinite(self, grid: np.ndarray, params: np.ndarray) -> np.ndarray:
        """``grid`` with its inner nodes at the 3D transfinite interpolation of its sides
        (at the nodes' parameters) moved to their closest points on the face: where the
        square map's grid bends its lines (a face of a polar bend, whose harmonic map puts
        the rows off its arcs), TFI keeps them on the arcs and at right angles."""
        u, v = params[1:-1, 1:-1, 0, None], params[1:-1, 1:-1, 1, None]
        along = {
            n: edge_nodes(self.sides[n], x.ravel()).reshape(*x.shape[:2], 3)
            for n, x in (("a0", u), ("a1", u), ("b0", v), ("b1", v))
        }
        c00, c10, c01, c11 = grid[0, 0], grid[-1, 0], grid[0, -1], grid[-1, -1]
        inner = (
            (1 - v) * along["a0"]
            + v * along["a1"]
            + (1 - u) * along["b0"]
            + u * along["b1"]
            - (1 - u) * (1 - v) * c00
            - u * (1 - v) * c10
            - (1 - u) * v * c01
            - u * v * c11
        )
        out = grid.copy()
        out[1:-1, 1:-1] = closest_points(self.points, self.tris, inner.reshape(-1, 3)).reshape(
            inner.shape
        )
        return out
