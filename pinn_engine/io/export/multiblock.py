"""A multi-block grid (SPEC 10) as the solver formats' writers take it: each format writes
it in its own way (``.cgns`` a zone a block with 1-to-1 joins and a ``BC_t`` per boundary
piece, ``.xyz`` a PLOT3D grid a block, and the unstructured formats the one merged mesh of
:func:`merged`, each shared node once).

The blocks come from the ``vtkMultiBlockDataSet`` (``vtm.multiblock_dataset``): each block's
points and its boundary pieces (field data ``PieceNames``, ``PieceTypes``, ``PieceRanges``),
so any route that holds the dataset can write it (``export.write_blocks``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from pinn_engine.errors import InputError
from pinn_engine.io.export.quadmesh import QuadMesh
from pinn_engine.io.export.topology import quads, side_edges

if TYPE_CHECKING:
    from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet

Z_UP = np.array([0.0, 0.0, 1.0])  # a multi-block grid lies in a plane z = const
# Field data of each block naming its boundary pieces (SPEC 10's patches; one entry a
# piece): the patch name, its type (``patchnames.TYPES``) and the piece's 0-based node range
# (i0, j0, i1, j1) along one side of the block
PIECE_NAMES, PIECE_TYPES, PIECE_RANGES = "PieceNames", "PieceTypes", "PieceRanges"


@dataclass(frozen=True)
class Piece:
    """A boundary piece of a block: patch ``name``, ``kind`` (``patchnames.TYPES``), and its
    0-based node range ``(i0, j0, i1, j1)`` along one side."""

    name: str
    kind: str
    nodes: tuple[int, int, int, int]

    @property
    def side(self) -> str:
        """The block side the piece lies on (its range is one row or column of nodes)."""
        i0, j0, i1, j1 = self.nodes
        if j0 == j1:
            return "bottom" if j0 == 0 else "top"
        return "left" if i0 == 0 else "right"


@dataclass(frozen=True)
class Blocks:
    """The blocks' nodes, each (nj, ni, 3), and their boundary pieces."""

    points: list[np.ndarray]
    pieces: list[list[Piece]]

    def types(self) -> dict[str, str]:
        """Patch name -> type, in the order the names first appear."""
        return {p.name: p.kind for block in self.pieces for p in block}


def blocks_of(dataset: vtkMultiBlockDataSet) -> Blocks:
    """The blocks of a multi-block dataset with their pieces; refused (one line) when a
    block carries no pieces (a dataset not made by ``vtm.multiblock_dataset``)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    points, pieces = [], []
    for k in range(dataset.GetNumberOfBlocks()):
        grid = dataset.GetBlock(k)
        ext = grid.GetExtent()
        ni, nj = ext[1] - ext[0] + 1, ext[3] - ext[2] + 1
        points.append(vtk_to_numpy(grid.GetPoints().GetData()).astype(float).reshape(nj, ni, 3))
        fd = grid.GetFieldData()
        names, kinds = fd.GetAbstractArray(PIECE_NAMES), fd.GetAbstractArray(PIECE_TYPES)
        ranges = fd.GetArray(PIECE_RANGES)
        if names is None or kinds is None or ranges is None:
            raise InputError(f"block {k} carries no boundary pieces ({PIECE_NAMES})", "grid")
        rows = vtk_to_numpy(ranges).reshape(-1, 4)
        pieces.append(
            [
                Piece(names.GetValue(n), kinds.GetValue(n), tuple(int(v) for v in rows[n]))
                for n in range(names.GetNumberOfValues())
            ]
        )
    return Blocks(points, pieces)


def node_ids(blocks: Blocks) -> tuple[np.ndarray, list[np.ndarray]]:
    """The unique nodes (n, 3) and each block's node ids (nj, ni) into them: nodes at the
    same point (a side shared by two blocks) are one."""
    flat = np.vstack([p.reshape(-1, 3) for p in blocks.points])
    unique, inverse = np.unique(flat, axis=0, return_inverse=True)
    inverse = inverse.ravel()
    ids, start = [], 0
    for p in blocks.points:
        ids.append(inverse[start : start + p.shape[0] * p.shape[1]].reshape(p.shape[:2]))
        start += p.shape[0] * p.shape[1]
    return unique, ids


def merged(blocks: Blocks) -> QuadMesh:
    """One quad mesh of all blocks, shared nodes merged; refused (one line) unless the
    blocks meet node to node and the pieces cover the boundary exactly."""
    points, ids = node_ids(blocks)
    cells = np.vstack([g.ravel()[quads(*g.shape[::-1])] for g in ids])
    patches: dict[str, list[np.ndarray]] = {}
    for g, pieces in zip(ids, blocks.pieces):
        nj, ni = g.shape
        for piece in pieces:
            i0, j0, i1, j1 = piece.nodes
            inside = np.zeros((nj, ni), dtype=bool)
            inside[j0 : j1 + 1, i0 : i1 + 1] = True
            edges = side_edges(ni, nj, piece.side)
            keep = inside.ravel()[edges].all(axis=1)
            patches.setdefault(piece.name, []).append(g.ravel()[edges[keep]])
    out = QuadMesh(points, cells, {k: np.vstack(v) for k, v in patches.items()}, blocks.types())
    _check_boundary(out)
    return out


def _check_boundary(mesh: QuadMesh) -> None:
    """Every edge of one quad only is a patch edge, and every patch edge is such an edge."""
    a = mesh.quads.ravel()
    b = np.roll(mesh.quads, -1, axis=1).ravel()
    key, counts = np.unique(np.sort(np.column_stack([a, b]), axis=1), axis=0, return_counts=True)
    if counts.max() > 2:
        raise InputError("the blocks overlap: an edge is shared by three cells", "grid")
    open_edges = {tuple(e) for e in key[counts == 1]}
    patch_edges = {tuple(sorted(e)) for v in mesh.patches.values() for e in v.tolist()}
    stray = open_edges ^ patch_edges
    if stray:
        x, y = mesh.points[next(iter(stray))[0], :2]
        raise InputError(
            f"the blocks do not meet node to node at ({x:.6g}, {y:.6g}): a side there is "
            "neither shared nor a boundary piece",
            "grid",
        )


__all__ = ["Z_UP", "Blocks", "Piece", "blocks_of", "merged"]
