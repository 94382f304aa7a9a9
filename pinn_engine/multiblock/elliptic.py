"""Winslow's equations on all blocks at once (SPEC 10): one sparse system over the unique
nodes, interface nodes moving as interior nodes, solved by Picard iterations (coefficients
frozen per step), each step's update solved inexactly by defect correction with a sparse LU
factorisation kept over the steps (:class:`InexactLU`).

A node inside an interface piece has a full 3 x 3 stencil: its own block's rows, and across
the interface the row of the block on the other side (the two blocks' index directions
continue each other there). Junctions inside the domain (piece ends where three or more
pieces meet) are interior nodes too, with the stencils of ``junctions.py``; an edge's end
on the boundary slides along it (``sliding.py``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from pinn_engine.classical.elliptic import winslow_coefficients
from pinn_engine.multiblock.blocks import Topology
from pinn_engine.multiblock.junctions import Star, junction_stencils, star_row
from pinn_engine.multiblock.layout import Layout
from pinn_engine.multiblock.sliding import place, slide, sliders

TOL = 1e-8  # converged when no node moves more than this share of the diagonal in a step
MAX_ITERATIONS = 1000  # Picard steps at most (the examples converge in under 100)
# each Picard step's update is solved to this share of its defect only: the next step's
# coefficients change the system by about as much
FORCING = 0.1
# the factorisation is refreshed when a correction leaves more than this share of the defect
# it started from (a fresh one leaves round-off)
STALE = 0.5
MAX_CORRECTIONS = 10  # defect corrections per step at most (a refreshed factorisation needs one)


def _sides(ids: np.ndarray) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Each side of a block's id array and the row of ids just inside it."""
    return {
        "bottom": (ids[0], ids[1]),
        "top": (ids[-1], ids[-2]),
        "left": (ids[:, 0], ids[:, 1]),
        "right": (ids[:, -1], ids[:, -2]),
    }


def _place(ids: np.ndarray, nodes: np.ndarray) -> tuple[str, np.ndarray]:
    """The side of a block holding ``nodes`` (a piece's ids) and their positions on it."""
    for name, (side, _) in _sides(ids).items():
        where = {int(n): k for k, n in enumerate(side)}
        if all(int(n) in where for n in nodes):
            return name, np.array([where[int(n)] for n in nodes])
    raise AssertionError("a piece lies on no side of its block")


@dataclass
class Crossing:
    """An interface piece's node ids, its two ``blocks`` and, for each, the ids just inside
    that block beside each node (the grid line leaving the node into the block) and the
    side and positions the piece has there."""

    nodes: np.ndarray
    blocks: tuple[int, int]
    inward: tuple[np.ndarray, np.ndarray]
    places: tuple[tuple[str, np.ndarray], tuple[str, np.ndarray]]


def crossings(topo: Topology, lay: Layout, held: frozenset[int] = frozenset()) -> list[Crossing]:
    """Every interface piece (but those ``held``) with the nodes on both sides of it."""
    out = []
    for k, (piece, nodes) in enumerate(zip(topo.pieces, lay.piece_ids)):
        if not piece.interface or k in held:
            continue
        places = tuple(_place(lay.ids[b], nodes) for b in piece.blocks)
        inward = tuple(
            _sides(lay.ids[b])[name][1][ks] for b, (name, ks) in zip(piece.blocks, places)
        )
        out.append(Crossing(nodes, tuple(piece.blocks), inward, places))
    return out


def _ghosted(ids: np.ndarray) -> np.ndarray:
    ext = np.full((ids.shape[0] + 2, ids.shape[1] + 2), -1)
    ext[1:-1, 1:-1] = ids
    return ext


def _ghost_slot(ext: np.ndarray, name: str, ks: np.ndarray) -> tuple:
    """Index of the ghost cells beyond side ``name`` at positions ``ks`` of an extended
    id array, and of the side's own nodes there."""
    nj, ni = ext.shape[0] - 2, ext.shape[1] - 2
    return {
        "bottom": ((0, 1 + ks), (1, 1 + ks)),
        "top": ((nj + 1, 1 + ks), (nj, 1 + ks)),
        "left": ((1 + ks, 0), (1 + ks, 1)),
        "right": ((1 + ks, ni + 1), (1 + ks, ni)),
    }[name]


def stencils(
    topo: Topology, lay: Layout, free_interfaces: bool, held: frozenset[int] = frozenset()
) -> tuple[np.ndarray, list[Star]]:
    """The 3 x 3 neighbourhoods (n, 3, 3) of node ids, ``[:, 1, 1]`` the node solved for:
    every block's interior nodes and, with ``free_interfaces``, the nodes inside interface
    pieces (each once, in its first block's index directions) and the junctions inside the
    domain with four quadrants; with ``free_interfaces`` also the stars of the junctions
    with other quadrant counts. The ``held`` pieces and their ends stay where drawn."""
    ext = [_ghosted(ids) for ids in lay.ids]
    found = []
    for e in ext:  # the windows centred on each block's interior nodes
        found.append(
            np.lib.stride_tricks.sliding_window_view(e, (3, 3))[1:-1, 1:-1].reshape(-1, 3, 3)
        )
    if not free_interfaces:
        return np.concatenate(found), []
    for c in crossings(topo, lay, held):
        (a, b), (place_a, place_b) = c.blocks, c.places
        ghost, _ = _ghost_slot(ext[a], *place_a)
        ext[a][ghost] = c.inward[1]
        ghost, _ = _ghost_slot(ext[b], *place_b)
        ext[b][ghost] = c.inward[0]
        _, own = _ghost_slot(ext[a], place_a[0], place_a[1][1:-1])
        for j, i in zip(*np.broadcast_arrays(*own)):
            found.append(ext[a][j - 1 : j + 2, i - 1 : i + 2][None])
    kept = {int(lay.piece_ids[k][e]) for k in held for e in (0, -1)}
    ends = sorted({int(n) for ids in lay.piece_ids for n in (ids[0], ids[-1])} - kept)
    regular, stars = junction_stencils(lay, ends)
    out = np.concatenate([*found, regular])
    assert (out >= 0).all(), "an interface node lacks a neighbour"
    return out, stars


class Operator:
    """The frozen-coefficient Winslow operator over the stencils ``st`` and ``stars``: its
    sparsity pattern, assembled once, and its weights at the nodes of each Picard step.
    Applying it needs no matrix (each node's row is its stencil's weighted sum); the matrix
    is assembled only when a factorisation is due."""

    def __init__(self, st: np.ndarray, stars: list[Star], column: np.ndarray) -> None:
        self.st, self.stars, self.column = st, stars, column
        n = len(st) + len(stars)
        rows = [np.repeat(np.arange(len(st)), 9)]
        ids = [st.reshape(-1)]
        for k, star in enumerate(stars):
            rows.append(np.full(1 + 2 * len(star.edges), len(st) + k))
            ids.append(np.concatenate([[star.node], star.edges, star.diagonals]))
        rows, ids = np.concatenate(rows), np.concatenate(ids)
        self.solved = column[ids] >= 0  # entries of the matrix; the others move to the right
        keys = column[ids[self.solved]] * n + rows[self.solved]  # column-major: CSC order
        unique, self.slot = np.unique(keys, return_inverse=True)
        self.indices = (unique % n).astype(np.int32)
        self.indptr = np.searchsorted(unique // n, np.arange(n + 1)).astype(np.int32)
        # the rows over all nodes, in entry order (rows ascend): values in, residuals out
        self.rows_ptr = np.searchsorted(rows, np.arange(n + 1)).astype(np.int32)
        self.ids, self.n, self.nodes = ids.astype(np.int32), n, len(column)

    def weights(self, points: np.ndarray) -> np.ndarray:
        """Every entry's weight with alpha, beta, gamma frozen at ``points``: the 3 x 3
        stencils' (Winslow's nine-point weights), then the stars'
        (:func:`junctions.star_row`)."""
        st = self.st
        x_xi = 0.5 * (points[st[:, 1, 2]] - points[st[:, 1, 0]])
        x_eta = 0.5 * (points[st[:, 2, 1]] - points[st[:, 0, 1]])
        a, b, c = winslow_coefficients(x_xi, x_eta)
        w = np.empty(self.st.shape)
        w[:, 1, 1] = -2 * (a + c)
        w[:, 1, 2] = w[:, 1, 0] = a
        w[:, 2, 1] = w[:, 0, 1] = c
        w[:, 0, 0] = w[:, 2, 2] = -0.5 * b
        w[:, 0, 2] = w[:, 2, 0] = 0.5 * b
        return np.concatenate([w.reshape(-1), *(star_row(points, s)[1] for s in self.stars)])

    def rows(self, weights: np.ndarray) -> sp.csr_matrix:
        """Each solved node's row over all nodes: applied to node positions, the Winslow
        residual of those positions."""
        return sp.csr_matrix((weights, self.ids, self.rows_ptr), shape=(self.n, self.nodes))

    def matrix(self, weights: np.ndarray) -> sp.csc_matrix:
        """The matrix over the solved nodes (their columns in ``column``'s order)."""
        data = np.bincount(self.slot, weights[self.solved], minlength=len(self.indices))
        return sp.csc_matrix((data, self.indices, self.indptr), shape=(self.n, self.n))


class InexactLU:
    """The Picard steps' updates, solved to FORCING of their defect by defect correction
    with a sparse LU factorisation kept over the steps: the coefficients change little from
    step to step, so an old factorisation still contracts the defect, and it is refreshed
    only when it stops doing so fast (a factorisation costs tens of corrections)."""

    def __init__(self, op: Operator, solved: np.ndarray) -> None:
        self.op, self.solved, self.lu = op, solved, None
        self.full = None  # node values with the update on the solved nodes, zero elsewhere

    def update(self, weights: np.ndarray, points: np.ndarray) -> np.ndarray:
        """The update of the solved nodes toward the frozen system's solution."""
        rows = self.op.rows(weights)
        defect = -(rows @ points)
        size = np.abs(defect).max()
        step, rest = np.zeros_like(defect), defect
        if self.full is None:
            self.full = np.zeros_like(points)
        for _ in range(MAX_CORRECTIONS):
            if self.lu is None:
                self.lu = splu(self.op.matrix(weights), permc_spec="MMD_AT_PLUS_A")
            step += self.lu.solve(rest)
            before = np.abs(rest).max()
            self.full[self.solved] = step
            rest = defect - rows @ self.full
            after = np.abs(rest).max()
            if after <= FORCING * size:
                break
            if after > STALE * before:  # the factorisation no longer pays: refresh it
                self.lu = None
        return step


def winslow(
    topo: Topology,
    lay: Layout,
    free_interfaces: bool = True,
    max_iterations: int = MAX_ITERATIONS,
    held: frozenset[int] = frozenset(),
    start: np.ndarray | None = None,
) -> tuple[np.ndarray, int]:
    """Node positions of the converged multi-block Winslow grid from ``lay``'s (TFI) start
    (or after ``max_iterations`` Picard steps), and the Picard steps taken; the ``held``
    interface pieces (those a spacing names) and their ends stay where drawn. From
    ``start`` (a family model's nodes, SPEC 16) the solved nodes start at its, the other
    nodes at the layout's, and each sliding end is put where the start has it (on its
    stretch of boundary, its pieces respaced evenly) and held there: the ends' own rule
    converges slowly (on the cylinder family of docs/family.md 38 to 159 steps from the
    model's nodes, 56 to 132 from the layout), the interior from the model's in 13 to 18."""
    points = lay.points.copy()
    st, stars = stencils(topo, lay, free_interfaces, held)
    solved = np.concatenate([st[:, 1, 1], [star.node for star in stars]]).astype(int)
    if start is not None:  # the solved nodes from it, every other node the layout's
        points[solved] = np.asarray(start, dtype=float)[solved]
    column = np.full(len(points), -1)
    column[solved] = np.arange(len(solved))
    slide_ends, rings, at = sliders(topo, lay) if free_interfaces else ([], [], {})
    kept = {int(lay.piece_ids[k][e]) for k in held for e in (0, -1)}
    slide_ends = [end for end in slide_ends if end.node not in kept]
    if start is not None:  # each end where the start put it, held there
        ends = [end.node for end in slide_ends]
        points[ends] = np.asarray(start, dtype=float)[ends]
        for end in slide_ends:
            place(points, end, rings[end.ring], at)
        slide_ends = []
    last: dict[int, tuple[float, float]] = {}  # each slider's previous position and target
    tol = TOL * topo.lines.diagonal
    op = Operator(st, stars, column)
    solver = InexactLU(op, solved)
    for step in range(1, max_iterations + 1):
        before = points.copy()
        points[solved] += solver.update(op.weights(points), points)
        for end in slide_ends:
            slide(points, end, rings[end.ring], at, last)
        if np.abs(points - before).max() <= tol:
            return points, step
    return points, max_iterations
