"""The grid nearest an adapted one that keeps SPEC 14's guard: the interior nodes moved, and
boundary nodes slid along their curves, as little as they can be (each in units of its
shortest edge) so that no corner exceeds the guard's limit. A quadratic penalty on every
corner angle over the limit, raised in turn until none is over (Nocedal and Wright, 17.1),
minimised by L-BFGS from the adapted grid.
Drawing the adapted grid back toward the unadapted one gives up the front's compression
where a cell is sheared; the nearest grid shears the cell back and keeps the compression."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize

# the penalty's weights, in turn, of a squared degree over the limit against a squared move
# of a node's shortest edge: a corner a degree over weighs what moving a node 1 to 10 edges
# does; the heavier weights take what the lighter ones leave over the limit
PENALTIES = (1.0, 10.0, 100.0)
# degrees under the guard's limit the penalty aims at: a quadratic penalty's minimum lies a
# little over its aim (the move's pull against it), so the limit itself is kept
MARGIN = 0.5
ITERATIONS = 200  # L-BFGS iterations a weight, at most (a 41 x 31 grid settles in 30-150)


@dataclass
class Slide:
    """Boundary nodes ``ids`` that slide along ``curve`` (a function of arc length with a
    ``derivative``), from their arc lengths ``s``."""

    ids: np.ndarray
    s: np.ndarray
    curve: Callable


def corner_angles(
    points: np.ndarray, quads: np.ndarray, turn: np.ndarray
) -> tuple[np.ndarray, tuple[np.ndarray, ...]]:
    """Every corner's angle (m, 4) in radians, 0 to 2 pi (over pi: reflex, the cell folds),
    of the cells ``quads`` (m, 4) in (i, j) order of a grid of orientation ``turn`` (m,),
    and the edges, cross and dot products its gradient needs."""
    p = points[quads]
    e = np.roll(p, -1, axis=1) - p  # e[:, k]: from corner k to corner k + 1
    back = np.roll(e, 1, axis=1)  # e[:, k - 1]: from corner k - 1 to corner k
    cross = turn[:, None] * (back[..., 0] * e[..., 1] - back[..., 1] * e[..., 0])
    dot = -(e[..., 0] * back[..., 0] + e[..., 1] * back[..., 1])
    return np.pi + np.arctan2(-cross, -dot), (e, back, cross, dot)


def angle_gradient(
    d_theta: np.ndarray, quads: np.ndarray, turn: np.ndarray, parts: tuple, n: int
) -> np.ndarray:
    """The gradient (n, 2) by the nodes of a function of the corner angles whose derivative
    by them is ``d_theta`` (m, 4); ``parts`` from :func:`corner_angles`."""
    e, back, cross, dot = parts
    square = cross**2 + dot**2
    d_cross = turn[:, None] * d_theta * dot / square
    d_dot = -d_theta * cross / square
    ax, ay, bx, by = e[..., 0], e[..., 1], -back[..., 0], -back[..., 1]
    da = np.stack([d_cross * by + d_dot * bx, d_dot * by - d_cross * bx], -1)
    db = np.stack([d_dot * ax - d_cross * ay, d_cross * ax + d_dot * ay], -1)
    ahead, behind = np.roll(quads, -1, axis=1), np.roll(quads, 1, axis=1)
    grad = np.zeros((n, 2))
    for d in range(2):
        grad[:, d] = (
            np.bincount(ahead.ravel(), da[..., d].ravel(), n)
            + np.bincount(behind.ravel(), db[..., d].ravel(), n)
            - np.bincount(quads.ravel(), (da[..., d] + db[..., d]).ravel(), n)
        )
    return grad


def _units(points: np.ndarray, quads: np.ndarray) -> np.ndarray:
    """Each node's shortest edge (its move's unit: angles change with a node's move
    relative to its cells)."""
    p = points[quads]
    length = np.linalg.norm(np.roll(p, -1, axis=1) - p, axis=-1)  # edge k: corner k to k + 1
    unit = np.full(len(points), np.inf)
    np.minimum.at(unit, quads, np.minimum(length, np.roll(length, 1, axis=1)))
    return unit


def nearest_within(
    points: np.ndarray,
    quads: np.ndarray,
    turn: np.ndarray,
    free: np.ndarray,
    limit: float,
    guarded: np.ndarray,
    slides: Sequence[Slide] = (),
) -> tuple[np.ndarray, list[np.ndarray]]:
    """``points`` (n, 2) with the ``free`` nodes moved and the ``slides``' nodes slid along
    their curves least so that no corner of the ``guarded`` cells (m,) of ``quads`` (m, 4,
    orientation ``turn``) exceeds ``limit`` degrees: the penalty's minimum at its last
    weight, or at the first weight that leaves no corner over the limit; and each slide's
    arc lengths."""
    index = np.flatnonzero(free)
    units = _units(points, quads)
    unit = units[index, None]
    along = [units[slide.ids] for slide in slides]
    tangents = [slide.curve.derivative() for slide in slides]
    aim = np.deg2rad(limit - MARGIN)
    weight = np.zeros(len(quads))
    weight[guarded] = 1.0
    cut = np.cumsum([2 * len(index)] + [len(slide.ids) for slide in slides])

    def moved(x: np.ndarray) -> tuple[np.ndarray, list[np.ndarray]]:
        out = points.copy()
        out[index] += unit * x[: cut[0]].reshape(-1, 2)
        arcs = [s.s + u * x[a:b] for s, u, a, b in zip(slides, along, cut[:-1], cut[1:])]
        for slide, arc in zip(slides, arcs):
            out[slide.ids] = slide.curve(arc)
        return out, arcs

    x = np.zeros(cut[-1])
    for penalty in PENALTIES:
        scale = penalty * np.rad2deg(1.0) ** 2  # the penalty counts degrees

        def loss(x: np.ndarray, scale: float = scale) -> tuple[float, np.ndarray]:
            at, arcs = moved(x)
            theta, parts = corner_angles(at, quads, turn)
            over = np.maximum(theta - aim, 0.0) * weight[:, None]
            grad = angle_gradient(2 * scale * over, quads, turn, parts, len(points))
            by_arc = [
                u * (grad[slide.ids] * tangent(arc)).sum(axis=1)
                for slide, u, tangent, arc in zip(slides, along, tangents, arcs)
            ]
            value = float(x @ x + scale * (over**2).sum())
            return value, 2 * x + np.concatenate([(grad[index] * unit).ravel(), *by_arc])

        x = minimize(loss, x, jac=True, method="L-BFGS-B", options={"maxiter": ITERATIONS}).x
        theta, _ = corner_angles(moved(x)[0], quads, turn)
        if not (np.rad2deg(theta[guarded]) > limit).any():
            break
    return moved(x)
