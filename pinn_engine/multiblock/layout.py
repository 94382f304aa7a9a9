"""The nodes of a multi-block grid: one numbering over all blocks, so that a node on a side
shared by two blocks is placed once and is the same point in both (SPEC 10)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pinn_engine.classical.tfi import tfi_of_sides
from pinn_engine.geometry.boundary import arc_lengths
from pinn_engine.multiblock.blocks import Topology


@dataclass
class Layout:
    """Node positions ``points`` (N, 2), per block its node ids ``ids`` (nj, ni) (i along
    side 0 from corner 0, j along side 3 backwards), per piece its node ids in the piece's
    own direction, and per piece its nodes' arc-length fractions ``piece_params`` (0 to 1:
    equal steps, or a grading's)."""

    points: np.ndarray
    ids: list[np.ndarray]
    piece_ids: list[np.ndarray]
    piece_params: list[np.ndarray]


def resample(polyline: np.ndarray, cells: int, params: np.ndarray | None = None) -> np.ndarray:
    """``cells + 1`` points along ``polyline`` at the arc-length fractions ``params`` (None:
    equal steps), its ends exactly."""
    s = arc_lengths(polyline)
    t = s[-1] * (np.linspace(0.0, 1.0, cells + 1) if params is None else params)
    out = np.column_stack([np.interp(t, s, polyline[:, 0]), np.interp(t, s, polyline[:, 1])])
    out[0], out[-1] = polyline[0], polyline[-1]
    return out


def _side_ids(side, piece_ids) -> np.ndarray:
    """Node ids along a side (a list of (piece, backwards)), corner to corner."""
    runs = [piece_ids[p][::-1] if back else piece_ids[p] for p, back in side]
    return np.concatenate([runs[0]] + [r[1:] for r in runs[1:]])


def layout(
    topo: Topology, counts: np.ndarray, graded: dict[int, np.ndarray] | None = None
) -> Layout:
    """Nodes of every piece at equal arc length (``counts`` cells a piece; ``graded``: piece
    -> its nodes' arc-length fractions instead), the piece ends shared by the pieces meeting
    there, and each block's interior by TFI of its sides."""
    points: list[np.ndarray] = []
    junction: dict[tuple[float, float], int] = {}

    def new(xy: np.ndarray) -> np.ndarray:
        start = sum(len(p) for p in points)
        points.append(np.asarray(xy, dtype=float).reshape(-1, 2))
        return np.arange(start, start + len(points[-1]))

    def end(xy: np.ndarray) -> int:
        key = (float(xy[0]), float(xy[1]))
        if key not in junction:
            junction[key] = int(new(xy)[0])
        return junction[key]

    piece_ids, params = [], []
    for k, (piece, n) in enumerate(zip(topo.pieces, counts)):
        params.append((graded or {}).get(k, np.linspace(0.0, 1.0, int(n) + 1)))
        nodes = resample(piece.points, int(n), params[-1])
        inner = new(nodes[1:-1])
        piece_ids.append(np.concatenate([[end(nodes[0])], inner, [end(nodes[-1])]]))
    ids = []
    for block in topo.blocks:
        s0, s1, s2, s3 = (_side_ids(side, piece_ids) for side in block.sides)
        bottom, right, top, left = s0, s1, s2[::-1], s3[::-1]
        nj, ni = len(right), len(bottom)
        grid = np.empty((nj, ni), dtype=int)
        grid[0], grid[-1], grid[:, 0], grid[:, -1] = bottom, top, left, right
        xy = np.concatenate(points)
        inner = tfi_of_sides(xy[bottom], xy[right], xy[top], xy[left])[1:-1, 1:-1]
        grid[1:-1, 1:-1] = new(inner).reshape(nj - 2, ni - 2)
        ids.append(grid)
    return Layout(np.concatenate(points), ids, piece_ids, params)


def side_lines(ids: np.ndarray, side: str) -> np.ndarray:
    """The grid lines of a block of node ``ids`` leaving ``side``, each from its node on it."""
    return {"bottom": ids.T, "top": ids[::-1].T, "left": ids, "right": ids[:, ::-1]}[side]
