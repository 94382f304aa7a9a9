"""Orthogonal patches of a multi-block grid (SPEC 10 with SPEC 7's ``--orthogonal``): grid
lines leave the patch's pieces along the wall normal.

As ``starts.orthogonal``'s normal rows do for one block, the first node off each wall node
goes onto the wall's normal there, at the distance it had (the first edge H of a spaced
patch is kept); the normal is that of the chord between the wall node's two neighbours
along the boundary (what SPEC 6's wall angle measures), so a node where two pieces of a
smooth wall meet gets one normal from both blocks. The move tapers to zero over the next
rows, so the line bends back onto the grid's own line within a few cells (a shear along the
wall of a fraction of the first edge: no cell folds). A wall node where the boundary turns
by a block corner's angle or more has no one normal and keeps its line (SPEC 7 excepts the
nodes nearest such corners). Each node moves once, so shared nodes stay identical.
"""

from __future__ import annotations

import numpy as np

from pinn_engine.geometry.boundary import turning_angles
from pinn_engine.multiblock.blocks import CORNER_TURN, Topology
from pinn_engine.multiblock.layout import Layout
from pinn_engine.multiblock.walls import WallSide

# Rows over which the first row's move onto the normal tapers to zero (the first row moves
# fully, row k by (ROWS + 1 - k) / ROWS): its kink in each line is a quarter of the wall
# angle it removes, spread over cells that grow away from a spaced wall
ORTHOGONAL_ROWS = 4


def boundary_neighbours(topo: Topology, lay: Layout) -> dict[int, list[int]]:
    """Each boundary node's two neighbours along the boundary (pieces joined at their ends)."""
    out: dict[int, list[int]] = {}
    for piece, ids in zip(topo.pieces, lay.piece_ids):
        if piece.interface:
            continue
        for a, b in zip(ids[:-1], ids[1:]):
            out.setdefault(int(a), []).append(int(b))
            out.setdefault(int(b), []).append(int(a))
    return out


def orthogonal(
    points: np.ndarray, sides: list[WallSide], names: tuple[str, ...], around: dict
) -> np.ndarray:
    """``points`` with the lines leaving the patches ``names`` turned onto the wall normals
    (``around``: :func:`boundary_neighbours`)."""
    moves: dict[int, np.ndarray] = {}
    for wall in sides:
        if wall.name not in names:
            continue
        for line in wall.lines[wall.on]:
            node = int(line[0])
            a, b = around[node]
            if abs(turning_angles(points[[a, node, b]])[1]) >= CORNER_TURN:
                continue
            t = points[b] - points[a]
            normal = np.array([-t[1], t[0]]) / np.linalg.norm(t)
            first = points[line[1]] - points[node]
            if normal @ first < 0:
                normal = -normal
            delta = points[node] + normal * np.linalg.norm(first) - points[line[1]]
            rows = min(ORTHOGONAL_ROWS, len(line) - 2)
            for k in range(1, rows + 1):
                moves[int(line[k])] = delta * (rows + 1 - k) / rows
    out = points.copy()
    for node, move in moves.items():
        out[node] += move
    return out
