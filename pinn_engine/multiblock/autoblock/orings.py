"""O-rings round holes (SPEC 13): a four-cornered box about each hole, cut from it by four
spokes, so that the hole is wrapped by four blocks whose grid lines leave it at right
angles; the box's corners then emit block edges like the boundary's reflex corners.

The box is aligned with the outer boundary's main directions (``main_axes``), as far from
the hole as the hole's own half-size and at most ``GAP_SHARE`` of the way to whatever lies
beyond each of its sides (the wall, another hole), so a body near a wall keeps a thin ring
there and a full one elsewhere. Holes so close that their boxes would crowd each other (a
slat before its main element, two squares side by side) may share one box instead, cut
midway across each gap, the gap a block of its own (``group_ring``).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import LineString, MultiLineString, Point, Polygon
from shapely.geometry.polygon import orient

from pinn_engine.geometry.boundary import turning_angles
from pinn_engine.multiblock.autoblock.corners import corner_points
from pinn_engine.multiblock.autoblock.faces import NoBlocking, faces_of, layout_cost
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
# holes whose boxes leave less than this share of the gap between the holes free (boxes
# facing each other across a gap leave a tenth) may share one box, cut between them
GROUP_SHARE = 0.5
SEPARATING_TURN = 80.0  # degrees a cut between grouped holes may turn from across the box
# a cut's gap is weighed by the cosine of its turn to this power: a cut square to the box
# unless turning widens the gap much (a flap tucked under a main element's trailing edge)
TURN_POWER = 16
CUT_ENDS = ("fitted", "none", "all")  # the spokes to the cuts' ends the search tries
FACING = 2.0  # a hole faces a cut where it is within this many times its nearest distance
FACING_STEP = 0.25  # the outline is measured every this many times that nearest distance


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


def ring_forms(rings: list[np.ndarray], axes: np.ndarray) -> list[list[ORing]]:
    """Every set of rings the search tries round the holes ``rings[1:]`` (``rings[0]`` the
    outer ring): each hole's :func:`o_rings`, and where holes stand so close that their
    boxes take more than GROUP_SHARE of the gap between them (a slat, a main element and
    a flap), one box round the group (:func:`group_ring`), the only one where their boxes
    overlap."""
    holes = rings[1:]
    singles = [o_rings(h, rings[:k] + rings[k + 1 :], axes) for k, h in enumerate(holes, 1)]
    boxes = [Polygon(s[0].box) for s in singles]
    solids = [Polygon(h) for h in holes]
    group = list(range(len(holes)))  # each hole's group: the least index joined to it
    overlap = set()
    for i, j in itertools.combinations(range(len(holes)), 2):
        between = boxes[i].distance(boxes[j])
        if between < GROUP_SHARE * solids[i].distance(solids[j]):
            old, new = max(group[i], group[j]), min(group[i], group[j])
            group = [new if g == old else g for g in group]
            overlap.update({i, j} if between == 0.0 else set())
    units = []
    for g in sorted(set(group)):
        members = [k for k in range(len(holes)) if group[k] == g]
        separate = [list(c) for c in itertools.product(*[singles[k] for k in members])]
        if len(members) == 1:
            units.append(separate)
            continue
        outside = [rings[0]] + [h for k, h in enumerate(holes) if group[k] != g]
        joined: list[ORing] = []
        for ends in CUT_ENDS:
            ring = group_ring([holes[k] for k in members], outside, axes, ends)
            if ring is not None and not any(_same(ring, other) for other in joined):
                joined.append(ring)
        apart = not overlap.intersection(members)
        units.append([[j] for j in joined] + separate * apart or separate)
    return [sum(choice, []) for choice in itertools.product(*units)]


def _same(a: ORing, b: ORing) -> bool:
    """Whether rings ``a`` and ``b`` have the same edges in both forms."""
    return all(
        x is y
        or (
            x is not None
            and y is not None
            and len(x) == len(y)
            and all(np.array_equal(e, f) for e, f in zip(x, y))
        )  # fmt: skip
        for x, y in ((a.edges, b.edges), (a.c_shaped, b.c_shaped))
    )


def group_ring(
    holes: list[np.ndarray], others: list[np.ndarray], axes: np.ndarray, ends: str = "fitted"
) -> ORing | None:
    """One ring round ``holes`` among the ``others`` (the outer ring first): the box
    :func:`o_ring` puts round all their points, cut between each hole and the next along
    the box's longer axis by a line that leaves them apart (:func:`_separating`), each
    hole cut from its own part of the box by spokes (:func:`_part_spokes`, with ``ends``)
    to the part's corners and to the ends of its stretch facing each cut (:func:`_facing`),
    so that the gap between two holes is a block of its own, split by the cut; the
    C-shaped form: each hole in its C-shaped form where it has one.
    None where no line leaves two neighbours apart or a part holds no whole hole."""
    box, _ = _box(np.vstack(holes), others, axes)
    frame = Polygon(box)
    along = axes[int(np.argmax(np.ptp(box @ axes.T, axis=0)))]
    order = sorted(range(len(holes)), key=lambda k: float(_centre(holes[k], axes) @ along))
    reach = 2.0 * float(np.linalg.norm(np.ptp(box, axis=0)))  # beyond the box every way
    edges = [np.array([box[k - 1], box[k]]) for k in range(4)]
    parts, cuts, lines = [], [], []
    rest = frame
    for a, b in zip(order, order[1:]):
        cut = _separating(holes[a], holes[b], along)
        if cut is None:
            return None
        middle, normal = cut
        lines.append(cut)
        side = np.array([-normal[1], normal[0]])
        behind = Polygon([middle + reach * (side - normal), middle + reach * side,
                          middle - reach * side, middle - reach * (side + normal)])  # fmt: skip
        parts.append(rest.intersection(behind))
        rest = rest.difference(behind)
        cuts.append(np.asarray(frame.intersection(LineString(behind.exterior.coords[1:3])).coords))
    parts.append(rest)
    if any(c.crosses(LineString(d)) for c, d in itertools.combinations(map(LineString, cuts), 2)):
        return None
    o_form, c_form, shaped = [], [], False
    for j, (k, part) in enumerate(zip(order, parts)):
        if not isinstance(part, Polygon) or not part.contains(Polygon(holes[k])):
            return None
        corners = np.asarray(orient(part.simplify(0.0)).exterior.coords)[:-1]
        facing = [p for m, n in lines[max(j - 1, 0) : j + 1] for p in _facing(holes[k], m, n)]
        spokes, c_spokes = _part_spokes(holes[k], corners, box, facing, axes, ends)
        o_form += spokes
        c_form += spokes if c_spokes is None else c_spokes
        shaped |= c_spokes is not None
    edges += cuts
    return ORing(box, edges + o_form, edges + c_form if shaped else None)


def _part_spokes(
    hole: np.ndarray,
    corners: np.ndarray,
    box: np.ndarray,
    facing: list,
    axes: np.ndarray,
    ends: str,
) -> tuple[list[np.ndarray], list[np.ndarray] | None]:
    """:func:`_spoked` for a ``hole`` in its part (``corners``) of a group's ``box``: spokes
    to the ``facing`` points (inserted on the cuts) and to the box's corners, and (``ends``)
    to the cuts' ends on the box: "none", "all", or "fitted": where the ring blocks beside
    them would otherwise not all have four corners (a round hole's arc turns there; a
    square's side runs on straight). A C-shaped form whose spokes, moved along the hole,
    cross it is none."""
    outline = _inserted(corners, facing)
    own = [c for c in corners if np.isclose(box, c).all(axis=1).any()]
    centre, half = _centre(hole, axes), _half(hole, axes)
    tried = []
    for targets in {"none": [own], "all": [list(corners)], "fitted": [own, list(corners)]}[ends]:
        spokes, c_spokes = _spoked(hole, outline, centre, half, np.array(targets + facing))
        if c_spokes is not None:
            try:
                faces_of([outline, hole], c_spokes)
            except NoBlocking:
                c_spokes = None
        tried.append((spokes, c_spokes))
        try:
            layout_cost([outline, hole], spokes)
        except NoBlocking:
            continue
        return spokes, c_spokes
    return tried[0]


def _facing(hole: np.ndarray, middle: np.ndarray, normal: np.ndarray) -> list[np.ndarray]:
    """The two ends, seen square across the cut through ``middle`` across ``normal``, of
    the stretch of ``hole`` that faces it (its points within FACING times its nearest
    distance to the cut): the corners of the hole's half of the block across the gap."""
    side = np.array([-normal[1], normal[0]])
    nearest = float(np.abs((hole - middle) @ normal).min())
    outline = shapely.segmentize(Polygon(hole).exterior, FACING_STEP * nearest)
    points = np.asarray(outline.coords)
    away = np.abs((points - middle) @ normal)
    near = (points - middle)[away <= FACING * nearest] @ side
    return [middle + near.min() * side, middle + near.max() * side]


def _inserted(corners: np.ndarray, points: list[np.ndarray]) -> np.ndarray:
    """The polygon ``corners`` with each of ``points`` (on its outline) inserted as a
    vertex of the side it lies on, unless it is one already."""
    out = list(corners)
    for point in points:
        if np.isclose(np.array(out), point).all(axis=1).any():
            continue
        ring = np.array(out)
        gaps = [LineString([ring[i - 1], ring[i]]).distance(Point(point)) for i in range(len(out))]
        out.insert(int(np.argmin(gaps)), point)
    return np.array(out)


def _separating(a: np.ndarray, b: np.ndarray, along: np.ndarray) -> tuple | None:
    """The line between holes ``a`` and ``b`` (``a`` first along ``along``) as (a point,
    its unit normal towards ``b``): of the lines that leave the two apart, turned at most
    SEPARATING_TURN from across ``along`` (one a degree), the one whose gap times the
    cosine of its turn to TURN_POWER is widest (a wide gap, a cut near square to the box),
    midway across the gap; None where no such line leaves them apart."""
    best, found = 0.0, None
    for turn in np.radians(np.arange(-SEPARATING_TURN, SEPARATING_TURN + 1.0)):
        c, s = np.cos(turn), np.sin(turn)
        normal = np.array([c * along[0] - s * along[1], s * along[0] + c * along[1]])
        gap = (b @ normal).min() - (a @ normal).max()
        if gap * c**TURN_POWER > best:
            middle = 0.5 * ((b @ normal).min() + (a @ normal).max())
            best, found = gap * c**TURN_POWER, (middle * normal, normal)
    return found


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
    framed = _box(hole, others, axes, walls)
    if framed is None:
        return None
    box, walled = framed
    # a side on the wall is the wall's: no edge along it
    edges = [np.array([box[k - 1], box[k]]) for k in range(4) if not walled[_SIDE_OF[k]]]
    o_form, c_form = _spoked(hole, box, _centre(hole, axes), _half(hole, axes))
    return ORing(box, edges + o_form, None if c_form is None else edges + c_form)


def _centre(points: np.ndarray, axes: np.ndarray) -> np.ndarray:
    """The middle of ``points``' extent along the main ``axes``."""
    local = points @ axes.T
    return 0.5 * (local.min(axis=0) + local.max(axis=0)) @ axes


def _half(points: np.ndarray, axes: np.ndarray) -> float:
    """Half the larger of ``points``' extents along the main ``axes``."""
    return 0.5 * float(np.ptp(points @ axes.T, axis=0).max())


def _box(
    hole: np.ndarray, others: list[np.ndarray], axes: np.ndarray, walls: bool = False
) -> tuple[np.ndarray, list[bool]] | None:
    """The box (4, 2), counter-clockwise, that :func:`o_ring` puts round the points
    ``hole`` among the ``others``, and which of its -u, +u, -v, +v sides lie on a wall;
    None where ``walls`` asks sides on a wall and none is."""
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
    return (box + np.where(held != 0, grow, free)) @ axes, walled


def _spoked(
    hole: np.ndarray,
    box: np.ndarray,
    centre: np.ndarray,
    half: float,
    targets: np.ndarray | None = None,
) -> tuple[list[np.ndarray], list[np.ndarray] | None]:
    """The spokes that cut ``hole`` from its ``box`` (from the hole's ``centre`` towards the
    box's corners, or the ``targets`` among them, onto a sharp vertex within SPOKE_SNAP of
    its ``half``-size, and one from each sharp corner no spoke ends at), and the C-shaped
    form's spokes (None where the hole has no corner too sharp for its spoke to leave block
    corners)."""
    ends = box if targets is None else targets
    spokes = [np.array([_spoke_end(hole, centre, c, half), c]) for c in ends]
    own = _corner_spokes(hole, box, spokes)
    beside = _beside_sharp_edges(spokes, own, hole, box, centre)
    return spokes + own, None if beside is None else beside + own


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
