"""Index arithmetic of a structured (ni, nj) grid and its one-cell extrusion (numpy only).

Node ``(i, j, k)`` has index ``i + ni * (j + nj * k)``; cell ``(i, j)`` has index
``i + (ni - 1) * j``. The grid is positively oriented (SPEC 1 and 3: i along bottom
counter-clockwise, j towards top), so the quads below are counter-clockwise and the faces
of the extrusion (k = 0 at z = 0, k = 1 at z = T) point out of the domain.
"""

from __future__ import annotations

import numpy as np

from pinn_engine.io.export.patches import SIDES


def layers(points: np.ndarray, thickness: float | None, normal: np.ndarray) -> np.ndarray:
    """``points`` (nj, ni, 3) as (nk, nj, ni, 3): nk = 1, or 2 with the copy moved by T
    along ``normal`` (z + T for a grid in a plane z = const)."""
    if thickness is None:
        return points[None]
    return np.stack([points, points + thickness * np.asarray(normal, dtype=float)])


def mean_edge(points: np.ndarray) -> float:
    """Mean length of the grid's edges (the default extrusion thickness)."""
    di = np.linalg.norm(np.diff(points, axis=1), axis=-1)
    dj = np.linalg.norm(np.diff(points, axis=0), axis=-1)
    return float(np.concatenate([di.ravel(), dj.ravel()]).mean())


def quads(ni: int, nj: int) -> np.ndarray:
    """(cells, 4) counter-clockwise node indices of the layer k = 0, i fastest."""
    jj, ii = np.mgrid[0 : nj - 1, 0 : ni - 1]
    n = (ii + ni * jj).ravel()
    return np.column_stack([n, n + 1, n + 1 + ni, n + ni])


def hexes(ni: int, nj: int) -> np.ndarray:
    """(cells, 8) node indices of the extruded cells: the quad at k = 0, then at k = 1."""
    q = quads(ni, nj)
    return np.hstack([q, q + ni * nj])


def side_nodes(ni: int, nj: int, side: str) -> np.ndarray:
    """Node indices of a side, counter-clockwise around the domain (domain on the left)."""
    i, j = np.arange(ni), np.arange(nj)
    return {
        "bottom": i,
        "right": ni - 1 + ni * j,
        "top": (i + ni * (nj - 1))[::-1],
        "left": (ni * j)[::-1],
    }[side]


def side_cells(ni: int, nj: int, side: str) -> np.ndarray:
    """The cell next to each edge of ``side_edges`` (same order)."""
    i, j = np.arange(ni - 1), np.arange(nj - 1)
    return {
        "bottom": i,
        "right": ni - 2 + (ni - 1) * j,
        "top": (i + (ni - 1) * (nj - 2))[::-1],
        "left": ((ni - 1) * j)[::-1],
    }[side]


def side_edges(ni: int, nj: int, side: str) -> np.ndarray:
    """(edges, 2) node pairs along a side, counter-clockwise (domain on the left)."""
    n = side_nodes(ni, nj, side)
    return np.column_stack([n[:-1], n[1:]])


def side_faces(ni: int, nj: int, side: str) -> np.ndarray:
    """(faces, 4) extruded side faces, normal out of the domain (same order as the edges)."""
    e = side_edges(ni, nj, side)
    top = ni * nj
    return np.column_stack([e[:, 0], e[:, 1], e[:, 1] + top, e[:, 0] + top])


def end_faces(ni: int, nj: int, end: str) -> np.ndarray:
    """(cells, 4) faces at k = 0 ("back", normal -z) or k = 1 ("front", normal +z)."""
    q = quads(ni, nj)
    return q[:, ::-1] if end == "back" else q + ni * nj


def side_size(ni: int, nj: int, side: str) -> int:
    """Nodes along a side."""
    return ni if side in ("bottom", "top") else nj


def index_range(ni: int, nj: int, side: str) -> tuple[tuple[int, int], tuple[int, int]]:
    """1-based ((imin, jmin), (imax, jmax)) of a side (CGNS PointRange)."""
    return {
        "bottom": ((1, 1), (ni, 1)),
        "right": ((ni, 1), (ni, nj)),
        "top": ((1, nj), (ni, nj)),
        "left": ((1, 1), (1, nj)),
    }[side]


__all__ = [
    "SIDES",
    "end_faces",
    "hexes",
    "index_range",
    "layers",
    "mean_edge",
    "quads",
    "side_cells",
    "side_edges",
    "side_faces",
    "side_nodes",
    "side_size",
]
