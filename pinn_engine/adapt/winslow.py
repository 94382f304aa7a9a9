"""The adaptive equations of SPEC 14, solved classically: Winslow's variable-diffusion
equations (Winslow 1981, "Adaptive-mesh zoning by the equipotential method"), the grid's
computational coordinates harmonic in the weight 1/M,

    div( (1/M) grad xi ) = 0,   div( (1/M) grad eta ) = 0,

inverted as the elliptic grid's equations are, with m = ln M:

    alpha x_xixi - 2 beta x_xieta + gamma x_etaeta
        + (alpha (m_xi + p) - beta m_eta) x_xi + (gamma (m_eta + q) - beta m_xi) x_eta = 0,

the Winslow operator of every solver here plus first-order control terms; p and q are the
unadapted grid's own (:func:`own_controls`): with M = 1 it solves the equations as it is,
its gradings and wall spacings kept. In one dimension it is M x_xi = const times the
unadapted spacing: cells shrink where M is large, M times cell size equidistributed. The
system is the multi-block solver's (``multiblock.elliptic``: a row a node), over the unique
nodes of any 2D grid (``nodes.py``; junctions of other than four cells stay), solved by
Picard steps with M sampled at the current nodes each step; boundary nodes slide along
their piece with the feet of their grid lines (on a free boundary the equations' natural
condition is grid lines at right angles; each node keeps its unadapted distance from its
foot), a step that would fold a cell is halved.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline, PPoly

from pinn_engine.adapt.monitor import gradient_size, monitor_values
from pinn_engine.adapt.nodes import NodeGraph
from pinn_engine.classical.elliptic import winslow_coefficients
from pinn_engine.multiblock.elliptic import InexactLU, Operator

STEPS = 80  # Picard steps at most (the benchmark's grids settle in 20 to 60)
TOL = 1e-4  # settled when no node moves more than this share of the diagonal in a step
HALVINGS = 8  # a step that folds a cell is halved this many times, then the grid stays
# each step moves the nodes this share of the Picard update: M follows the nodes, and a full
# step overshoots the front and oscillates (a tanh front: no settling in 150 full steps,
# 37 halved ones)
RELAX = 0.5
FOOT_STEPS = 3  # Newton steps to a grid line's foot on a boundary curve, from the node
# a sliding node keeps this share of its piece's smallest unadapted step from its neighbours
MIN_GAP = 0.05


def _jet(curve: CubicSpline) -> PPoly:
    """One piecewise polynomial of ``curve``'s point, first and second derivative side by
    side (n, 6): a Newton step of :meth:`Piece.foot` evaluates it once, not three splines
    (the sliding's cost is the calls). The derivatives' coefficients are padded with zeros
    at the highest powers, which adds exact zeros: the values are the splines' own."""
    c = np.zeros(curve.c.shape[:2] + (6,))
    c[..., :2] = curve.c
    for k, order in ((2, 1), (4, 2)):
        c[order:, :, k : k + 2] = curve.derivative(order).c
    return PPoly(c, curve.x)


class Piece:
    """A boundary piece's curve (a not-a-knot spline through its unadapted nodes in arc
    length: a straight piece stays straight, a curve is followed to fourth order), its
    nodes' arc lengths now, and the node inside the domain each of its nodes' grid line
    leads to (-1 where there is none: a node with other than two cells)."""

    def __init__(self, ids: np.ndarray, points: np.ndarray, inward: np.ndarray) -> None:
        self.ids, self.inward = ids, inward
        steps = np.linalg.norm(np.diff(points[ids], axis=0), axis=1)
        self.s = np.concatenate([[0.0], np.cumsum(steps)])
        kind = "not-a-knot" if len(ids) > 3 else "natural"
        self.curve = CubicSpline(self.s, points[ids], bc_type=kind)
        self.jet = _jet(self.curve)
        # each node's distance along the curve from its grid line's foot in the unadapted
        # grid: kept, so that the unadapted grid is where the sliding starts from and stays
        self.offset = np.zeros(len(ids))
        self.offset = self.s - self._feet(points)

    def _feet(self, points: np.ndarray) -> np.ndarray:
        """Arc lengths of the feet of the nodes' grid lines' next nodes (a node without
        one: its own arc length, less its offset)."""
        inner = np.flatnonzero(self.inward >= 0)
        feet = self.s - self.offset
        feet[inner] = self.foot(points[self.inward[inner]], self.s[inner] - self.offset[inner])
        return feet

    def foot(self, p: np.ndarray, s: np.ndarray) -> np.ndarray:
        """Arc lengths of the feet on the curve of points ``p`` near arc lengths ``s``
        (Newton's steps on the squared distance)."""
        for _ in range(FOOT_STEPS):
            jet = self.jet(s)
            r, t, c = jet[:, :2] - p, jet[:, 2:4], jet[:, 4:]
            s = s - np.einsum("nk,nk->n", r, t) / np.maximum(
                np.einsum("nk,nk->n", t, t) + np.einsum("nk,nk->n", r, c), 1e-300
            )
            s = np.clip(s, self.s[0], self.s[-1])
        return s

    def slide(self, points: np.ndarray, relax: float) -> np.ndarray:
        """Move the nodes ``relax`` of the way to the feet of their grid lines' next nodes
        (grid lines leave a sliding boundary at right angles: the natural condition of the
        adaptive equations where the boundary is free), kept in order; their new
        positions."""
        target = self._feet(points) + self.offset
        s = self.s + relax * (target - self.s)
        gap = MIN_GAP * np.diff(self.s).min(initial=0.0)  # no node passes its neighbour
        k = np.arange(len(s)) * gap
        s = np.maximum.accumulate(s - k) + k  # each at least gap past the one before
        s = np.minimum.accumulate((s - k)[::-1])[::-1] + k  # and gap short of the next
        s[0], s[-1] = self.s[0], self.s[-1]
        self.s = s
        return self.curve(s)


def _first(points: np.ndarray, st: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """x_xi and x_eta at the stencils' centres, central differences."""
    return (
        0.5 * (points[st[:, 1, 2]] - points[st[:, 1, 0]]),
        0.5 * (points[st[:, 2, 1]] - points[st[:, 0, 1]]),
    )


def _controls(
    points: np.ndarray, st: np.ndarray, m: np.ndarray, own: tuple[np.ndarray, np.ndarray]
) -> tuple[np.ndarray, ...]:
    """The control terms' coefficients at the stencils' centres: the monitor's (alpha m_xi
    - beta m_eta, gamma m_eta - beta m_xi), m = ln M at the nodes, plus the unadapted
    grid's own (alpha p, gamma q) (:func:`own_controls`)."""
    a, b, c = winslow_coefficients(*_first(points, st))
    m_xi = 0.5 * (m[st[:, 1, 2]] - m[st[:, 1, 0]])
    m_eta = 0.5 * (m[st[:, 2, 1]] - m[st[:, 0, 1]])
    return a * (m_xi + own[0]) - b * m_eta, c * (m_eta + own[1]) - b * m_xi


def own_controls(points: np.ndarray, st: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Control functions p, q that make the unadapted grid an exact solution with M = 1
    (Thompson's sources taken from a given grid, scaled as Hilgenstock's by alpha and
    gamma): alpha p x_xi + gamma q x_eta = -(alpha x_xixi - 2 beta x_xieta + gamma
    x_etaeta). Its gradings, wall spacings and angles are then what the monitor moves from,
    not what the solve undoes."""
    x_xi, x_eta = _first(points, st)
    a, b, c = winslow_coefficients(x_xi, x_eta)
    p = points[st]
    x_xixi = p[:, 1, 2] - 2 * p[:, 1, 1] + p[:, 1, 0]
    x_etaeta = p[:, 2, 1] - 2 * p[:, 1, 1] + p[:, 0, 1]
    x_xieta = 0.25 * (p[:, 2, 2] - p[:, 0, 2] - p[:, 2, 0] + p[:, 0, 0])
    rhs = -(a[:, None] * x_xixi - 2 * b[:, None] * x_xieta + c[:, None] * x_etaeta)
    cols = np.stack([a[:, None] * x_xi, c[:, None] * x_eta], axis=-1)  # (k, 2, 2)
    pq = np.linalg.solve(cols, rhs[..., None])[..., 0]
    return pq[:, 0], pq[:, 1]


def corner_areas(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """The signed area at each corner of each cell (m, 4): positive while counter-clockwise."""
    p = points[cells]
    e = np.roll(p, -1, axis=1) - p
    prev = np.roll(e, 1, axis=1)
    return prev[..., 0] * e[..., 1] - prev[..., 1] * e[..., 0]


@dataclass
class Solved:
    """An adapted grid's unique nodes, its boundary pieces' arc lengths (``Piece.s``), its
    monitor at the nodes and the Picard steps taken."""

    points: np.ndarray
    params: list[np.ndarray]
    monitor: np.ndarray
    steps: int


def pieces_of(graph: NodeGraph) -> list[Piece]:
    """The boundary pieces of ``graph`` on the curves of its unadapted nodes."""
    return [Piece(ids, graph.points, graph.inward[ids]) for ids in graph.pieces]


def adaptive_winslow(
    graph: NodeGraph,
    sample: Callable[[np.ndarray], np.ndarray],
    strength: np.ndarray,
    largest: float,
    initial: Solved | None = None,
) -> Solved:
    """The grid of ``graph`` adapted to the field ``sample`` gives at points (n, 2), with
    the monitor of ``strength`` (at each node) scaled by the field's largest gradient
    ``largest``, from the unadapted grid or ``initial``."""
    points = graph.points.copy() if initial is None else initial.points.copy()
    st, stars = graph.stencils, []  # junctions of other than four cells stay
    solved = st[:, 1, 1].astype(int)
    column = np.full(len(points), -1)
    column[solved] = np.arange(len(solved))
    op = Operator(st, stars, column)
    solver = InexactLU(op, solved)
    pieces = pieces_of(graph)
    if initial is not None:
        for piece, s in zip(pieces, initial.params):
            piece.s = s.copy()
    tol = TOL * graph.diagonal
    centre = slice(0, 9 * len(st))
    m = np.zeros(len(points))
    convex = corner_areas(graph.points, graph.cells) > 0  # the corners that must stay so
    own = own_controls(graph.points, st)
    steps = 0
    while steps < STEPS:
        steps += 1
        gradient = gradient_size(points, graph.cells, sample(points))
        m = np.log(monitor_values(gradient, strength, largest))
        weights = op.weights(points)
        w = weights[centre].reshape(-1, 3, 3)
        cp, cq = _controls(points, st, m, own)
        w[:, 1, 2] += 0.5 * cp
        w[:, 1, 0] -= 0.5 * cp
        w[:, 2, 1] += 0.5 * cq
        w[:, 0, 1] -= 0.5 * cq
        move = np.zeros_like(points)
        move[solved] = RELAX * solver.update(weights, points)
        for piece in pieces:
            move[piece.ids] = piece.slide(points, RELAX) - points[piece.ids]
        for _ in range(HALVINGS):
            if (corner_areas(points + move, graph.cells)[convex] > 0).all():
                break
            move *= 0.5
        else:
            break
        points = points + move
        if np.abs(move).max() <= tol:
            break
    m = monitor_values(gradient_size(points, graph.cells, sample(points)), strength, largest)
    return Solved(points, [piece.s for piece in pieces], m, steps)
