"""1-to-1 joins between the blocks of a multi-block grid (CGNS ``GridConnectivity1to1_t``):
where a run of one block's side nodes is the same points as a run of another's, both ways,
with the ``Transform`` of CGNS SIDS (each of our index axes as a signed donor axis)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# Each side: the index axis it runs along (0: i, 1: j) and whether it lies at the largest
# index of the other axis (top, right) or the smallest (bottom, left)
SIDE_AXES = {"bottom": (0, False), "right": (1, True), "top": (0, True), "left": (1, False)}


@dataclass(frozen=True)
class Join:
    """A ``GridConnectivity1to1_t``: its name, the donor zone, the 1-based 2D (i, j) point
    ranges here and in the donor (begin to end, the donor's begin matching ours) and the
    2D ``Transform`` (signed donor axis of each of our axes)."""

    name: str
    donor: str
    here: tuple[tuple[int, int], tuple[int, int]]
    there: tuple[tuple[int, int], tuple[int, int]]
    transform: tuple[int, int]


def _side_ij(ni: int, nj: int, side: str) -> np.ndarray:
    """(n, 2) 0-based (i, j) of a side's nodes in increasing index order."""
    run = np.arange(ni if SIDE_AXES[side][0] == 0 else nj)
    fixed = {"bottom": 0, "right": ni - 1, "top": nj - 1, "left": 0}[side]
    other = np.full_like(run, fixed)
    return np.column_stack([run, other] if SIDE_AXES[side][0] == 0 else [other, run])


def _edges(points: list[np.ndarray]) -> dict[tuple, list[tuple[int, str, int]]]:
    """Every side edge of every block by its two end points (sorted): (block, side,
    position of the edge's first node along the side)."""
    out: dict[tuple, list[tuple[int, str, int]]] = {}
    for b, pts in enumerate(points):
        nj, ni = pts.shape[:2]
        for side in SIDE_AXES:
            ij = _side_ij(ni, nj, side)
            xy = [tuple(pts[j, i]) for i, j in ij]
            for k in range(len(xy) - 1):
                out.setdefault(tuple(sorted((xy[k], xy[k + 1]))), []).append((b, side, k))
    return out


def _transform(side: str, donor_side: str, along: int) -> tuple[int, int]:
    """Our axes as signed donor axes (1-based): along the side, +-the donor's running axis
    (``along`` the sign: +1 when both run alike); across it, the donor's other axis, + when
    stepping out of our block steps into the donor's (our largest index meets its
    smallest, or the reverse)."""
    a, at_max = SIDE_AXES[side]
    b, donor_at_max = SIDE_AXES[donor_side]
    out = [0, 0]
    out[a] = along * (b + 1)
    out[1 - a] = (1 if at_max != donor_at_max else -1) * (2 - b)
    return out[0], out[1]


def joins(points: list[np.ndarray], block: int) -> list[Join]:
    """The joins of ``block`` with the blocks (their nodes (nj, ni, 3)) it shares side
    nodes with: one a run of consecutive shared edges with one donor side."""
    edges = _edges(points)
    nj, ni = points[block].shape[:2]
    out = []
    for side in SIDE_AXES:
        ij = _side_ij(ni, nj, side)
        xy = [tuple(points[block][j, i]) for i, j in ij]
        runs: list[list] = []  # [donor, donor side, along, first k, last k, donor positions]
        for k in range(len(xy) - 1):
            others = [e for e in edges[tuple(sorted((xy[k], xy[k + 1])))] if e[:2] != (block, side)]
            if not others:
                runs.append(None)
                continue
            b, s, m = others[0]
            dij = _side_ij(*points[b].shape[1::-1], s)
            along = 1 if tuple(points[b][dij[m][1], dij[m][0]]) == xy[k] else -1
            start, end = (m, m + 1) if along == 1 else (m + 1, m)
            last = runs[-1] if runs else None
            if last and last[:3] == [b, s, along] and last[4] == k - 1:
                last[4], last[5][1] = k, end
            else:
                runs.append([b, s, along, k, k, [start, end]])
        for run in runs:
            if run is None:
                continue
            b, s, along, k0, k1, (d0, d1) = run
            dij = _side_ij(*points[b].shape[1::-1], s)
            here = (tuple(int(v) + 1 for v in ij[k0]), tuple(int(v) + 1 for v in ij[k1 + 1]))
            there = (tuple(int(v) + 1 for v in dij[d0]), tuple(int(v) + 1 for v in dij[d1]))
            name = f"to_block{b}_{len(out)}"
            out.append(Join(name, f"block{b}", here, there, _transform(side, s, along)))
    return out
