"""SPEC 14's guard: no fold, and no cell whose MaxIncludedAngle exceeds the unadapted
grid's worst by more than ``GUARD_DEGREES``. Where the adapted grid breaks it, the grid is
solved again with the shear cap (the compression across a front bounded by what the cells
there take within the bound, :func:`~pinn_engine.adapt.monitor.shear_cap`), then with the
strength lowered round the cells that still break; what still breaks is drawn back toward
the unadapted grid (each node's move, a boundary node's along its curve, scaled down round
the offending cells, each by as much as it is over the bound) until it holds. The first
solve's moves (and, blocks joined, those of the first solve slipped: its compressed cells
turned along the front), whole and scaled down everywhere, drawn back the same way, are
further candidates, and so is the grid within the bound nearest the candidate that carries
the field best (:func:`~pinn_engine.adapt.nearest.nearest_within`); the one carrying the
field best is kept."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from pinn_engine.adapt.error import interpolation_error
from pinn_engine.adapt.nearest import Slide, nearest_within
from pinn_engine.adapt.nodes import NodeGraph
from pinn_engine.adapt.parametric import ParameterSpace
from pinn_engine.adapt.pieces import Piece, Solved, pieces_of
from pinn_engine.quality import corner_angles_and_folds

GUARD_DEGREES = 10.0  # SPEC 14: the worst cell may exceed the unadapted grid's by this much
ROUNDS = 12  # solves with the strength lowered round the offending cells, at most
# a round that leaves more than this share of the last round's offending cells is the last:
# the cells left are pulled by the monitor farther away, and the draw-back takes them
PROGRESS = 0.8
# each round multiplies the strength round an offending cell by this (and a draw-back round
# the move round a folded cell)
LOWER = 0.7
# the lowering reaches this many rings of cells round an offending cell, fading: a strength
# cut at one node alone would crease the monitor there
SPREAD = 6
DRAWBACKS = 120  # rounds of drawing moves back, at most (GENTLE**120: every move undone)
# a round of drawing back keeps at least this share of a move round an offending cell: a
# front's compression is given up a little at a time, only where the bound still breaks
GENTLE = 0.9
# where the first solve breaks the guard, its moves scaled by each of these everywhere are
# also drawn back: a front's compression kept whole at a lower amplitude (the lowering cuts
# it where it is strongest); the candidate carrying the field best is kept
BLENDS = (1.0, 0.8, 0.6, 0.4)
# rings of cells round the offending ones whose nodes move to reach the bound: a sheared
# cell is straightened by its neighbours taking up the move, the rest of the grid stays
NEAREST_RINGS = 4
REFLEX = 180.0  # degrees: a cell with a corner above it folds


@dataclass
class Guarded:
    """The grid that keeps the guard, each node's share of the strength asked (1: all of
    it), the share of each node's move kept by the draw-back, the solves made, and the
    grid's interpolation error (``within`` False: the first solve broke the guard and
    already carried the field no better than the bound asked, so it was not guarded;
    ``moved``: its nodes were moved to the nearest grid within the bound)."""

    solved: Solved
    share: np.ndarray
    kept: np.ndarray
    rounds: list[dict] = field(default_factory=list)
    error: float = np.inf
    within: bool = True
    moved: bool = False


def _angles(
    graph: NodeGraph, points: np.ndarray, cells: np.ndarray | slice = slice(None)
) -> tuple[np.ndarray, np.ndarray]:
    """The MaxIncludedAngle of ``cells`` (all by default, in ``graph.cells`` order) and
    whether they fold; a cell the unadapted grid folds is not the guard's (angle 0, no
    fold)."""
    quads, orientation, folded = graph.lattice_cells
    q = quads[cells]
    angle, folds = corner_angles_and_folds([points[q[:, k]] for k in range(4)], orientation[cells])
    return np.where(folded[cells], 0.0, angle), folds & ~folded[cells]


def offending(graph: NodeGraph, points: np.ndarray, limit: float) -> np.ndarray:
    """Which cells fold (that the unadapted grid does not fold) or have a MaxIncludedAngle
    over ``limit``, in ``graph.cells`` order."""
    angle, folds = _angles(graph, points)
    return (angle > limit) | folds


def _largest(values: np.ndarray, index: np.ndarray) -> np.ndarray:
    """The largest of ``values`` over each row of ``index`` (column by column: faster than
    a reduction along a short axis)."""
    out = values[index[:, 0]]
    for column in range(1, index.shape[1]):
        out = np.maximum(out, values[index[:, column]])
    return out


def _round(graph: NodeGraph, cut: np.ndarray) -> np.ndarray:
    """Each cell's ``cut`` (0 to 1) at its nodes (the largest of a node's cells), fading
    over ``SPREAD`` rings round them; only the rings' nodes and cells are visited."""
    n, m = len(graph.points), len(graph.cells)
    values, cells = np.append(cut, 0.0), np.flatnonzero(cut > 0.0)  # node_cells pads with m
    weight = np.zeros(n)
    for ring in range(SPREAD + 1):
        nodes = np.flatnonzero(np.bincount(graph.cells[cells].ravel(), minlength=n))
        level = np.zeros(n)
        level[nodes] = _largest(values, graph.node_cells[nodes])
        weight[nodes] = np.maximum(weight[nodes], (1.0 - ring / (SPREAD + 1)) * level[nodes])
        cells = np.flatnonzero(np.bincount(graph.node_cells[nodes].ravel(), minlength=m + 1)[:m])
        values = np.zeros(m + 1)
        values[cells] = _largest(level, graph.cells[cells])
    return weight


def guarded(
    graph: NodeGraph,
    space: ParameterSpace,
    strength: float,
    limit: float,
    isotropic: bool = False,
    bound: float = np.inf,
    curvature: bool = False,
    joined: bool = False,
    first: tuple[Solved, float] | None = None,
    unadapted: float = np.inf,
) -> Guarded:
    """The grid adapted with ``strength`` lowered where the guard (``limit`` degrees, no
    fold) needs it (``isotropic``, ``curvature``: the diffusion tensor's form, ``joined``:
    a multi-block grid's blocks solved joined, :meth:`ParameterSpace.solve`; ``first``: its
    first solve and that grid's error, where made already), its candidates kept where they
    carry the field better than ``bound`` (the best grid so far); not guarded where its
    first and capped solves break the guard and carry the field no better than the
    ``unadapted`` grid's error (the guard's lowering and draw-back adapt less: they seldom
    gain it back)."""
    n = len(graph.points)
    share = np.ones(n)

    scored: dict[bytes, float] = {}

    def error(points: np.ndarray) -> float:
        # a grid is scored once: a candidate's scaled moves are scored before it is drawn
        # back, and again where it keeps the guard as it is
        key = points.tobytes()
        if key not in scored:
            scored[key] = interpolation_error(points, graph.cells, space.sample)
        return scored[key]

    if first is None:
        made = space.solve(share * strength, isotropic, False, curvature, joined)
        first = made, error(made.points)
    first, now = first
    solved = first
    bad = offending(graph, solved.points, limit)
    rounds = [{"steps": solved.steps, "offending_cells": int(bad.sum())}]
    if not bad.any():
        return Guarded(solved, share, np.ones(n), rounds, now)
    # joined blocks: the first solve slipped (its compressed cells turned along the front,
    # not sheared) is a candidate too, its moves scaled and drawn back as the first's
    starts = [first]
    if joined and space.joined is not None:
        starts.append(space.solve(share * strength, isotropic, False, curvature, joined, True))
        now = min(now, error(starts[-1].points))
    # the shear cap, then the strength lowered round the cells that still break
    capped = None
    for _ in range(ROUNDS - 1):
        solved = space.solve(strength * share, isotropic, True, curvature, joined)
        bad = offending(graph, solved.points, limit)
        rounds.append({"steps": solved.steps, "offending_cells": int(bad.sum())})
        if capped is None:
            capped = solved
            now = min(now, error(solved.points))
            if bad.any() and now >= unadapted:
                return Guarded(solved, share, np.ones(n), rounds, now, within=False)
        if not bad.any() or bad.sum() > PROGRESS * rounds[-2]["offending_cells"]:
            break
        share = share * (1.0 - (1.0 - LOWER) * _round(graph, bad.astype(float)))
    sources = [(solved, share, 1.0)] + [(capped, np.ones(n), 1.0)] * (solved is not capped)
    sources += [(start, np.ones(n), blend) for start in starts for blend in BLENDS]
    nearest = _nearest(graph, sources, limit, error, bound)
    best = None
    for k, (source, its_share, blend) in enumerate(nearest + sources):
        # drawing back adapts less: a candidate that carries the field no better than the
        # best one (or the grid kept) before it is drawn back is not drawn back
        found = _drawn_back(graph, source, its_share, limit, rounds, blend, error, bound)
        if found is not None and found.error < bound:
            best, bound = found, found.error
            best.moved = k < len(nearest)
    return best or Guarded(first, share, np.ones(n), rounds, now, within=False)


def _drawn_back(
    graph: NodeGraph,
    solved: Solved,
    share: np.ndarray,
    limit: float,
    rounds: list[dict],
    blend: float,
    error: Callable[[np.ndarray], float],
    bound: float,
) -> Guarded | None:
    """``solved`` with its moves scaled by ``blend``, then down round the offending cells
    until none is left (the unadapted grid, all moves undone, keeps the guard), and its
    ``error``; None where the scaled moves' grid carries the field no better than ``bound``."""
    pieces = pieces_of(graph)
    start_params = [p.s.copy() for p in pieces]
    kept = np.full(len(graph.points), blend)
    before, _ = _angles(graph, graph.points)
    angle, folds = before.copy(), np.zeros(len(before), dtype=bool)
    changed: np.ndarray | slice = slice(None)  # the cells whose nodes moved: all at first
    for step in range(DRAWBACKS):
        points, params = _scaled(graph, pieces, solved, kept)
        if step == 0 and error(points) >= bound:
            return None
        angle[changed], folds[changed] = _angles(graph, points, changed)
        bad = (angle > limit) | folds
        if not bad.any():
            adapted = Solved(points, params, solved.steps)
            return Guarded(adapted, share, kept, rounds, error(points))
        # the share of its move a cell keeps to come as far under the bound as it is over
        # (its angle taken linear in the share kept), GENTLE at least: a cell just over the
        # bound gives up little of the front's compression; a fold keeps LOWER
        over, room = angle - limit, np.maximum(limit - before, 0.0)
        keep = np.clip((room - over) / np.maximum(room + over, 1e-12), GENTLE, 1.0)
        keep = np.where(folds, LOWER, keep)
        cut = _round(graph, np.where(bad, 1.0 - keep, 0.0))
        kept = kept * (1.0 - cut)
        mark = np.zeros(len(graph.cells) + 1, dtype=bool)
        mark[graph.node_cells[cut > 0.0]] = True
        changed = np.flatnonzero(mark[:-1])
    unadapted = Solved(graph.points.copy(), start_params, 0)
    return Guarded(unadapted, share * 0, kept * 0, rounds, error(graph.points))


def _scaled(
    graph: NodeGraph, pieces: list[Piece], solved: Solved, kept: np.ndarray
) -> tuple[np.ndarray, list[np.ndarray]]:
    """The grid whose nodes keep the share ``kept`` (n,) of their moves to ``solved``, a
    boundary node's along its piece's curve, and the pieces' arc lengths."""
    points = graph.points + kept[:, None] * (solved.points - graph.points)
    params = []
    for piece, s1 in zip(pieces, solved.params):
        s = piece.s + kept[piece.ids] * (s1 - piece.s)
        points[piece.ids] = piece.curve(s)
        params.append(s)
    return points, params


def _nearest(
    graph: NodeGraph,
    sources: list[tuple],
    limit: float,
    error: Callable[[np.ndarray], float],
    bound: float,
) -> list[tuple]:
    """The grid nearest one of ``sources`` (solved, share, blend) within ``limit``
    (interior nodes moved, boundary nodes slid along their pieces, the pieces' ends kept),
    as a source: of the sources that break the guard and carry the field better than
    ``bound``, the one of least error and the one of fewest offending cells (the nearest
    the bound), drawn back until no cell folds, the first whose nearest grid keeps the
    guard; none where none does."""
    pieces = pieces_of(graph)
    quads, orientation, folded = graph.lattice_cells
    free = ~graph.held
    for piece in graph.pieces:
        free[piece] = False
    scaled = []
    for solved, share, blend in sources:
        points, _ = _scaled(graph, pieces, solved, np.full(len(graph.points), blend))
        bad = int(offending(graph, points, limit).sum())
        if bad:
            scaled.append((error(points), bad, solved, share, blend))
    scaled = [s for s in scaled if s[0] < bound]
    if not scaled:
        return []
    least_error, fewest = (min(scaled, key=lambda s: s[k]) for k in (0, 1))
    for _, _, solved, share, blend in [least_error] + [fewest] * (fewest is not least_error):
        # a folded cell does not unfold by lowering its angles: drawn back first
        unfolded = _drawn_back(graph, solved, share, REFLEX, [], blend, error, np.inf).solved
        points, params = unfolded.points, unfolded.params
        cells = _rings(graph, offending(graph, points, limit), NEAREST_RINGS)
        near = np.isin(np.arange(len(points)), quads[cells])
        inner = [np.flatnonzero(near[p.ids[1:-1]]) + 1 for p in pieces]  # the ends stay
        slides = [Slide(p.ids[k], s[k], p.curve) for p, s, k in zip(pieces, params, inner)]
        moved, arcs = nearest_within(
            points, quads[cells], orientation[cells], free & near, limit, ~folded[cells], slides
        )
        if not offending(graph, moved, limit).any():
            slid = [s.copy() for s in params]
            for s, k, arc in zip(slid, inner, arcs):
                s[k] = arc
            return [(Solved(moved, slid, solved.steps), share, 1.0)]
    return []


def _rings(graph: NodeGraph, cells: np.ndarray, rings: int) -> np.ndarray:
    """The cells ``cells`` (a mask, m) and those within ``rings`` rings of them (sharing a
    node), as a mask."""
    m = len(graph.cells)
    for _ in range(rings):
        nodes = np.unique(graph.cells[cells])
        near = np.zeros(m + 1, dtype=bool)
        near[graph.node_cells[nodes].ravel()] = True
        cells = cells | near[:m]
    return cells
