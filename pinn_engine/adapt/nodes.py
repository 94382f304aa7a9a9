"""The nodes of a 2D grid of any kind as one graph (SPEC 14): each block's nodes merged
where they coincide (a shared block side, an O-grid's seam, a C-grid's wake cut), every
cell counter-clockwise, and the boundary cut into pieces between the nodes that stay."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from pinn_engine.quality import cell_quality

# Nodes of two blocks (or of a seam or cut) are one node when this share of the diagonal or
# less apart: exporters join them at the same tolerance's scale, and shared nodes are equal
MERGE_TOL = 1e-9
# A boundary node where the boundary turns by this many degrees or more stays: a corner of
# the drawing (SPEC 10's corner angle), such as a sharp trailing edge
CORNER_TURN = 30.0


@dataclass
class NodeGraph:
    """``points`` (n, 2) of the unique nodes, each block's id lattice ``ids`` (nj, ni),
    ``cells`` (m, 4) counter-clockwise, ``pieces``: the boundary between staying nodes
    (each an id run, its two ends staying), ``held``: the nodes that stay (corners, block
    corners, and those the caller holds), ``junctions``: the block corners inside the domain
    that the caller does not hold (a multi-block grid's joined solve moves them)."""

    points: np.ndarray
    ids: list[np.ndarray]
    cells: np.ndarray
    pieces: list[np.ndarray]
    held: np.ndarray
    junctions: np.ndarray

    @property
    def diagonal(self) -> float:
        """The diagonal of the nodes' bounding box."""
        return float(np.linalg.norm(np.ptp(self.points, axis=0)))

    def grids(self, points: np.ndarray) -> list[np.ndarray]:
        """Each block's grid (nj, ni, 2) of unique node positions ``points``."""
        return [points[ids] for ids in self.ids]

    @cached_property
    def node_cells(self) -> np.ndarray:
        """Each node's cells (n, k), padded with ``len(cells)`` (a junction has 3 or 5 cells,
        a boundary node 1 or 2): a value a cell, with one more appended, read at the nodes."""
        n, m = len(self.points), len(self.cells)
        flat = self.cells.ravel()
        order = np.argsort(flat, kind="stable")
        counts = np.bincount(flat, minlength=n)
        slot = np.arange(len(flat)) - np.repeat(np.cumsum(counts) - counts, counts)
        out = np.full((n, max(int(counts.max()), 1)), m)
        out[flat[order], slot] = order // 4
        return out

    @cached_property
    def lattice_cells(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Every cell's node ids in its block's (i, j) order (m, 4), in ``cells``' order, as
        :func:`cell_quality` reads them; its block's orientation (+1: counter-clockwise) and
        whether it folds, both in the unadapted grid."""
        quads = [lattice_quads([i]) for i in self.ids]
        orientation = []
        for q in quads:
            p = self.points[q]
            d1, d2 = p[:, 2] - p[:, 0], p[:, 3] - p[:, 1]
            area = (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]).sum()
            orientation.append(np.full(len(q), 1.0 if area >= 0 else -1.0))
        folded = np.concatenate([f.ravel() for f in self.folded])
        return np.vstack(quads), np.concatenate(orientation), folded

    @cached_property
    def folded(self) -> list[np.ndarray]:
        """Each block's cells (nj - 1, ni - 1) that fold in the unadapted grid (the guard
        asks every adapted grid of it)."""
        return [cell_quality(grid)["Folded"] for grid in self.grids(self.points)]


def _merged(grids: list[np.ndarray]) -> tuple[np.ndarray, list[np.ndarray]]:
    """The unique nodes of ``grids`` and each block's id lattice."""
    flat = np.vstack([g.reshape(-1, 2) for g in grids])
    diagonal = float(np.linalg.norm(np.ptp(flat, axis=0)))
    pairs = cKDTree(flat).query_pairs(MERGE_TOL * diagonal, output_type="ndarray")
    n = len(flat)
    link = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, label = connected_components(link, directed=False)
    _, first, ids = np.unique(label, return_index=True, return_inverse=True)
    out, at = [], 0
    for g in grids:
        size = g.shape[0] * g.shape[1]
        out.append(ids[at : at + size].reshape(g.shape[:2]))
        at += size
    return flat[first], out


def lattice_quads(ids: list[np.ndarray]) -> np.ndarray:
    """The cells (m, 4) of id lattices, (j, i), (j, i + 1), (j + 1, i + 1), (j + 1, i)."""
    return np.vstack(
        [
            np.stack([i[:-1, :-1], i[:-1, 1:], i[1:, 1:], i[1:, :-1]], axis=-1).reshape(-1, 4)
            for i in ids
        ]
    )


def _cells(points: np.ndarray, ids: list[np.ndarray]) -> np.ndarray:
    """Every cell's four node ids, counter-clockwise."""
    quads = lattice_quads(ids)
    p = points[quads]
    d1, d2 = p[:, 2] - p[:, 0], p[:, 3] - p[:, 1]
    area = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    quads[area < 0] = quads[area < 0][:, ::-1]
    return quads


def _boundary_edges(cells: np.ndarray, n: int) -> np.ndarray:
    """The undirected edges (k, 2) that only one cell has."""
    edges = np.sort(np.stack([cells, np.roll(cells, -1, axis=1)], axis=-1).reshape(-1, 2), axis=1)
    keys, counts = np.unique(edges[:, 0] * n + edges[:, 1], return_counts=True)
    once = keys[counts == 1]
    return np.column_stack([once // n, once % n])


def node_graph(grids: list[np.ndarray], held: list[np.ndarray] | None = None) -> NodeGraph:
    """The graph of the blocks ``grids`` (each (nj, ni, 2)); ``held``: per block, a mask of
    nodes that must stay (walls whose first edge or angle was asked, with their first row)."""
    points, ids = _merged(grids)
    cells = _cells(points, ids)
    n = len(points)
    stay, corner = np.zeros(n, dtype=bool), np.zeros(n, dtype=bool)
    for lattice, mask in zip(ids, held or [None] * len(ids)):
        corner[lattice[[0, 0, -1, -1], [0, -1, 0, -1]]] = True
        if mask is not None:
            stay[lattice[mask]] = True
    boundary_edges = _boundary_edges(cells, n)
    junctions = corner & ~stay
    junctions[boundary_edges.ravel()] = False
    stay |= corner
    pieces, corners = _pieces(points, boundary_edges, stay)
    stay[corners] = True
    return NodeGraph(points, ids, cells, pieces, stay, junctions)


def _pieces(
    points: np.ndarray, edges: np.ndarray, stay: np.ndarray
) -> tuple[list[np.ndarray], list[int]]:
    """The boundary's runs of nodes between staying nodes (corners found here too: turns of
    ``CORNER_TURN`` or more, and a node on a ring where nothing stays)."""
    neighbours: dict[int, list[int]] = {}
    for a, b in edges:
        neighbours.setdefault(int(a), []).append(int(b))
        neighbours.setdefault(int(b), []).append(int(a))
    corners = []
    for node, near in neighbours.items():
        if len(near) != 2:
            corners.append(node)
            continue
        u, v = points[node] - points[near[0]], points[near[1]] - points[node]
        cos = np.dot(u, v) / max(np.linalg.norm(u) * np.linalg.norm(v), 1e-300)
        if np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))) >= CORNER_TURN:
            corners.append(node)
    ends = {n for n in neighbours if stay[n]} | set(corners)
    seen: set[tuple[int, int]] = set()
    pieces = []
    for start in sorted(neighbours):
        if start not in ends:
            continue
        for nxt in neighbours[start]:
            if (start, nxt) in seen:
                continue
            run = [start, nxt]
            while run[-1] not in ends:
                a, b = neighbours[run[-1]]
                run.append(b if a == run[-2] else a)
            for p, q in zip(run[:-1], run[1:]):
                seen.add((p, q))
                seen.add((q, p))
            pieces.append(np.array(run))
    loose = {n for e in map(tuple, edges) for n in e} - {n for p in pieces for n in p}
    while loose:  # a ring on which nothing stays: its lowest node does
        start = min(loose)
        corners.append(start)
        ring = [start, neighbours[start][0]]
        while ring[-1] != start:
            a, b = neighbours[ring[-1]]
            ring.append(b if a == ring[-2] else a)
        pieces.append(np.array(ring))
        loose -= set(ring)
    return [p for p in pieces if len(p) > 2], corners
