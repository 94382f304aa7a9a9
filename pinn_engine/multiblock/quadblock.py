"""A block of a multi-block grid as a four-sided domain (SPEC 1): its boundary through its
side nodes, for the four-sided PINN that trains on it (``network.py``), and the auxiliary
lines inside it (SPEC 2 in the block).

An auxiliary line belongs to the block that holds its middle point (half its length along
it) and runs, as SPEC 2's lines do, from one side of that block to the opposite side; its
(xi, eta) are SPEC 2's rule on the block's sides, parametrised by node index as the PINN's
hard boundary is, so the line's ends are where those side parameters put them.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

from pinn_engine.classical.tfi import node_params
from pinn_engine.errors import InputError
from pinn_engine.geometry.auxlines import AuxLine, RawLine, inside, map_lines
from pinn_engine.geometry.boundary import Boundary, Frame, Polyline


class NodeSide(Polyline):
    """A side polyline through a block's side nodes, parametrised by node index: node k of
    n is at t = k / (n - 1), so that the map's boundary nodes on the uniform lattice are the
    block's side nodes exactly (arc length would put them elsewhere where the side nodes
    are not evenly spaced)."""

    def __init__(self, points: np.ndarray) -> None:
        super().__init__(points)
        self.t = node_params(len(self.points))


@dataclasses.dataclass(frozen=True)
class BlockBoundary(Boundary):
    """A block's four sides as a :class:`Boundary` in its working frame, the sides
    parametrised by node index (:class:`NodeSide`)."""

    def side(self, name: str) -> NodeSide:
        return NodeSide(super().side(name).points)


def block_boundary(grid: np.ndarray) -> BlockBoundary:
    """The boundary of a block grid (nj, ni, 2), in the working frame around it: ring from
    corner 0 along bottom, right, top and left (SPEC 1's side order)."""
    nj, ni = grid.shape[:2]
    ring = np.concatenate([grid[0, :-1], grid[:-1, -1], grid[-1, :0:-1], grid[:0:-1, 0]])
    frame = Frame.around(ring)
    corners = (0, ni - 1, ni + nj - 2, 2 * ni + nj - 3)
    return BlockBoundary(ring=frame.to_unit(ring), corners=corners, frame=frame)


def _middle(points: np.ndarray) -> np.ndarray:
    """The point half way along a polyline."""
    return Polyline(points).at(np.array([0.5]))[0]


def block_lines(raws: Sequence[RawLine], grids: list[np.ndarray]) -> list[list[AuxLine]]:
    """Per block of ``grids`` (nj, ni, 2), the auxiliary lines ``raws`` (user (x, y)) whose
    middle point lies in it, mapped by SPEC 2 in the block's working frame; refused in one
    line naming the line: one in no block, and one that does not run from a side of its
    block to the opposite side (SPEC 2's checks, the block named by a point inside it)."""
    boundaries = [block_boundary(g) for g in grids]
    rings = [b.frame.to_user(b.ring) for b in boundaries]
    found: list[list[RawLine]] = [[] for _ in grids]
    for raw in raws:
        middle = _middle(raw.points)
        hits = [k for k, ring in enumerate(rings) if inside(middle[None], ring)[0]]
        if not hits:
            raise InputError(
                f"its middle point ({middle[0]:.4g}, {middle[1]:.4g}) lies in no block; an "
                "auxiliary line runs inside one block, from a side to the opposite side",
                raw.name,
            )
        found[hits[0]].append(raw)
    out = []
    for grid, boundary, mine in zip(grids, boundaries, found):
        try:
            out.append(map_lines(list(mine), boundary))
        except InputError as exc:
            x, y = grid[grid.shape[0] // 2, grid.shape[1] // 2]
            raise InputError(
                f"{exc.template} (in the block at ({x:.4g}, {y:.4g}); an auxiliary line "
                "runs inside one block, from a side to the opposite side)",
                exc.source,
            ) from None
    return out
