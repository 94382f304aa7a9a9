"""Faces of an untagged surface (an ``.stl``, SPEC 11): the regions its sharp edges bound.

Two neighbouring triangles are in one face unless their normals differ by more than
``settings.FACE_ANGLE`` (SPEC 11's 40 degrees, or the run's ``face_angle``); the faces are the
connected regions of triangles so joined. The normals are
compared as the shared edge orients them (a triangle wound the other way round is turned),
so that an STL whose triangles disagree on their winding still splits where it bends.
"""

from __future__ import annotations

import numpy as np

from pinn_engine.settings import FACE_ANGLE


def faces_at_sharp_edges(
    points: np.ndarray, triangles: np.ndarray, angle: float = FACE_ANGLE
) -> tuple[int, np.ndarray]:
    """The number of faces and the face index of each triangle; edges held by other than two
    triangles join nothing (the topology check reports an open surface)."""
    # imported here: only an STL's faces are found at its edges
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    normal = np.cross(
        points[triangles[:, 1]] - points[triangles[:, 0]],
        points[triangles[:, 2]] - points[triangles[:, 0]],
    )
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
    start = triangles.ravel()
    end = np.roll(triangles, -1, axis=1).ravel()
    owner = np.repeat(np.arange(len(triangles)), 3)
    key = np.sort(np.column_stack([start, end]), axis=1)
    _, edge, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    edge = edge.ravel()
    pair = np.flatnonzero(counts[edge] == 2)
    pair = pair[np.argsort(edge[pair], kind="stable")].reshape(-1, 2)
    a, b = pair[:, 0], pair[:, 1]
    turned = np.where(start[a] == start[b], -1.0, 1.0)  # same direction: windings disagree
    cos = turned * np.einsum("ij,ij->i", normal[owner[a]], normal[owner[b]])
    smooth = cos >= np.cos(np.radians(angle))
    n = len(triangles)
    graph = coo_matrix(
        (np.ones(int(smooth.sum())), (owner[a][smooth], owner[b][smooth])), shape=(n, n)
    )
    count, face_of = connected_components(graph, directed=False)
    return count, face_of
