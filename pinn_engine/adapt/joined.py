"""The adaptive equations of SPEC 14 on a multi-block grid's blocks joined into one: the
interfaces and the junctions inside the domain are interior nodes (SPEC 10's interfaces
solved, not drawn), so they move with a front as any node does.

The blocks' lattices share no parameter space (a junction of three or five blocks has no
common (u, v)), so the joined grid is adapted in the plane with its own refined cells as
the reference, the computational mesh (Li, Tang and Zhang, "Moving mesh methods in multiple
dimensions based on harmonic maps", J. Comput. Phys. 170, 2001): Winslow's equations for
the computational coordinates xi(x), both with the diffusion tensor D,

    div( D grad xi ) = 0,    xi = x at the nodes that stay, a boundary piece's xi given,

by piecewise-linear finite elements on the refined sub-cells' triangles (each sub-cell cut
along its diagonal that is Delaunay in D's metric), then inverted: each node goes where
xi takes its unadapted position. With D constant xi = x solves them exactly, discretely too
(a linear function is discrete-harmonic on any triangulation): the unadapted grid, its
gradings and its wall rows, is kept where the field is flat."""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix, csr_matrix
from scipy.spatial import cKDTree

from pinn_engine.adapt.nodes import NodeGraph, _boundary_edges, _merged, lattice_quads

# a node's triangles tried, nearest image centroid first, for the one whose image holds
# its unadapted position (the refined sub-cells round a node: 8 triangles, and their ring)
NEAREST = 16


class Joined:
    """The refined lattices ``refined`` (each block's points (rows, cols, 2), ``r``
    sub-cells a cell side) of ``graph``'s blocks joined: their unique ``points``, each
    block's id lattice ``ids`` of them, the ``fixed`` refined nodes (the boundary, held
    nodes and the insides of held cells) and the unadapted nodes ``inner`` the inversion
    places (interfaces and junctions among them)."""

    def __init__(self, graph: NodeGraph, refined: list[np.ndarray], r: int) -> None:
        self.points, self.ids = _merged(refined)
        self.quads = lattice_quads(self.ids)
        n = len(self.points)
        stays = graph.held & ~graph.junctions
        fixed = np.zeros(n, dtype=bool)
        fixed[_boundary_edges(self.quads, n).ravel()] = True
        at = np.zeros(len(graph.points), dtype=int)  # each unadapted node's refined id
        for block, ids in zip(graph.ids, self.ids):
            held = stays[block]
            at[block] = ids[::r, ::r]
            whole = held[:-1, :-1] & held[:-1, 1:] & held[1:, :-1] & held[1:, 1:]
            sub = np.kron(whole, np.ones((r, r), dtype=bool))
            rows, cols = ids.shape
            for dj, di in ((0, 0), (0, 1), (1, 0), (1, 1)):
                fixed[ids[dj : rows - 1 + dj, di : cols - 1 + di][sub]] = True
        fixed[at[stays]] = True
        self.fixed = fixed
        self.inner = np.flatnonzero(~fixed[at])

    def system(self, tensors: list[np.ndarray]) -> tuple[csr_matrix, np.ndarray]:
        """The operator of div(D grad) on the joined triangles (D: ``tensors``, each
        block's at its refined nodes (rows, cols, 3)) and the triangles."""
        d = np.zeros((len(self.points), 3))
        for ids, tensor in zip(self.ids, tensors):
            d[ids] = tensor
        triangles = _split(self.points, self.quads, d)
        return _stiffness(self.points, triangles, d[triangles].mean(axis=1)), triangles

    def jacobian(self, xi: np.ndarray, triangles: np.ndarray) -> np.ndarray:
        """d xi / d x (n, 2, 2) of the piecewise-linear map ``xi`` (n, 2) of the joined
        refined nodes: each of ``triangles``' own, their mean at each node."""
        p, v = self.points[triangles], xi[triangles]
        e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
        f1, f2 = v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]
        det = _cross(e1, e2)
        det = np.where(np.abs(det) > 1e-300, det, 1e-300)
        # J (e1 e2) = (f1 f2), so J = (f1 e2^perp - f2 e1^perp) / det, e^perp = (e_y, -e_x)
        jac = (
            f1[:, :, None] * np.stack([e2[:, 1], -e2[:, 0]], -1)[:, None, :]
            - f2[:, :, None] * np.stack([e1[:, 1], -e1[:, 0]], -1)[:, None, :]
        ) / det[:, None, None]
        n, corners = len(self.points), triangles.ravel()
        count = np.maximum(np.bincount(corners, minlength=n), 1)
        flat = jac.reshape(-1, 4)
        total = [np.bincount(corners, np.repeat(flat[:, k], 3), minlength=n) for k in range(4)]
        return (np.stack(total, axis=-1) / count[:, None]).reshape(n, 2, 2)

    def placed(self, xi: np.ndarray, triangles: np.ndarray, targets: np.ndarray) -> np.ndarray:
        """The points where the piecewise-linear map ``xi`` (n, 2) of the joined refined
        nodes takes ``targets`` (k, 2): in the one of each target's ``NEAREST``
        ``triangles`` (by their images' centroids) whose image holds it (its smallest
        barycentric coordinate the largest: the nearest where none holds it)."""
        image = xi[triangles]
        _, near = cKDTree(image.mean(axis=1)).query(targets, k=NEAREST)
        x0 = image[near, 0]
        e1, e2 = image[near, 1] - x0, image[near, 2] - x0
        det = e1[..., 0] * e2[..., 1] - e1[..., 1] * e2[..., 0]
        det = np.where(np.abs(det) > 1e-300, det, 1e-300)
        dx = targets[:, None, :] - x0
        l1 = (dx[..., 0] * e2[..., 1] - dx[..., 1] * e2[..., 0]) / det
        l2 = (e1[..., 0] * dx[..., 1] - e1[..., 1] * dx[..., 0]) / det
        low = np.minimum(np.minimum(l1, l2), 1.0 - l1 - l2)
        pick = np.argmax(low, axis=1)
        rows = np.arange(len(targets))
        a, b = l1[rows, pick][:, None], l2[rows, pick][:, None]
        corners = self.points[triangles[near[rows, pick]]]
        return (1 - a - b) * corners[:, 0] + a * corners[:, 1] + b * corners[:, 2]


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _angle(a: np.ndarray, b: np.ndarray, metric: np.ndarray) -> np.ndarray:
    """The angle between the vectors a and b (k, 2) in the metric (k, 3: xx, xy, yy)."""
    dot = (
        metric[:, 0] * a[:, 0] * b[:, 0]
        + metric[:, 1] * (a[:, 0] * b[:, 1] + a[:, 1] * b[:, 0])
        + metric[:, 2] * a[:, 1] * b[:, 1]
    )
    det = np.sqrt(np.maximum(metric[:, 0] * metric[:, 2] - metric[:, 1] ** 2, 0.0))
    return np.arctan2(np.abs(_cross(a, b)) * det, dot)


def _split(points: np.ndarray, quads: np.ndarray, d: np.ndarray) -> np.ndarray:
    """The triangles (2 k, 3) of the sub-cells ``quads`` (k, 4), each cut along the diagonal
    that is Delaunay in the metric D^-1 (the two angles opposite it sum to pi or less): the
    finite elements' weight on it is then not negative."""
    mean = d[quads].mean(axis=1)
    det = np.maximum(mean[:, 0] * mean[:, 2] - mean[:, 1] ** 2, 1e-300)
    metric = np.stack([mean[:, 2], -mean[:, 1], mean[:, 0]], axis=-1) / det[:, None]
    p = points[quads]
    opposite = _angle(p[:, 0] - p[:, 1], p[:, 2] - p[:, 1], metric) + _angle(
        p[:, 2] - p[:, 3], p[:, 0] - p[:, 3], metric
    )
    c0, c1, c2, c3 = quads.T
    along = (opposite <= np.pi)[:, None]  # the diagonal from c0 to c2
    first = np.where(along, np.stack([c0, c1, c2], -1), np.stack([c0, c1, c3], -1))
    second = np.where(along, np.stack([c0, c2, c3], -1), np.stack([c1, c2, c3], -1))
    return np.vstack([first, second])


def _stiffness(points: np.ndarray, triangles: np.ndarray, d: np.ndarray) -> csr_matrix:
    """The piecewise-linear finite-element operator of div(D grad) on ``triangles``, D
    (k, 3) constant on each: the sum of area grad(phi_a)^T D grad(phi_b)."""
    p = points[triangles]
    opposite = [p[:, 2] - p[:, 1], p[:, 0] - p[:, 2], p[:, 1] - p[:, 0]]
    twice = _cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    grads = [np.stack([-e[:, 1], e[:, 0]], axis=-1) / twice[:, None] for e in opposite]
    area = 0.5 * np.abs(twice)
    rows, cols, values = [], [], []
    for a, ga in enumerate(grads):
        for b, gb in enumerate(grads):
            rows.append(triangles[:, a])
            cols.append(triangles[:, b])
            values.append(
                area
                * (
                    d[:, 0] * ga[:, 0] * gb[:, 0]
                    + d[:, 1] * (ga[:, 0] * gb[:, 1] + ga[:, 1] * gb[:, 0])
                    + d[:, 2] * ga[:, 1] * gb[:, 1]
                )
            )
    n = len(points)
    return coo_matrix(
        (np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)
    ).tocsr()
