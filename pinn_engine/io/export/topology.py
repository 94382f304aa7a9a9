"""Index arithmetic of a structured (ni, nj) grid, its one-cell extrusion and a hexahedral
(ni, nj, nk) grid (numpy only).

Node ``(i, j, k)`` has index ``i + ni * (j + nj * k)``; cell ``(i, j, k)`` has index
``i + (ni - 1) * (j + (nj - 1) * k)``. The 2D grid is positively oriented (SPEC 1 and 3: i
along bottom counter-clockwise, j towards top), so the quads below are counter-clockwise
and the faces of the extrusion (k = 0 at z = 0, k = 1 at z = T) point out of the domain;
a hexahedral grid is right-handed in (i, j, k) (SPEC 11), so its box faces point out too.
"""

from __future__ import annotations

import numpy as np

from pinn_engine.io.export.patches import BOX_SIDES, SIDES


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


def hexahedra(ni: int, nj: int, nk: int) -> np.ndarray:
    """(cells, 8) node indices of the hexahedra, VTK's order: the quad at k, then at k + 1."""
    layer = ni * nj
    q = (quads(ni, nj)[None] + layer * np.arange(nk - 1)[:, None, None]).reshape(-1, 4)
    return np.hstack([q, q + layer])


def hexes(ni: int, nj: int) -> np.ndarray:
    """(cells, 8) node indices of the extruded cells: the quad at k = 0, then at k = 1."""
    return hexahedra(ni, nj, 2)


def _planes(ids: np.ndarray, axis: int) -> np.ndarray:
    """``ids`` (indexed [i, j, k]) as planes across ``axis``: [along axis, b, c] with b, c
    the next axes in cyclic order, so that b x c points along +axis."""
    return ids.transpose(axis, (axis + 1) % 3, (axis + 2) % 3)


def _plane_quads(planes: np.ndarray, plus: bool) -> np.ndarray:
    """(faces, 4) quads of node planes [along axis, b, c], normals along +axis (``plus``) or
    -axis; plane after plane, c fastest."""
    p00, p10 = planes[:, :-1, :-1], planes[:, 1:, :-1]
    p11, p01 = planes[:, 1:, 1:], planes[:, :-1, 1:]
    corners = (p00, p10, p11, p01) if plus else (p00, p01, p11, p10)
    return np.stack([x.ravel() for x in corners], axis=1)


def _ids(ni: int, nj: int, nk: int) -> np.ndarray:
    """Node (or, given cell counts, cell) indices as an array [i, j, k]."""
    return np.arange(ni * nj * nk).reshape(nk, nj, ni).transpose(2, 1, 0)


def box_faces(ni: int, nj: int, nk: int, side: str) -> np.ndarray:
    """(faces, 4) boundary faces of a side (``BOX_SIDES``) of a hexahedral grid, normals
    out of the domain."""
    axis, end = divmod(BOX_SIDES.index(side), 2)
    planes = _planes(_ids(ni, nj, nk), axis)
    return _plane_quads(planes[[-1 if end else 0]], plus=bool(end))


def box_cells(ni: int, nj: int, nk: int, side: str) -> np.ndarray:
    """The cell next to each face of ``box_faces`` (same order)."""
    axis, end = divmod(BOX_SIDES.index(side), 2)
    return _planes(_ids(ni - 1, nj - 1, nk - 1), axis)[-1 if end else 0].ravel()


def inner_faces(ni: int, nj: int, nk: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The faces between the cells of a hexahedral grid, each with its normal from the
    lower cell (the owner) to the higher (the neighbour): faces, owners, neighbours."""
    nodes, cells = _ids(ni, nj, nk), _ids(ni - 1, nj - 1, nk - 1)
    faces, owner, neighbour = [], [], []
    for axis in range(3):
        faces.append(_plane_quads(_planes(nodes, axis)[1:-1], plus=True))
        across = _planes(cells, axis)
        owner.append(across[:-1].ravel())
        neighbour.append(across[1:].ravel())
    return np.vstack(faces), np.concatenate(owner), np.concatenate(neighbour)


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


def box_range(ni: int, nj: int, nk: int, side: str) -> tuple[tuple[int, ...], tuple[int, ...]]:
    """1-based ((imin, jmin, kmin), (imax, jmax, kmax)) of a side of a hexahedral grid."""
    axis, end = divmod(BOX_SIDES.index(side), 2)
    lo, hi = [1, 1, 1], [ni, nj, nk]
    lo[axis] = hi[axis] = hi[axis] if end else 1
    return tuple(lo), tuple(hi)


def index_range(ni: int, nj: int, side: str) -> tuple[tuple[int, int], tuple[int, int]]:
    """1-based ((imin, jmin), (imax, jmax)) of a side (CGNS PointRange)."""
    return {
        "bottom": ((1, 1), (ni, 1)),
        "right": ((ni, 1), (ni, nj)),
        "top": ((1, nj), (ni, nj)),
        "left": ((1, 1), (1, nj)),
    }[side]


__all__ = [
    "BOX_SIDES",
    "SIDES",
    "box_cells",
    "box_faces",
    "box_range",
    "end_faces",
    "hexahedra",
    "hexes",
    "index_range",
    "inner_faces",
    "layers",
    "mean_edge",
    "quads",
    "side_cells",
    "side_edges",
    "side_faces",
    "side_nodes",
]
