"""The rule every written 2D grid keeps: it covers exactly the domain drawn.

:func:`check_cover` runs on every job's grid before any route sees it (``job.run``), so no
route writes a grid that breaks it: every sharp corner of the drawn boundary is a grid node,
every boundary node lies on the drawn boundary (a body's wall within SPEC 9's tolerance), and
the cells cover the region the boundary nodes enclose once, with no overlap between blocks
and nothing outside; and (:func:`unfolded`, after any adaptation) no cell is folded. A grid
that breaks it is refused in one line that names the fix. The area test runs on fold-free
grids, where it measures overlaps and gaps alone.
"""

from __future__ import annotations

import numpy as np

from pinn_engine.blocks3d.checks import SKEW_LIMIT, cell_areas, planar_figures
from pinn_engine.errors import InputError, folded_cells_refusal
from pinn_engine.geometry.boundary import (
    SHARP_TURN,
    segment_distance,
    segment_feet,
    signed_area,
    turning_angles,
)
from pinn_engine.multiblock.walls import first_edges_refusal

# A node is on the drawn boundary, or at a corner, within this share of the domain's
# diagonal: the nodes are placed there exactly, so only rounding separates them
NODE_TOL = 1e-7
# A body's wall follows a smooth interpolant through the file's points, no node farther
# than this share of the chord from the drawn polyline (SPEC 9)
WALL_TOL = 1e-3
# A body's corner node may sit this share of the chord off the drawn corner: a trailing-edge
# gap of at most 1e-4 chord is closed at its mean point (SPEC 9)
BODY_CORNER_TOL = 1e-4
# ... or within this share of its largest coordinate: the rounding that coordinates far from
# the origin carry (a domain 1e-6 wide at 1e5: 2e-11 a coordinate), sixteen-fold
ROUNDING = 16 * np.finfo(float).eps
# The cells' area may differ from the area the boundary nodes enclose by this share (the
# rounding of summing many cells' areas)
AREA_TOL = 1e-7
# A drawn line is an instruction: the default four-sided grid's line through it (SPEC 2's
# measure) keeps within this share of the diagonal, a tenth of a cell of a 41 x 21 grid
LINE_TOL = 2e-3
# The fix of a multi-block grid whose first edges miss the spacing asked: the lines leaving
# the wall there are too short, or their nodes too few, to start with it
EDGES_FIX = (
    "a smaller first edge in {spacing} or a finer {cell_size}, or draw the block edges and {blocks}"
)


def _perimeter(grid: np.ndarray) -> np.ndarray:
    """The nodes on a grid's four sides."""
    return np.vstack([grid[0], grid[-1], grid[:, 0], grid[:, -1]])


def _arc_positions(points: np.ndarray, ring: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each point's arc position along the closed ``ring`` at its nearest place, and its
    distance there."""
    a, b = ring, np.roll(ring, -1, axis=0)
    ab = b - a
    length = np.linalg.norm(ab, axis=1)
    start = np.concatenate([[0.0], np.cumsum(length)[:-1]])
    ab2 = np.maximum(length**2, 1e-300)
    s, d = np.empty(len(points)), np.empty(len(points))
    for k in range(0, len(points), 256):
        u, dist = segment_feet(points[k : k + 256], a, ab, ab2)
        near = dist.argmin(axis=1)
        rows = np.arange(len(near))
        s[k : k + 256] = start[near] + u[rows, near] * length[near]
        d[k : k + 256] = dist[rows, near]
    return s, d


def sharp_corners(ring: np.ndarray, turn: float = SHARP_TURN) -> np.ndarray:
    """The vertices of a closed ``ring`` (either orientation) where it turns by ``turn``
    degrees or more."""
    return ring[np.abs(turning_angles(ring)) >= turn]


def _missed_corner(nodes: np.ndarray, corners: np.ndarray, tol: float) -> np.ndarray | None:
    """The first of ``corners`` with no node within ``tol``, or None."""
    for corner in corners:  # a few corners: one pass over the nodes each
        if np.linalg.norm(nodes - corner, axis=1).min() > tol:
            return corner
    return None


def check_blocks_cover(
    grids: list[np.ndarray], rings: list[np.ndarray], source: str, fix: str
) -> dict:
    """Refuse a multi-block grid (blocks (nj, ni, 2)) that does not cover the domain of
    ``rings`` (outer boundary first, then holes) exactly; ``fix`` ends the refusal. Returns
    the figures of the report's ``domain`` entry."""
    rings = [np.asarray(r, dtype=float)[:, :2] for r in rings]
    diagonal = float(np.linalg.norm(np.ptp(rings[0], axis=0)))
    tol = max(NODE_TOL * diagonal, ROUNDING * float(np.abs(np.vstack(rings)).max()))
    # areas from coordinates relative to the domain (sums of products of large coordinates
    # far from the origin would cancel); equal coordinates stay equal
    origin = rings[0].min(axis=0)
    rings = [r - origin for r in rings]
    grids = [g[..., :2] - origin for g in grids]
    nodes = np.vstack([g.reshape(-1, 2) for g in grids])
    corners = np.vstack([sharp_corners(r) for r in rings])
    missed = _missed_corner(nodes, corners, tol)
    if missed is not None:
        missed = missed + origin
        raise InputError(
            f"the grid does not cover the domain drawn: its sharp corner at "
            f"({missed[0]:.6g}, {missed[1]:.6g}) is no grid node; {fix}",
            source,
        )
    perimeter = np.vstack([_perimeter(g) for g in grids])
    enclosed = 0.0
    for k, ring in enumerate(rings):
        s, d = _arc_positions(perimeter, ring)
        on = d <= tol
        ring_nodes = perimeter[on][np.unique(np.round(s[on] / tol), return_index=True)[1]]
        if len(ring_nodes) < 3:
            raise InputError(
                f"the grid does not cover the domain drawn: no grid side runs along "
                f"{'its outer boundary' if k == 0 else f'hole {k}'}; {fix}",
                source,
            )
        area = abs(signed_area(ring_nodes))
        enclosed += area if k == 0 else -area
    areas = [cell_areas(g) for g in grids]
    cells = float(sum(np.abs(a).sum() for a in areas))
    folded = any((np.sign(a) != np.sign(a.sum())).any() for a in areas)
    domain = abs(signed_area(rings[0])) - sum(abs(signed_area(r)) for r in rings[1:])
    if not folded and abs(cells - enclosed) > AREA_TOL * abs(domain):
        more = "more" if cells > enclosed else "less"
        raise InputError(
            f"the grid does not cover the domain drawn: its cells cover "
            f"{abs(cells - enclosed) / abs(domain):.2g} of its area {more} than the boundary "
            f"encloses (blocks overlap or leave a gap); {fix}",
            source,
        )
    return {
        "area": domain,
        "cells_area": cells,
        "sharp_corners": len(corners),
    }


def check_blocks_skewness(grids: list[np.ndarray], source: str, fix: str) -> dict:
    """Refuse a multi-block grid (blocks (nj, ni, 2)) with a face that OpenFOAM's checkMesh
    finds skewed beyond ``SKEW_LIMIT`` (a multi-block grid with such a face fails checkMesh,
    so it is not written), measured as checkMesh measures it (``checks.planar_figures``; a
    cell squeezed to a near-180-degree corner beside a thin wall row has such a face);
    ``fix`` ends the refusal. Returns the figures of the report's ``checkmesh`` entry."""
    found = planar_figures(grids)
    if found.max_skewness > SKEW_LIMIT:
        raise InputError(
            f"the grid is not written: a face is skewed {found.max_skewness:.3g} (checkMesh's "
            f"limit {SKEW_LIMIT:g}), a cell squeezed beside a thin row; {fix}",
            source,
        )
    return {
        "max_skewness": found.max_skewness,
        "max_non_orthogonality": found.max_non_orthogonality,
    }


def check_body_cover(
    grid: np.ndarray,
    surface: np.ndarray,
    edge: np.ndarray,
    chord: float,
    wall: slice,
    source: str,
    fix: str,
) -> dict:
    """Refuse a body grid whose wall (``grid[0][wall]``) misses a corner of the trailing
    ``edge`` (its points: a sharp edge's one, a base's two), or has a node farther than
    ``WALL_TOL`` chord from the body's closed polyline ``surface`` (the wall is a spline
    through every point of the file: where it rounds a corner off, or swings between
    sparse points, its nodes leave the polyline); ``fix`` ends the refusal. Returns the
    figures of the report's ``domain`` entry."""
    ring = np.asarray(surface, dtype=float)[:, :2]
    if np.allclose(ring[0], ring[-1]):
        ring = ring[:-1]
    nodes = grid[0][wall]
    missed = _missed_corner(nodes, np.asarray(edge, dtype=float), BODY_CORNER_TOL * chord)
    if missed is not None:
        raise InputError(
            f"the grid does not cover the body drawn: its trailing-edge corner at "
            f"({missed[0]:.6g}, {missed[1]:.6g}) is no wall node; {fix}",
            source,
        )
    off = segment_distance(nodes, ring) / chord
    worst = int(np.argmax(off))
    if off[worst] > WALL_TOL:
        x, y = nodes[worst]
        raise InputError(
            f"the grid's wall leaves the body drawn by {off[worst]:.2g} chord at "
            f"({x:.6g}, {y:.6g}) (at most {WALL_TOL:g}); {fix}",
            source,
        )
    deviation = float(off.max())
    return {"wall_deviation": deviation, "sharp_corners": len(edge)}


def unfolded(outcome):
    """``outcome`` (a ``job.Outcome`` of a 2D domain) if no cell of its grid is folded;
    refused (``InputError``, the fix in the route's words) otherwise."""
    refusal = folded_cells_refusal(outcome.report, outcome.report.get("source"))
    if refusal is not None:
        raise refusal
    return outcome


def followed(outcome, settings):
    """``outcome`` (a four-sided ``job.Outcome``) if its grid follows every auxiliary line
    within ``LINE_TOL`` where the default promises it (``settings.objective`` best, taking
    the quality objective's line-following start); refused (``InputError``) otherwise."""
    if not (settings.objective == "best" and settings.quality_objective):
        return outcome
    distances = outcome.report.get("aux_line_distance") or {}
    missed = {name: d for name, d in distances.items() if d > LINE_TOL}
    if not missed:
        return outcome
    name, distance = max(missed.items(), key=lambda item: item[1])
    raise InputError(
        f"the grid is not written: it follows auxiliary line {name} only to {distance:.1e} "
        f"of the diagonal ({LINE_TOL:g} asked) without folding; try a line the grid lines "
        "can reach (one that stays clear of the boundary's notches and steps), or "
        "{method:elliptic} to mesh without following the lines",
        outcome.report.get("source"),
    )


def covered(outcome, geometry):
    """``outcome`` (a ``job.Outcome`` of a 2D domain: four-sided, multi-block or a body)
    once its grid is checked to cover ``geometry``'s domain, the figures in its report's
    ``domain``; refused (``InputError``) otherwise."""
    if outcome.kind == "four-sided":
        # a side's sharp vertices are nodes where its nodes allow (pins.pin_sharp): more
        # sharp vertices close together than nodes between them need more nodes
        fix = "a larger {size} (a node for each sharp corner along a side)"
        boundary = geometry.boundary
        ring = boundary.frame.to_user(boundary.ring)
        figures = check_blocks_cover(outcome.grids, [ring], boundary.source, fix)
    elif outcome.kind == "blocks":
        fix = "draw the block edges (a block corner at every sharp corner) and {blocks}"
        figures = check_blocks_cover(outcome.grids, geometry.rings, geometry.source, fix)
        if not outcome.report["quality"]["folded_cells"]:  # a fold is refused as such
            walls = geometry.walls
            spaced = walls is not None and (walls.spacing or walls.sides)
            fix = (
                "draw the block edges (a block corner at every reflex corner, on both "
                "sides) and {blocks}"
            )
            fix = f"a larger first edge in {{spacing}}, or {fix}" if spaced else fix
            outcome.report["checkmesh"] = check_blocks_skewness(outcome.grids, geometry.source, fix)
            off = first_edges_refusal(outcome.report)
            if off is not None:
                raise InputError(
                    f"the grid is not written: {off} (SPEC 7); {EDGES_FIX}", geometry.source
                )
    elif outcome.kind == "body":
        body, grid = geometry.body, outcome.grids[0]
        n_wake = outcome.report["topology"]["wake_nodes"]
        wall = slice(0, grid.shape[1]) if n_wake == 0 else slice(n_wake, grid.shape[1] - n_wake)
        edge = body.surface[:1] if body.sharp else body.surface[[0, -1]]
        fix = "give the file more points where the wall bends most"
        figures = check_body_cover(grid, body.ring(), edge, body.chord, wall, body.source, fix)
    else:
        return outcome
    outcome.report["domain"] = figures
    return outcome
