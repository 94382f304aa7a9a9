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

Where the wall's nodes are much closer together than the first edge and the grid's lines
lean (beside a block corner on a smooth wall), neighbouring lines turned by different moves
can cross: the lines at the corners of a cell that the turn folds move half as far, until
no cell is folded that was not before (SPEC 7: "without folding a cell").
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
# Halvings of the moves of lines at a cell the turn folds before those lines keep theirs
# (each halves the shear between neighbouring lines), and the share of a move by which
# neighbouring wall nodes' moves may differ after a halving (full again four lines on)
FOLD_ROUNDS, FOLD_RAMP = 6, 0.25


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


def _folded(points: np.ndarray, ids: list[np.ndarray]) -> list[np.ndarray]:
    """Each block's cells (nj - 1, ni - 1) with a corner whose orientation opposes the
    block's (SPEC 6's folded cell)."""
    out = []
    for block in ids:
        p = points[block]
        a, b, c, d = p[:-1, :-1], p[:-1, 1:], p[1:, 1:], p[1:, :-1]
        turns = [
            (q - o)[..., 0] * (r - o)[..., 1] - (q - o)[..., 1] * (r - o)[..., 0]
            for o, q, r in ((a, b, d), (b, c, a), (c, d, b), (d, a, c))
        ]
        sign = np.sign(np.sum(turns[0]))
        out.append(np.any([sign * t <= 0 for t in turns], axis=0))
    return out


def orthogonal(
    points: np.ndarray,
    sides: list[WallSide],
    names: tuple[str, ...],
    around: dict,
    ids: list[np.ndarray],
) -> np.ndarray:
    """``points`` with the lines leaving the patches ``names`` turned onto the wall normals
    (``around``: :func:`boundary_neighbours`; ``ids``: each block's node ids), no cell
    folded that was not before."""
    lines: list[tuple[np.ndarray, np.ndarray]] = []  # each line's moved nodes and moves
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
            taper = (rows + 1 - np.arange(1, rows + 1)) / rows
            lines.append((line[: rows + 2], delta * taper[:, None]))
    before = _folded(points, ids)
    scale = {int(line[0]): 1.0 for line, _ in lines}  # each wall node's share of its move
    for round_ in range(FOLD_ROUNDS + len(scale) + 1):
        out = points.copy()
        for line, moves in lines:
            out[line[1:-1]] = points[line[1:-1]] + scale[int(line[0])] * moves
        bad = set()
        for block, now, was in zip(ids, _folded(out, ids), before):
            for j, i in np.argwhere(now & ~was):
                bad.update(int(n) for n in block[j : j + 2, i : i + 2].ravel())
        hit = {int(line[0]) for line, _ in lines if bad.intersection(line.tolist())}
        if not hit:
            return out
        # halvings first; then the lines still folding keep theirs, one round at a time
        # (all kept is the grid as it was, so this ends); the shares then rise back by
        # FOLD_RAMP a wall node along the wall, so neighbouring lines move alike
        for node in hit:
            scale[node] *= 0.5 if round_ < FOLD_ROUNDS else 0.0
        for _ in range(int(np.ceil(1.0 / FOLD_RAMP))):
            for node in scale:
                near = [scale[n] for n in around[node] if n in scale]
                scale[node] = min([scale[node], *(v + FOLD_RAMP for v in near)])
    return out
