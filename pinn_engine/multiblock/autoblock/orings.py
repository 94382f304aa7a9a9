"""O-rings round holes (SPEC 13): a four-cornered box about each hole, cut from it by four
spokes, so that the hole is wrapped by four blocks whose grid lines leave it at right
angles; the box's corners then emit block edges like the boundary's reflex corners.

The box is aligned with the outer boundary's main directions (``main_axes``), as far from
the hole as the hole's own half-size and at most ``GAP_SHARE`` of the way to whatever lies
beyond each of its sides (the wall, another hole), so a body near a wall keeps a thin ring
there and a full one elsewhere.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from shapely.geometry import LineString, MultiLineString, Point, Polygon

from pinn_engine.multiblock.autoblock.corners import corner_points

RING_SHARE = 1.0  # the ring's thickness over the hole's half-size (a cylinder's box: 2 D wide)
GAP_SHARE = 0.45  # the most of the gap beyond a box side that the ring takes (two boxes facing
# each other across a gap leave a tenth of it between them)
SHRINKS = 6  # times the ring's thickness is halved to keep a box off a slanted wall
SPOKE_SNAP = 0.25  # a spoke ends on a sharp vertex of the hole this close (share of its half-size)


@dataclass
class ORing:
    """A hole's ``box`` (4, 2), counter-clockwise, and its eight ``edges``: the box's four
    sides and four spokes from the hole to the box's corners."""

    box: np.ndarray
    edges: list[np.ndarray]


def main_axes(outer: np.ndarray) -> np.ndarray:
    """The outer boundary's two main directions (2, 2) as rows: the length-weighted mean of
    its segments' directions modulo a quarter turn (the directions a cross field aligned
    with the boundary takes)."""
    d = np.roll(outer, -1, axis=0) - outer
    length = np.linalg.norm(d, axis=1)
    angle = np.angle(np.sum(length * np.exp(4j * np.arctan2(d[:, 1], d[:, 0])))) / 4.0
    u = np.array([np.cos(angle), np.sin(angle)])
    return np.array([u, [-u[1], u[0]]])


def _spoke_end(hole: np.ndarray, centre: np.ndarray, corner: np.ndarray, half: float):
    """Where the spoke from ``centre`` towards the box ``corner`` leaves the hole: a sharp
    vertex of the hole within SPOKE_SNAP of the hole's half-size, else the crossing."""
    ring = Polygon(hole).exterior
    far = centre + 4.0 * (corner - centre)
    hit = ring.intersection(LineString([centre, far]))
    points = np.array([g.coords[0] for g in getattr(hit, "geoms", [hit]) if not g.is_empty])
    if not len(points):
        points = np.array(ring.interpolate(ring.project(Point(corner))).coords)
    end = points[np.argmin(np.linalg.norm(points - corner, axis=1))]
    sharp = corner_points(hole)
    if len(sharp):
        near = np.linalg.norm(sharp - end, axis=1)
        if near.min() <= SPOKE_SNAP * half:
            return sharp[int(np.argmin(near))]
    return end


def o_ring(hole: np.ndarray, others: list[np.ndarray], axes: np.ndarray) -> ORing:
    """The O-ring of ``hole`` among the ``others`` (the outer ring and the other holes)."""
    local = hole @ axes.T
    lo, hi = local.min(axis=0), local.max(axis=0)
    half = 0.5 * float(np.max(hi - lo))
    obstacles = MultiLineString([np.vstack([r, r[:1]]) for r in others])
    box = np.array([lo, [hi[0], lo[1]], hi, [lo[0], hi[1]]])  # counter-clockwise, local
    margins = []
    for a, b in ((3, 0), (1, 2), (0, 1), (2, 3)):  # the -u, +u, -v, +v sides
        side = LineString((box[[a, b]] @ axes).tolist())
        margins.append(min(RING_SHARE * half, GAP_SHARE * side.distance(obstacles)))
    grow = np.array(
        [[-margins[0], -margins[2]], [margins[1], -margins[2]], [margins[1], margins[3]],
         [-margins[0], margins[3]]]
    )  # fmt: skip
    for _ in range(SHRINKS):  # a corner past a slanted wall: the ring thinner until inside
        if not Polygon((box + grow) @ axes).intersects(obstacles):
            break
        grow = 0.5 * grow
    box = (box + grow) @ axes
    centre = 0.5 * (lo + hi) @ axes
    edges = [np.array([box[k - 1], box[k]]) for k in range(4)]
    edges += [np.array([_spoke_end(hole, centre, c, half), c]) for c in box]
    return ORing(box, edges)
