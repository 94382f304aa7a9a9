"""The choice among candidate blockings (SPEC 13): every reflex vertex's direction (or none,
where another edge already ends on it) is tried, each layout completed round face centres
or along a hexagon's diagonals (``faces.py``), ranked by its blocks' corner angles (to
``RANK_DIGITS``: a tie in the order found), and the best few meshed by the elliptic
multi-block solver, whose quality (and interface kinks) picks the winner (``score.py``).

Few reflex vertices (up to ``EXHAUSTIVE`` combinations) are tried in every combination;
more, coordinate by coordinate from two starts (each needed vertex its shortest edge, the
others none; every vertex its shortest edge), each vertex in turn taking the choice that
lowers the layout cost, the others held, until no choice improves.
"""

from __future__ import annotations

import itertools
from collections import Counter
from collections.abc import Callable, Iterable

import numpy as np

from pinn_engine.multiblock.autoblock.corners import Reflex
from pinn_engine.multiblock.autoblock.faces import NoBlocking, completions, place
from pinn_engine.multiblock.autoblock.score import Rejected

EXHAUSTIVE = 256  # combinations tried one by one; more go coordinate by coordinate
SHORTLIST = 2  # layouts of each edge count (the cheapest by corner angles) meshed
MAX_MESHED = 8  # layouts meshed at most (the shortlist's cheapest)
MAX_SWEEPS = 4  # passes of the coordinate search over all vertices
SAME_POINT = 1e-12  # relative: an edge's end is a vertex (edges start exactly at vertices)
# Significant digits of a layout's cost or score that rank it: mirror layouts cost the same
# but for rounding, which differs between machines far below this; a tie goes by the order
# the search found them in, the same on every machine, so every machine picks the same one
RANK_DIGITS = 9

Choice = tuple[int, ...]  # per reflex vertex: index into its ray options, or -1 for none


def _combinations(sizes: list[int]) -> Iterable[Choice]:
    """Every choice: each vertex one of its directions or none (-1)."""
    return itertools.product(*[range(-1, n) for n in sizes])


def candidates(
    vertices: list[Reflex],
    options: list[list[list[np.ndarray]]],
    build: Callable[[list[tuple[Reflex, np.ndarray]]], list[np.ndarray]],
    rings: list[np.ndarray],
    fixed: list[np.ndarray],
    failures: Counter[str],
) -> list[tuple[float, list[np.ndarray]]]:
    """The feasible completed layouts (cost, edges), cheapest first, of the ``fixed`` edges
    (the O-rings) and the vertices' ray ``options`` (each a list of directions, the
    shortest edge first); ``build`` turns (vertex, direction) rays into edges. Each layout
    tried that is no blocking counts its reason in ``failures``."""
    seen: dict[bytes, tuple[float, list[np.ndarray]]] = {}  # completed layouts
    costs: dict[bytes, float] = {}  # the cheapest completion of each choice's edges
    needed = [v.point for v in vertices if v.needed]

    def cost_of(choice: Choice) -> float:
        rays = [(v, d) for v, opts, c in zip(vertices, options, choice) if c >= 0 for d in opts[c]]
        cuts = build(rays)
        uncut = _uncut(needed, cuts)
        if uncut is not None:
            where = place(uncut, float(np.abs(uncut).max()))  # a vertex as drawn
            failures[f"the reflex corner at {where} gets no edge"] += 1
            return np.inf
        edges = fixed + cuts
        key = _key(edges)
        if key not in costs:
            try:
                done = completions(rings, edges)
            except NoBlocking as exc:
                failures[str(exc)] += 1
                done = []
            for layout, cost in done:
                seen[_key(layout)] = (cost, layout)
            costs[key] = min((cost for _, cost in done), default=np.inf)
        return costs[key]

    sizes = [len(o) for o in options]
    if np.prod([n + 1 for n in sizes], dtype=float) <= EXHAUSTIVE:
        for choice in _combinations(sizes):
            cost_of(choice)
    else:
        starts = (  # the needed vertices' shortest edges; every vertex's shortest edge
            [0 if n and v.needed else -1 for v, n in zip(vertices, sizes)],
            [0 if n else -1 for n in sizes],
        )
        for choice in starts:
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
    return ranked(seen.values())


def ranked(layouts: Iterable[tuple[float, list[np.ndarray]]]) -> list[tuple[float, list]]:
    """The feasible ``layouts`` (cost, edges), cheapest first, a tie (to ``RANK_DIGITS``)
    in the order the search found them, whichever costs a hair less."""
    feasible = (item for item in layouts if np.isfinite(item[0]))
    return sorted(feasible, key=lambda item: _rounded(item[0]))


def _rounded(cost: float) -> float:
    """``cost`` to ``RANK_DIGITS`` significant digits, as layouts are ranked."""
    return float(f"{cost:.{RANK_DIGITS}g}")


def _key(edges: list[np.ndarray]) -> bytes:
    """The same bytes for the same set of edges, whatever their order and direction."""
    rounded = [np.round(e, 9) for e in edges]
    ends = [e if tuple(e[0]) <= tuple(e[-1]) else e[::-1] for e in rounded]
    return repr(sorted(tuple(map(tuple, e)) for e in ends)).encode()


def _uncut(points: list[np.ndarray], edges: list[np.ndarray]) -> np.ndarray | None:
    """The first of ``points`` (the reflex vertices that need an edge) that no edge ends at;
    None when every one has its edge."""
    ends = np.array([e[[0, -1]] for e in edges]).reshape(-1, 2)
    for p in points:
        if not len(ends) or np.abs(ends - p).max(axis=1).min() / (1 + np.abs(p).max()) > SAME_POINT:
            return p
    return None


def shortlist(layouts: list[tuple[float, list[np.ndarray]]]) -> list[list[np.ndarray]]:
    """The SHORTLIST cheapest of ``layouts`` (cheapest first) with each number of edges, at
    most MAX_MESHED: fewer blocks and more both get meshed, whatever the corner angles'
    ranking."""
    taken: dict[int, int] = {}
    out = []
    for _, edges in layouts:
        if taken.get(len(edges), 0) < SHORTLIST:
            taken[len(edges)] = taken.get(len(edges), 0) + 1
            out.append(edges)
    return out[:MAX_MESHED]


def best_meshed(
    layouts: list[tuple[float, list[np.ndarray]]],
    score: Callable[[list[np.ndarray]], float],
    confirm: Callable[[list[np.ndarray]], float] | None = None,
) -> list[np.ndarray]:
    """Of the ``shortlist`` of ``layouts``, the edges whose grid ``score``s lowest and,
    with ``confirm`` (the score at the run's own cell size, where the search judged them
    coarser), is not rejected there too: the next best where it is. Rejected, with the
    reason of the layout nearest to meshing (the fewest folded cells), when none can be
    meshed."""
    scored, rejected = [], []
    for k, edges in enumerate(shortlist(layouts)):
        try:
            scored.append((score(edges), k, edges))
        except Rejected as exc:
            rejected.append(exc)
    for _, _, edges in sorted(scored, key=lambda item: (_rounded(item[0]), item[1])):
        try:
            if confirm is not None:
                confirm(edges)
        except Rejected as exc:
            rejected.append(exc)
            continue
        return edges
    nearest = min(rejected, key=lambda exc: exc.folds)  # the first of the fewest folds
    raise Rejected(f"of the {len(rejected)} layouts meshed, the nearest {nearest}", nearest.folds)
