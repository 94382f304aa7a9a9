"""The choice among candidate blockings (SPEC 13): every reflex vertex's direction (or none,
where another edge already ends on it) is tried, each layout completed round face centres
(``faces.py``), ranked by its blocks' corner angles, and the best few meshed coarsely by the
elliptic multi-block solver, whose quality (and interface kinks) picks the winner.

Few reflex vertices (up to ``EXHAUSTIVE`` combinations) are tried in every combination;
more, coordinate by coordinate from the motorcycle graph's own start (each needed vertex its
shortest edge, the others none), each vertex in turn taking the choice that lowers the
layout cost, the others held, until no choice improves.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Iterable

import numpy as np

from pinn_engine.multiblock.autoblock.corners import Reflex
from pinn_engine.multiblock.autoblock.faces import NoBlocking, completed

EXHAUSTIVE = 256  # combinations tried one by one; more go coordinate by coordinate
SHORTLIST = 6  # layouts (cheapest by corner angles) meshed to choose among
MAX_SWEEPS = 4  # passes of the coordinate search over all vertices
SAME_POINT = 1e-12  # relative: an edge's end is a vertex (edges start exactly at vertices)

Choice = tuple[int, ...]  # per reflex vertex: index into its directions, or -1 for none


def _combinations(sizes: list[int]) -> Iterable[Choice]:
    """Every choice: each vertex one of its directions or none (-1)."""
    return itertools.product(*[range(-1, n) for n in sizes])


def candidates(
    vertices: list[Reflex],
    options: list[list[np.ndarray]],
    build: Callable[[list[tuple[Reflex, np.ndarray]]], list[np.ndarray]],
    rings: list[np.ndarray],
) -> list[tuple[float, list[np.ndarray]]]:
    """The feasible completed layouts (cost, edges), cheapest first, of the vertices'
    direction ``options`` (each vertex's shortest first); ``build`` turns (vertex,
    direction) rays into edges."""
    seen: dict[bytes, tuple[float, list[np.ndarray]]] = {}
    needed = [v.point for v in vertices if v.needed]

    def cost_of(choice: Choice) -> float:
        rays = [(v, opts[c]) for v, opts, c in zip(vertices, options, choice) if c >= 0]
        edges = build(rays)
        if not _all_cut(needed, edges):
            return np.inf
        key = np.concatenate([e.ravel() for e in edges] or [np.zeros(0)]).round(9).tobytes()
        if key not in seen:
            try:
                done, cost = completed(rings, edges)
                seen[key] = (cost, done)
            except NoBlocking:
                seen[key] = (np.inf, edges)
        return seen[key][0]

    sizes = [len(o) for o in options]
    if np.prod([n + 1 for n in sizes], dtype=float) <= EXHAUSTIVE:
        for choice in _combinations(sizes):
            cost_of(choice)
    else:
        choice = [0 if n and v.needed else -1 for v, n in zip(vertices, sizes)]
        best = cost_of(tuple(choice))
        for _ in range(MAX_SWEEPS):
            improved = False
            for k, n in enumerate(sizes):
                for c in range(-1, n):
                    trial = tuple(choice[:k] + [c] + choice[k + 1 :])
                    cost = cost_of(trial)
                    if cost < best:
                        best, choice, improved = cost, list(trial), True
            if not improved:
                break
    return sorted((v for v in seen.values() if np.isfinite(v[0])), key=lambda item: item[0])


def _all_cut(points: list[np.ndarray], edges: list[np.ndarray]) -> bool:
    """Whether an edge ends at each of ``points`` (the reflex vertices that need one)."""
    if not points:
        return True
    ends = np.array([e[[0, -1]] for e in edges]).reshape(-1, 2)
    if not len(ends):
        return False
    near = [np.abs(ends - p).max(axis=1).min() / (1 + np.abs(p).max()) for p in points]
    return max(near) <= SAME_POINT


def best_meshed(
    layouts: list[tuple[float, list[np.ndarray]]],
    score: Callable[[list[np.ndarray]], float],
) -> list[np.ndarray] | None:
    """Of the SHORTLIST cheapest ``layouts``, the edges whose coarse grid ``score``s lowest
    (None when none can be meshed)."""
    best = None
    for _, edges in layouts[:SHORTLIST]:
        value = score(edges)
        if np.isfinite(value) and (best is None or value < best[0]):
            best = (value, edges)
    return None if best is None else best[1]
