"""Multi-block grids read back: polylines written as .vtp, each block's sides, the kinks
of grid lines across interfaces and the first cells at a named patch (imported as
``multiblock_checks`` by the multi-block tests)."""

from __future__ import annotations

import numpy as np
import pyvista as pv


def write_polylines(path, polylines, closed: bool = False) -> str:
    """Write polylines (each a list of (x, y)) to a .vtp file."""
    points, cells = [], []
    for line in polylines:
        ids = list(range(len(points), len(points) + len(line)))
        points += [(x, y, 0.0) for x, y in line]
        cells += [len(ids) + closed, *ids, *ids[:1] * closed]
    poly = pv.PolyData(np.array(points, dtype=float), lines=np.array(cells))
    poly.save(path)
    return str(path)


def block_sides(block: pv.StructuredGrid):
    """Each side's nodes and the nodes just inside it, (n, 2) each, corner to corner."""
    ni, nj, _ = block.dimensions
    g = block.points[:, :2].reshape(nj, ni, 2)
    return [(g[0], g[1]), (g[-1], g[-2]), (g[:, 0], g[:, 1]), (g[:, -1], g[:, -2])]


def interface_kinks(grid: pv.MultiBlock, corner_nodes: int = 2) -> np.ndarray:
    """180 minus the angle between the two blocks' grid edges leaving each node that two
    blocks share, the ``corner_nodes`` nodes nearest each block corner left out."""
    leaving: dict[tuple, list] = {}
    for block in grid:
        for side, inside in block_sides(block):
            n = len(side)
            for k in range(n):
                near = k <= corner_nodes or k >= n - 1 - corner_nodes
                leaving.setdefault(tuple(side[k]), []).append((near, inside[k] - side[k]))
    kinks = []
    for found in leaving.values():
        if len(found) == 2 and not (found[0][0] or found[1][0]):
            u, v = found[0][1], found[1][1]
            cos = u @ v / (np.linalg.norm(u) * np.linalg.norm(v))
            kinks.append(180.0 - np.degrees(np.arccos(np.clip(cos, -1, 1))))
    return np.array(kinks)


def patch_walls(grid: pv.MultiBlock, name: str):
    """For each side of a block holding a piece of patch ``name``: its nodes and the nodes
    just inside it, corner to corner."""
    out = []
    for block in grid:
        ni, nj, _ = block.dimensions
        g = block.points[:, :2].reshape(nj, ni, 2)
        ranges = block.field_data["PieceRanges"].reshape(-1, 4)
        for piece, (i0, j0, _, j1) in zip(block.field_data["PieceNames"], ranges):
            if piece != name:
                continue
            if j0 == j1:
                out.append((g[j0], g[1 if j0 == 0 else -2]))
            else:
                out.append((g[:, i0], g[:, 1 if i0 == 0 else -2]))
    return out


def first_edges(walls) -> np.ndarray:
    """First edges at the wall nodes, block corners aside."""
    return np.concatenate([np.linalg.norm(inside - side, axis=1)[1:-1] for side, inside in walls])


def wall_angles(walls) -> np.ndarray:
    """Degrees off 90 of the first edge against the wall's chord tangent, the two nodes
    nearest each block corner aside."""
    out = []
    for side, inside in walls:
        tangent, leave = side[2:] - side[:-2], (inside - side)[1:-1]
        cos = np.einsum("nk,nk->n", tangent, leave) / (
            np.linalg.norm(tangent, axis=1) * np.linalg.norm(leave, axis=1)
        )
        out.append(np.abs(90.0 - np.degrees(np.arccos(cos)))[1:-1])
    return np.concatenate(out)
