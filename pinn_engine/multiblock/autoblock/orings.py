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
from shapely.geometry.polygon import orient

from pinn_engine.geometry.boundary import turning_angles
from pinn_engine.multiblock.autoblock.corners import corner_points
from pinn_engine.multiblock.blocks import CORNER_TURN

RING_SHARE = 1.0  # the ring's thickness over the hole's half-size (a cylinder's box: 2 D wide)
GAP_SHARE = 0.45  # the most of the gap beyond a box side that the ring takes (two boxes facing
# each other across a gap leave a tenth of it between them)
SHRINKS = 6  # times the ring's thickness is halved to keep a box off a slanted wall
SPOKE_SNAP = 0.25  # a spoke ends on a sharp vertex of the hole this close (share of its half-size)
# a box side may lie on the straight wall beyond it where the ring there would be thinner
# than this share of its thickness elsewhere: the block between box and wall, thinner
# still, is left out and the ring blocks reach the wall (a square 0.25 above a floor)
WALL_SHARE = 0.5
WALL_TOL = 1e-6  # share of the gap: a side moved onto the wall lies on it within this
_SIDE_OF = (0, 2, 1, 3)  # the edge from box corner k - 1 to k: the -u, -v, +u, +v side


@dataclass
class ORing:
    """A hole's ``box`` (4, 2), counter-clockwise, and its eight ``edges``: the box's four
    sides and four spokes from the hole to the box's corners (and one from each sharp
    corner no spoke ends at); ``c_shaped``: the same box with C-shaped ring blocks beside
    a corner too sharp for its spoke to leave block corners (:func:`_beside_sharp_edges`),
    the search's other choice, or None."""

    box: np.ndarray
    edges: list[np.ndarray]
    c_shaped: list[np.ndarray] | None = None


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


def o_rings(hole: np.ndarray, others: list[np.ndarray], axes: np.ndarray) -> list[ORing]:
    """The rings the search tries round ``hole`` among the ``others`` (the outer ring first,
    then the other holes): the O-ring, and where a side of its box is near a straight wall
    the ring reaching that wall (:func:`o_ring` with ``walls``)."""
    free = o_ring(hole, others, axes)
    walled = o_ring(hole, others, axes, walls=True)
    return [free] if walled is None else [free, walled]


def o_ring(
    hole: np.ndarray, others: list[np.ndarray], axes: np.ndarray, walls: bool = False
) -> ORing | None:
    """The O-ring of ``hole`` among the ``others`` (the outer ring first, then the other
    holes). With ``walls``, a box side whose ring would be thinner than WALL_SHARE of its
    thickness elsewhere, a straight wall of the outer ring beyond it, lies on that wall, and
    the other sides take their gaps beyond them, not beside them; None where no side does."""
    local = hole @ axes.T
    lo, hi = local.min(axis=0), local.max(axis=0)
    half = 0.5 * float(np.max(hi - lo))
    obstacles = MultiLineString([np.vstack([r, r[:1]]) for r in others])
    box = np.array([lo, [hi[0], lo[1]], hi, [lo[0], hi[1]]])  # counter-clockwise, local
    margins, walled = [], []
    sides = ((3, 0), (1, 2), (0, 1), (2, 3))  # the -u, +u, -v, +v sides
    reach = float(np.ptp(np.vstack(others), axis=0).sum())  # farther than any obstacle
    for a, b in sides:
        side = box[[a, b]] @ axes
        if walls:
            gap = _gap_beyond(side, 0.5 * (lo + hi) @ axes, obstacles, reach)
        else:
            gap = LineString(side.tolist()).distance(obstacles)
        on_wall = walls and _wall_beyond(box[[a, b]], gap, local, others[0] @ axes.T)
        walled.append(on_wall and GAP_SHARE * gap < WALL_SHARE * RING_SHARE * half)
        margins.append(gap if walled[-1] else min(RING_SHARE * half, GAP_SHARE * gap))
    if walls and not any(walled):
        return None
    sign = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]])  # each corner's way out, per axis
    grow = sign * np.array([[margins[0], margins[2]], [margins[1], margins[2]],
                            [margins[1], margins[3]], [margins[0], margins[3]]])  # fmt: skip
    held = sign * np.array([[walled[0], walled[2]], [walled[1], walled[2]],
                            [walled[1], walled[3]], [walled[0], walled[3]]])  # fmt: skip
    free = np.where(held != 0, 0.0, grow)
    for _ in range(SHRINKS):  # a corner past a slanted wall: the ring thinner until inside
        if not Polygon((box + free) @ axes).intersects(obstacles):
            break
        free = 0.5 * free
    box = (box + np.where(held != 0, grow, free)) @ axes
    centre = 0.5 * (lo + hi) @ axes
    # a side on the wall is the wall's: no edge along it
    edges = [np.array([box[k - 1], box[k]]) for k in range(4) if not walled[_SIDE_OF[k]]]
    spokes = [np.array([_spoke_end(hole, centre, c, half), c]) for c in box]
    own = _corner_spokes(hole, box, spokes)
    beside = _beside_sharp_edges(spokes, own, hole, box, centre)
    c_shaped = None if beside is None else edges + beside + own
    return ORing(box, edges + spokes + own, c_shaped)


def _gap_beyond(side: np.ndarray, centre: np.ndarray, obstacles, reach: float) -> float:
    """The distance from the box ``side`` (2, 2) to the nearest of the ``obstacles`` in the
    strip it sweeps moving away from the ``centre`` (``reach`` far): the gap beyond it, not
    beside it (a square's sides beside a floor below it keep their full ring)."""
    along = side[1] - side[0]
    out = np.array([along[1], -along[0]]) / np.linalg.norm(along)
    if out @ (side[0] - centre) < 0:
        out = -out
    strip = Polygon(np.vstack([side, side[::-1] + reach * out]))
    beyond = obstacles.intersection(strip)
    return np.inf if beyond.is_empty else LineString(side.tolist()).distance(beyond)


def _wall_beyond(side: np.ndarray, gap: float, hole: np.ndarray, outer: np.ndarray) -> bool:
    """Whether the box ``side`` (2, 2), moved by ``gap`` away from the ``hole`` (both in the
    main axes' frame), lies along the ``outer`` ring's boundary over its whole length: a
    straight wall parallel to it."""
    if gap <= 0:
        return False
    along = side[1] - side[0]
    out = np.array([along[1], -along[0]]) / np.linalg.norm(along)
    if out @ (side[0] - hole.mean(axis=0)) < 0:
        out = -out
    moved = LineString((side + gap * out).tolist())
    wall = LineString(np.vstack([outer, outer[:1]]).tolist())
    return wall.buffer(WALL_TOL * gap).contains(moved)


def _beside_sharp_edges(
    spokes: list[np.ndarray],
    own: list[np.ndarray],
    hole: np.ndarray,
    box: np.ndarray,
    centre: np.ndarray,
) -> list[np.ndarray] | None:
    """The box corners' ``spokes`` less the two on either side of a spoke of ``own`` from a
    corner of the ``hole`` so sharp that its spoke leaves both of its angles flatter than a
    block corner (an airfoil's trailing edge: 171.7 degrees on each side); None where the
    hole has no such corner. That corner then lies inside the sides of the two ring blocks
    beside its spoke, as a C-grid's trailing edge lies inside its block's side; each of
    those blocks takes the box's corner beyond it, the spoke's end on the box and the other
    spoke's ends as its four corners (with both spokes it may have three). The spokes kept
    end where they divide the hole's perimeter, from the sharp corner, in the proportions
    their box corners divide the box's from the spoke's end, so each ring block's sides on
    the hole and on the box keep one ratio (a spoke from the centre of a thin hole meets it
    at a glancing angle, no block corner)."""
    turn = dict(zip(map(tuple, hole), np.abs(turning_angles(hole))))
    angle = [np.arctan2(*(s[1] - centre)[::-1]) for s in spokes]
    drop: set[int] = set()
    sharp = None
    for spoke in own:
        if 90.0 - 0.5 * turn.get(tuple(spoke[0]), 0.0) >= CORNER_TURN:
            continue  # its two angles are block corners
        a = np.arctan2(*(spoke[1] - centre)[::-1])
        ahead = [(b - a) % (2 * np.pi) for b in angle]
        drop.update({int(np.argmin(ahead)), int(np.argmax(ahead))})
        sharp = spoke
    if sharp is None:
        return None
    inner = orient(Polygon(hole)).exterior  # both counter-clockwise
    outer = orient(Polygon(box)).exterior
    start_in, start_out = inner.project(Point(sharp[0])), outer.project(Point(sharp[1]))
    kept = []
    for k, (_, corner) in enumerate(spokes):
        if k in drop:
            continue
        share = ((outer.project(Point(corner)) - start_out) % outer.length) / outer.length
        foot = inner.interpolate((start_in + share * inner.length) % inner.length)
        kept.append(np.array([np.array(foot.coords)[0], corner]))
    return kept


def _corner_spokes(hole: np.ndarray, box: np.ndarray, spokes: list[np.ndarray]) -> list:
    """A spoke from each sharp corner of ``hole`` that no spoke ends at, along the
    bisector of its angle outside the hole to the ``box``: a ring block's side on the
    hole then runs between two corners of its own, none inside it (a block corner at
    every sharp corner, SPEC 10). Where it would cross a box corner's spoke (a thin body
    turned in its box: the diagonal spoke meets its long side short of the corner), the
    two are one spoke, from the corner to the box corner: that spoke of ``spokes`` is
    moved there (unless its own end is a sharp corner, or the moved spoke would cross the
    hole or another spoke). A spoke that would cross the hole or another spoke is left
    out (the blocking is then refused)."""
    solid = Polygon(hole)
    frame = LineString(np.vstack([box, box[:1]]))
    size = float(np.linalg.norm(np.ptp(box, axis=0)))
    touch = 1e-12 * size  # a spoke this near another meets it
    ends = [s[0] for s in spokes]
    out: list[np.ndarray] = []
    turn = turning_angles(hole)
    for i in np.flatnonzero(np.abs(turn) >= CORNER_TURN):
        p = hole[i]
        if min(np.linalg.norm(e - p) for e in ends) <= touch:
            continue
        a, b = hole[i - 1] - p, hole[(i + 1) % len(hole)] - p
        bisector = a / np.linalg.norm(a) + b / np.linalg.norm(b)
        if np.linalg.norm(bisector) < 1e-9:  # a straight vertex: no corner
            continue
        bisector /= np.linalg.norm(bisector)
        step = 1e-6 * size
        if solid.contains(Point(p - step * bisector)) or not solid.contains(
            Point(p + step * bisector)
        ):
            bisector = -bisector  # the bisector that leaves the hole
        hit = frame.intersection(LineString([p, p - 2 * size * bisector]))
        points = np.array([g.coords[0] for g in getattr(hit, "geoms", [hit]) if not g.is_empty])
        if not len(points):
            continue
        end = points[np.argmin(np.linalg.norm(points - p, axis=1))]
        spoke = LineString([p, end])
        if _through(spoke, solid):
            continue
        met = _met(spoke, spokes + out, touch)
        if not met:
            out.append(np.array([p, end]))
        elif (
            len(met) == 1 and met[0] < len(spokes) and _moved(spokes, met[0], p, solid, out, touch)
        ):
            ends[met[0]] = p
    return out


def _through(line: LineString, solid: Polygon) -> bool:
    """Whether ``line`` crosses the hole ``solid`` or runs inside it."""
    return line.crosses(solid.exterior) or solid.contains(line.interpolate(0.5, normalized=True))


def _met(line: LineString, edges: list[np.ndarray], touch: float) -> list[int]:
    """The ``edges`` that ``line`` crosses or comes within ``touch`` of."""
    return [
        k
        for k, e in enumerate(edges)
        if line.crosses(o := LineString(e)) or line.distance(o) <= touch
    ]


def _moved(
    spokes: list[np.ndarray], k: int, p: np.ndarray, solid: Polygon, out: list, touch: float
) -> bool:
    """Whether box corner ``k``'s spoke was moved to start at the hole's sharp corner ``p``
    (``spokes`` changed in place): not where it ends at a sharp corner of its own, nor where
    the moved spoke would cross the hole or another spoke."""
    sharp = corner_points(np.asarray(solid.exterior.coords)[:-1])
    if len(sharp) and np.linalg.norm(sharp - spokes[k][0], axis=1).min() <= touch:
        return False
    moved = LineString([p, spokes[k][1]])
    rest = [e for j, e in enumerate(spokes + out) if j != k]
    if _through(moved, solid) or _met(moved, rest, touch):
        return False
    spokes[k] = np.array([p, spokes[k][1]])
    return True
