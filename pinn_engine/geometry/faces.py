"""Quad faces of hexahedra matched by their points, whichever cell and corner they are met
from (the polyMesh writer's faces, checkMesh's figures). NumPy alone."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# OpenFOAM's hexahedron: its six faces by corner, each with its normal out of the cell
HEX_FACES = np.array(
    [[0, 4, 7, 3], [1, 2, 6, 5], [0, 1, 5, 4], [3, 7, 6, 2], [0, 3, 2, 1], [4, 5, 6, 7]]
)


def face_keys(quads: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each quad's (m, 4) point ids sorted, packed as two int64 keys (the two lowest ids,
    the two highest): one face met from its two cells has the same keys, and sorting by
    them (``np.lexsort((high, low))``) is sorting by the four sorted ids, in a third of the
    time of a four-key sort."""
    key = np.sort(quads, axis=1).astype(np.int64)
    n = int(key[:, 3].max(initial=0)) + 1  # below 3e9 points: n * n fits in an int64
    return key[:, 0] * n + key[:, 1], key[:, 2] * n + key[:, 3]


def pairing(quads: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The faces (m, 4) met twice, as pairs (k, 2) of their indices (the lower first), and
    those met once."""
    low, high = face_keys(quads)
    order = np.lexsort((high, low))
    low, high = low[order], high[order]
    same = (low[1:] == low[:-1]) & (high[1:] == high[:-1])
    first = np.flatnonzero(same)
    pairs = np.sort(np.column_stack([order[first], order[first + 1]]), axis=1)
    paired = np.zeros(len(quads), dtype=bool)
    paired[pairs.ravel()] = True
    return pairs[np.argsort(pairs[:, 0])], np.flatnonzero(~paired)


@dataclass
class FaceTopology:
    """Each face of hexahedra once, as its owner sees it (OpenFOAM's faces; the neighbour's
    copy is the same face with its area vector reversed): the internal faces first, then the
    boundary's. What :func:`figures` needs of the cells alone, computed once per mesh."""

    quads: np.ndarray  # (f, 4) point ids
    owner: np.ndarray  # (f,) each face's owner cell
    neighbour: np.ndarray  # (internal faces,) each internal face's other cell
    of_cell: np.ndarray  # (cells, 6) each cell face's index among ``quads``
    sign: np.ndarray  # (cells, 6) 1 where the cell owns the face, -1 where it neighbours it


def topology(cells: np.ndarray) -> FaceTopology:
    """The faces of the hexahedra ``cells`` (m, 8), each once (:class:`FaceTopology`)."""
    quads = np.take(cells, HEX_FACES, axis=1).reshape(-1, 4)
    pairs, single = pairing(quads)
    once = np.concatenate([pairs[:, 0], single])
    of_cell = np.empty(len(quads), dtype=np.int64)
    of_cell[once] = np.arange(len(once))
    of_cell[pairs[:, 1]] = np.arange(len(pairs))
    sign = np.ones(len(quads))
    sign[pairs[:, 1]] = -1.0
    return FaceTopology(
        np.take(quads, once, axis=0),  # np.take: rows several times faster than [once]
        once // 6,
        pairs[:, 1] // 6,
        of_cell.reshape(-1, 6),
        sign.reshape(-1, 6),
    )
