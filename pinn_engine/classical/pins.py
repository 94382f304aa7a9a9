"""Sharp vertices inside a side as grid nodes (a grid covers exactly the domain drawn).

A four-sided grid's boundary nodes sit at the node parameters of its sides; a vertex where a
side turns by ``SHARP_TURN`` or more between two nodes would be cut off by the cell edge
joining them. Two steps tie each such vertex to a node, both by one assignment
(:func:`assign`: the vertices onto inner nodes, in order, with the least total move):

- :func:`pinned_boundary` reparametrizes each side, piecewise linearly in arc length
  between its sharp vertices, so that the uniform nodes of the start's lattice land on
  them: the start, the training and the guard all see them as nodes. The ends of the
  auxiliary lines followed are pinned with them, so that the grid line along a drawn line
  starts where the line does, not on a chord past a curved side;
- :func:`pin_sharp` moves the nodes of a grid of another size or distribution (a
  spacing's) onto them, only the nodes assigned (the spacing asked at the corners' walls
  stays), the move spread into the domain as TFI blends the sides.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

from pinn_engine.classical.tfi import tfi_of_sides
from pinn_engine.geometry.auxlines import AuxLine
from pinn_engine.geometry.boundary import (
    SHARP_TURN,
    SIDES,
    Boundary,
    Polyline,
    segment_distance,
    turning_angles,
)

# arc-length fraction within which a line's end is taken to be at a corner, a sharp vertex or
# another line's end (it shares their node): far below any lattice's node spacing
MERGED = 1e-6
# a line's end becomes a node where the cell edge between the nodes round it misses it by more
# than this share of the diagonal, a quarter of the 2e-3 at which a line counts as followed:
# pinning moves a node up to half a cell, which costs more than a smaller miss (fig2's line
# ends at 21 x 11, pinned: mean 1 degree higher)
END_MISS = 5e-4


def side_sharp_params(points: np.ndarray, t: np.ndarray) -> np.ndarray:
    """The arc-length parameters ``t`` of the inner vertices of an open polyline ``points``
    that turn by ``SHARP_TURN`` degrees or more."""
    if len(points) < 3:
        return np.empty(0)
    turn = turning_angles(points)[1:-1]  # the ends' wrap-around turns are not the side's
    return t[1:-1][np.abs(turn) >= SHARP_TURN]


def _running_min(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The least of ``values[: q + 1]`` for each q, and where it is."""
    where = np.zeros(len(values), dtype=int)
    for q in range(1, len(values)):
        where[q] = q if values[q] < values[where[q - 1]] else where[q - 1]
    return values[where], where


def assign(nodes: np.ndarray, vertices: np.ndarray) -> np.ndarray | None:
    """Indices (strictly increasing, inside ``1 .. len(nodes) - 2``) of the nodes moved onto
    ``vertices`` (sorted parameters) with the least total move |nodes[k] - vertex| such that
    the moved sequence stays strictly increasing; None where there is no such assignment
    (more sharp vertices than inner nodes between them). Dynamic programming over
    (vertex, node)."""
    n, m = len(nodes), len(vertices)
    if m == 0:
        return np.empty(0, dtype=int)
    k = np.arange(n)
    inner = (k >= 1) & (k <= n - 2)
    move = np.abs(nodes[None, :] - vertices[:, None])
    # an unmoved node k - 1 stays below vertex a; an unmoved node q + 1 above vertex a
    cost = np.full((m, n), np.inf)  # the least move of vertices 0..a with vertex a on node k
    back = np.zeros((m, n), dtype=int)
    cost[0] = np.where(inner & (nodes[np.maximum(k - 1, 0)] < vertices[0]), move[0], np.inf)
    for a in range(1, m):
        prev = cost[a - 1]
        # vertex a - 1 on node q < k - 1: node q + 1 unmoved, above it, and node k - 1 below a
        apart = np.where(nodes[np.minimum(k + 1, n - 1)] > vertices[a - 1], prev, np.inf)
        least, where = _running_min(apart)
        far = np.full(n, np.inf)
        far[2:] = least[:-2]
        far = np.where(nodes[np.maximum(k - 1, 0)] < vertices[a], far, np.inf)
        near = np.concatenate([[np.inf], prev[:-1]])  # vertex a - 1 on node k - 1
        take_near = near <= far
        cost[a] = np.where(inner, np.where(take_near, near, far) + move[a], np.inf)
        back[a] = np.where(take_near, k - 1, np.concatenate([[0, 0], where[:-2]]))
    above = (nodes[np.minimum(k + 1, n - 1)] > vertices[-1]) | (k == n - 2)
    last = np.where(above, cost[-1], np.inf)
    if not np.isfinite(last).any():
        return None
    picks = [int(np.argmin(last))]
    for a in range(m - 1, 0, -1):
        picks.append(int(back[a, picks[-1]]))
    return np.asarray(picks[::-1])


def _side_map(nodes: np.ndarray, vertices: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """Knots (nodes, moved nodes) of the piecewise-linear map of a side's parameter that
    takes its nodes onto its sharp vertices; None where nothing moves or no assignment
    exists."""
    picks = assign(nodes, vertices)
    if picks is None or not len(picks):
        return None
    moved = nodes.copy()
    moved[picks] = vertices
    if np.array_equal(moved, nodes):
        return None
    return nodes, moved


def _blend(params: np.ndarray, maps: dict[str, tuple[np.ndarray, np.ndarray]]) -> np.ndarray:
    """Parameters (..., 2) under each side's piecewise-linear map (``maps[side]``: its
    knots; identity where absent), blended across the domain as TFI blends the sides: on a
    side, its own map exactly."""

    def mapped(side: str, x: np.ndarray) -> np.ndarray:
        return np.interp(x, *maps[side]) if side in maps else x

    def blended(x: np.ndarray, s: np.ndarray, low: str, high: str) -> np.ndarray:
        """x moved by the two sides' moves blended along s: unmoved (bit for bit) where
        neither side moves it, and on a side (s 0 or 1) exactly that side's map."""
        at_low, at_high = mapped(low, x), mapped(high, x)
        inside = x + (1 - s) * (at_low - x) + s * (at_high - x)
        return np.where(s == 0, at_low, np.where(s == 1, at_high, inside))

    xi, eta = params[..., 0], params[..., 1]
    out = params.copy()  # a direction whose two sides keep their nodes keeps its parameter
    if "bottom" in maps or "top" in maps:
        out[..., 0] = blended(xi, eta, "bottom", "top")
    if "left" in maps or "right" in maps:
        out[..., 1] = blended(eta, xi, "left", "right")
    return out


def line_ends(lines: Sequence[AuxLine], side: str) -> np.ndarray:
    """The arc-length parameters on ``side`` where auxiliary ``lines`` (mapped on the
    arc-length sides, SPEC 2) end; lines given their own (xi, eta) have no mapped ends."""
    ends = []
    for line in lines:
        if line.sides is None:
            continue
        axis = 0 if line.sides[0] == "bottom" else 1  # the parameter along the end's side
        for end, name in ((line.xi_eta[0], line.sides[0]), (line.xi_eta[-1], line.sides[1])):
            if name == side:
                ends.append(float(end[axis]))
    return np.asarray(ends)


def _missed(
    line: Polyline, sharp: np.ndarray, nodes: np.ndarray, ends: np.ndarray, diagonal: float
) -> np.ndarray:
    """The ``ends`` (arc-length parameters) that the side's cell edge between the two nodes
    round each misses by more than ``END_MISS`` of the ``diagonal``, the side's ``nodes``
    placed with its ``sharp`` vertices pinned (a straight stretch misses none)."""
    arc, param = np.array([0.0, 1.0]), np.array([0.0, 1.0])
    picks = assign(nodes, sharp)
    if picks is not None and len(picks):
        arc, param = np.insert(arc, 1, sharp), np.insert(param, 1, nodes[picks])
    side = line.reparametrized(arc, param)
    out = []
    for t in ends:
        q = np.interp(t, arc, param)  # the end's parameter on the side so placed
        k = int(np.clip(np.searchsorted(nodes, q, side="right") - 1, 0, len(nodes) - 2))
        chord = side.at(nodes[k : k + 2])
        if segment_distance(line.at(np.array([t])), chord, closed=False)[0] > END_MISS * diagonal:
            out.append(t)
    return np.asarray(out)


def _side_vertices(
    line: Polyline, ends: np.ndarray, nodes: np.ndarray, diagonal: float
) -> list[np.ndarray]:
    """The parameters a side's nodes should sit on, the most wanted first: its sharp vertices
    with the auxiliary lines' ``ends`` that a cell edge would miss (:func:`_missed`; apart
    from them and from the corners by at least ``MERGED``), then the sharp vertices alone."""
    sharp = side_sharp_params(line.points, line.t)
    anchors = np.concatenate([[0.0, 1.0], sharp])
    far = [t for t in np.unique(ends) if np.abs(anchors - t).min() > MERGED]
    far = [t for k, t in enumerate(far) if k == 0 or t - far[k - 1] > MERGED]
    far = list(_missed(line, sharp, nodes, np.asarray(far), diagonal)) if far else []
    return [np.sort(np.concatenate([sharp, far])), sharp] if far else [sharp]


def pinned_boundary(
    boundary: Boundary, ni: int, nj: int, lines: Sequence[AuxLine] = ()
) -> Boundary:
    """``boundary`` with each side whose sharp inner vertices, and the ends of auxiliary
    ``lines`` on it, are not all at uniform nodes of an ``ni`` x ``nj`` lattice
    reparametrized so that they are (``Boundary.knots``): a cell edge then neither cuts a
    corner off nor misses where a drawn line meets a curved side. Where the ends leave no
    assignment (more of them than nodes) only the sharp vertices are pinned; ``boundary``
    itself where nothing moves."""
    knots = []
    for side in SIDES:
        line = boundary.arc_side(side)
        nodes = np.linspace(0.0, 1.0, ni if side in ("bottom", "top") else nj)
        for vertices in _side_vertices(line, line_ends(lines, side), nodes, boundary.diagonal):
            picks = assign(nodes, vertices)
            if picks is not None:
                break
        if picks is None or np.array_equal(nodes[picks], vertices):
            continue
        ends = np.array([0.0, 1.0])
        knots.append((side, np.insert(ends, 1, vertices), np.insert(ends, 1, nodes[picks])))
    return dataclasses.replace(boundary, knots=tuple(knots)) if knots else boundary


def pinned_lines(lines: Sequence[AuxLine], boundary: Boundary) -> list[AuxLine]:
    """Auxiliary lines mapped on the arc-length sides, their (xi, eta) on ``boundary``'s
    reparametrized sides (:func:`pinned_boundary`): an end on a side keeps its point, on a
    node where the side was pinned with the lines."""
    if not boundary.knots:
        return list(lines)
    maps = {side: (arc, param) for side, arc, param in boundary.knots}
    return [dataclasses.replace(line, xi_eta=_blend(line.xi_eta, maps)) for line in lines]


def pin_sharp(boundary: Boundary, params: np.ndarray) -> np.ndarray:
    """Node parameters ``params`` (nj, ni, 2) with a node of each side on each of its sharp
    inner vertices (where :func:`assign` finds one); ``params`` itself where no node
    moves."""
    rows = {
        "bottom": params[0, :, 0],
        "top": params[-1, :, 0],
        "left": params[:, 0, 1],
        "right": params[:, -1, 1],
    }
    maps = {}
    for side, nodes in rows.items():
        line = boundary.side(side)
        found = _side_map(nodes, side_sharp_params(line.points, line.t))
        if found is not None:
            maps[side] = found
    return _blend(params, maps) if maps else params


def placed_on_boundary(grid: np.ndarray, boundary: Boundary) -> np.ndarray:
    """``grid`` (nj, ni, 2, working frame) with its boundary rows on ``boundary``: each node
    at the closest point of its own side (a side's parameters kept in order, its ends on the
    corners), the nodes nearest each sharp vertex on it (:func:`pin_sharp`); the interior
    moved by the TFI of the boundary nodes' moves, so the rows next to the sides move with
    them. A grid of the soft boundary mode, whose network only approaches the sides, so
    covers exactly the domain drawn."""
    nj, ni = grid.shape[:2]
    rows = {
        "bottom": (np.s_[0, :], 0),
        "top": (np.s_[-1, :], 0),
        "left": (np.s_[:, 0], 1),
        "right": (np.s_[:, -1], 1),
    }
    params = np.stack(np.meshgrid(np.linspace(0, 1, ni), np.linspace(0, 1, nj)), axis=-1)
    for side, (row, axis) in rows.items():
        line = boundary.side(side)
        t = np.array([line.project(p)[0] for p in grid[row]])
        t = np.maximum.accumulate(np.clip(t, 0.0, 1.0))
        t[0], t[-1] = 0.0, 1.0
        params[row + (axis,)] = t
    params = pin_sharp(boundary, params)
    placed = grid.copy()
    for side, (row, axis) in rows.items():
        placed[row] = boundary.side(side).at(params[row + (axis,)])
    move = placed - grid
    out = grid + tfi_of_sides(move[0], move[:, -1], move[-1], move[:, 0])
    for row, _ in rows.values():  # the sides exactly where placed
        out[row] = placed[row]
    return out
