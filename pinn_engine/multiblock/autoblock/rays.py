"""Block edges from reflex vertices (SPEC 13): each reflex vertex emits one straight edge,
a cross field's separatrix, in one of a few directions, traced as in a motorcycle graph.

The directions are those of a cross field aligned with either side at the vertex: each side
carried on (a 270-degree corner's two separatrices) and each side's normal (a Y's mouth),
and those of a smooth cross field, which splits the interior angle evenly into about right
angles (a tilted tee's branch corners); those leaving less than ``MIN_SPLIT`` of the
interior angle on one side are dropped.
Edges are placed shortest first, each stopping where it meets the boundary or an edge placed
before it; an end near a corner of the boundary or another edge's start goes onto it, so no
sliver of a block is left between them.
"""

from __future__ import annotations

import numpy as np

from pinn_engine.multiblock.autoblock.corners import Reflex

# degrees of the interior angle a direction leaves on each side, at least: a block corner
# sharper than the sharpest a block may have on the boundary's side (150 degrees' turn);
# a steep tee's branch wall carried on leaves 90 less its lean (30 at 60 degrees)
MIN_SPLIT = 30.0
# degrees each corner beside a wall carried on must have, at least, where a wall spacing
# asks both continuations (``layered``): a 270-degree corner's (90), not a Y's 210-degree
# mouth's (30), whose walls' layers bend round it within a block
PAIR_SPLIT = 45.0
SAME_DIRECTION = 10.0  # degrees: directions closer than this are one
END_SNAP = 0.15  # an end goes onto a corner or edge start this close (share of its length)
NEAR_ZERO = 1e-9  # share of the diagonal below which a hit is the ray's own start


def _left(d: np.ndarray) -> np.ndarray:
    return np.array([-d[1], d[0]])


def _ccw(frm: np.ndarray, to: np.ndarray) -> float:
    """The counter-clockwise angle in degrees from direction ``frm`` to ``to``, in [0, 360)."""
    a = np.degrees(np.arctan2(to[1], to[0]) - np.arctan2(frm[1], frm[0]))
    return float(a % 360.0)


def _turned(d: np.ndarray, degrees: float) -> np.ndarray:
    """``d`` turned counter-clockwise by ``degrees``."""
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    return np.array([c * d[0] - s * d[1], s * d[0] + c * d[1]])


def separatrices(vertex: Reflex) -> list[np.ndarray]:
    """The separatrices of a smooth cross field at ``vertex``: its interior angle split
    evenly into the number of right angles nearest it, so each block corner there comes
    as close to 90 degrees as the angle allows (a 270-degree corner: its two sides carried
    on; a tee's 245-degree corner: two lines 81.7 degrees apart)."""
    parts = max(int(round(vertex.angle / 90.0)), 1)
    return [_turned(vertex.d_out, k * vertex.angle / parts) for k in range(1, parts)]


def directions(vertex: Reflex) -> list[np.ndarray]:
    """The directions an edge may leave ``vertex`` in: the two sides carried on, their
    normals, the cross field's separatrices (duplicates and slivers dropped)."""
    candidates = [vertex.d_in, -vertex.d_out, _left(vertex.d_in), _left(vertex.d_out)]
    candidates += separatrices(vertex)
    out: list[np.ndarray] = []
    for d in candidates:
        a = _ccw(vertex.d_out, d)  # the interior sweeps from d_out counter-clockwise
        if not MIN_SPLIT <= a <= vertex.angle - MIN_SPLIT:
            continue
        if all(min(_ccw(d, o), _ccw(o, d)) >= SAME_DIRECTION for o in out):
            out.append(d)
    return out


def trace(start: np.ndarray, d: np.ndarray, segments: np.ndarray, tiny: float) -> np.ndarray:
    """The first point where the ray from ``start`` along ``d`` meets one of ``segments``
    (m, 2, 2), farther than ``tiny``; the start itself when it meets none."""
    a, b = segments[:, 0], segments[:, 1]
    e = b - a
    denom = d[0] * e[:, 1] - d[1] * e[:, 0]
    w = a - start
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (w[:, 0] * e[:, 1] - w[:, 1] * e[:, 0]) / denom
        s = (w[:, 0] * d[1] - w[:, 1] * d[0]) / denom
    ok = (np.abs(denom) > 1e-14) & (t > tiny) & (s >= -1e-12) & (s <= 1 + 1e-12)
    if not ok.any():
        return start
    return start + t[ok].min() * d


def ray_options(vertex: Reflex, fixed: np.ndarray, diagonal: float) -> list[list[np.ndarray]]:
    """The ways ``vertex`` may emit edges, each a list of directions: one direction each,
    ordered by how far it runs to the ``fixed`` segments (shortest first, the motorcycle
    graph's natural choice), then both sides carried on where both are directions (a
    270-degree corner's two separatrices: no T-junction left at it)."""
    tiny = NEAR_ZERO * diagonal
    single = directions(vertex)
    lengths = [np.linalg.norm(trace(vertex.point, d, fixed, tiny) - vertex.point) for d in single]
    out = [[single[k]] for k in np.argsort(lengths, kind="stable")]
    carried = [d for d in single if np.allclose(d, vertex.d_in) or np.allclose(d, -vertex.d_out)]
    if len(carried) == 2:
        out.append(carried)
    return out


def layered(vertex: Reflex) -> bool:
    """Whether a wall spacing asks ``vertex`` to carry both its walls on (its two
    separatrices), each wall's layer then running on along a block edge: where both leave
    corners of PAIR_SPLIT or more beside the walls."""
    return vertex.angle - 180.0 >= PAIR_SPLIT


def motorcycles(
    rays: list[tuple[Reflex, np.ndarray]],
    fixed: np.ndarray,
    targets: np.ndarray,
    diagonal: float,
) -> list[np.ndarray]:
    """The edges of ``rays`` (vertex, direction): traced against the ``fixed`` segments
    alone to order them shortest first, then each against those and the edges placed
    before it; an end within END_SNAP of its length of one of ``targets`` (corners, the
    rays' starts) goes onto it; an edge joining two points already joined is dropped."""
    tiny = NEAR_ZERO * diagonal
    free = [np.linalg.norm(trace(v.point, d, fixed, tiny) - v.point) for v, d in rays]
    placed: list[np.ndarray] = []
    for k in np.argsort(free, kind="stable"):
        vertex, d = rays[k]
        segments = np.concatenate([fixed, np.array(placed).reshape(-1, 2, 2)])
        end = trace(vertex.point, d, segments, tiny)
        length = np.linalg.norm(end - vertex.point)
        if length <= tiny:
            continue
        near = np.linalg.norm(targets - end, axis=1)
        near[np.linalg.norm(targets - vertex.point, axis=1) <= tiny] = np.inf
        if near.size and near.min() <= END_SNAP * length:
            end = targets[int(np.argmin(near))]
        edge = np.array([vertex.point, end])
        both = np.array(placed + [e[::-1] for e in placed]).reshape(-1, 2, 2)  # either way
        if np.isclose(edge, both).all(axis=(1, 2)).any():  # np.allclose against each
            continue
        placed.append(edge)
    return placed
