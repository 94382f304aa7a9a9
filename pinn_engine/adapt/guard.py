"""SPEC 14's guard: no fold, and no cell whose MaxIncludedAngle exceeds the unadapted
grid's worst by more than ``GUARD_DEGREES``. Where the adapted grid breaks it, the strength
is lowered where it breaks (the monitor flattened round the offending cells) and the grid
solved again from where it was; what still breaks after ``ROUNDS`` is drawn back toward
the unadapted grid (each node's move, a boundary node's along its curve, scaled down
round the offending cells) until it holds. The first solve's moves scaled down everywhere,
then drawn back the same way, are further candidates; the one carrying the field best is
kept."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pinn_engine.adapt.error import interpolation_error
from pinn_engine.adapt.monitor import to_nodes
from pinn_engine.adapt.nodes import NodeGraph
from pinn_engine.adapt.parametric import ParameterSpace
from pinn_engine.adapt.pieces import Solved, pieces_of
from pinn_engine.quality import cell_quality

GUARD_DEGREES = 10.0  # SPEC 14: the worst cell may exceed the unadapted grid's by this much
ROUNDS = 12  # solves with the strength lowered round the offending cells, at most
# a round that leaves more than this share of the last round's offending cells is the last:
# the cells left are pulled by the monitor farther away, and the draw-back takes them
PROGRESS = 0.8
LOWER = 0.7  # each round multiplies the strength round an offending cell by this
# the lowering reaches this many rings of cells round an offending cell, fading: a strength
# cut at one node alone would crease the monitor there
SPREAD = 6
DRAWBACKS = 40  # rounds of drawing moves back, at most (each scales moves by at most LOWER)
# where the first solve breaks the guard, its moves scaled by each of these everywhere are
# also drawn back: a front's compression kept whole at a lower amplitude (the lowering cuts
# it where it is strongest); the candidate carrying the field best is kept
BLENDS = (0.8, 0.6, 0.4)


@dataclass
class Guarded:
    """The grid that keeps the guard, each node's share of the strength asked (1: all of
    it), the share of each node's move kept by the draw-back, the solves made, and the
    grid's interpolation error (``within`` False: the first solve broke the guard and
    already carried the field no better than the bound asked, so it was not guarded)."""

    solved: Solved
    share: np.ndarray
    kept: np.ndarray
    rounds: list[dict] = field(default_factory=list)
    error: float = np.inf
    within: bool = True


def offending(graph: NodeGraph, points: np.ndarray, limit: float) -> np.ndarray:
    """Which cells fold (that the unadapted grid does not fold) or have a MaxIncludedAngle
    over ``limit``, in ``graph.cells`` order."""
    bad = []
    for grid, folded in zip(graph.grids(points), graph.folded):
        q = cell_quality(grid)
        bad.append((((q["MaxIncludedAngle"] > limit) | q["Folded"]) & ~folded).ravel())
    return np.concatenate(bad)


def _round(graph: NodeGraph, bad: np.ndarray) -> np.ndarray:
    """1 at the nodes of offending cells, fading over ``SPREAD`` rings round them."""
    n = len(graph.points)
    near = to_nodes(graph.cells, bad.astype(float), n) > 0
    weight = near.astype(float)
    for ring in range(1, SPREAD + 1):
        grown = to_nodes(graph.cells, weight[graph.cells].max(axis=1), n) > 0
        weight = np.maximum(weight, np.where(grown, 1.0 - ring / (SPREAD + 1), 0.0))
    return weight


def guarded(
    graph: NodeGraph,
    space: ParameterSpace,
    strength: float,
    limit: float,
    isotropic: bool = False,
    bound: float = np.inf,
) -> Guarded:
    """The grid adapted with ``strength`` lowered where the guard (``limit`` degrees, no
    fold) needs it (``isotropic``: the diffusion tensor's form, :meth:`ParameterSpace.solve`);
    not guarded where its first solve breaks the guard and carries the field no better than
    ``bound`` (the guard's lowering and draw-back adapt less: they seldom gain it back)."""
    n = len(graph.points)
    share = np.ones(n)

    def error(points: np.ndarray) -> float:
        return interpolation_error(points, graph.cells, space.sample)

    first = solved = space.solve(share * strength, isotropic)
    bad = offending(graph, solved.points, limit)
    rounds = [{"steps": solved.steps, "offending_cells": int(bad.sum())}]
    now = error(solved.points)
    if not bad.any() or now >= bound:
        return Guarded(solved, share, np.ones(n), rounds, now, within=not bad.any())
    for _ in range(ROUNDS - 1):
        share = share * (1.0 - (1.0 - LOWER) * _round(graph, bad))
        solved = space.solve(strength * share, isotropic)
        bad = offending(graph, solved.points, limit)
        rounds.append({"steps": solved.steps, "offending_cells": int(bad.sum())})
        if not bad.any() or bad.sum() > PROGRESS * rounds[-2]["offending_cells"]:
            break
    candidates = [_drawn_back(graph, solved, share, limit, rounds)] + [
        _drawn_back(graph, first, np.ones(n), limit, rounds, blend) for blend in BLENDS
    ]
    for candidate in candidates:
        candidate.error = error(candidate.solved.points)
    return min(candidates, key=lambda c: c.error)


def _drawn_back(
    graph: NodeGraph,
    solved: Solved,
    share: np.ndarray,
    limit: float,
    rounds: list[dict],
    blend: float = 1.0,
) -> Guarded:
    """``solved`` with its moves scaled by ``blend``, then down round the offending cells
    until none is left (the unadapted grid, all moves undone, keeps the guard)."""
    pieces = pieces_of(graph)
    start_params = [p.s.copy() for p in pieces]
    kept = np.full(len(graph.points), blend)
    points = solved.points
    for _ in range(DRAWBACKS):
        points = graph.points + kept[:, None] * (solved.points - graph.points)
        params = []
        for piece, s0, s1 in zip(pieces, start_params, solved.params):
            s = s0 + kept[piece.ids] * (s1 - s0)
            points[piece.ids] = piece.curve(s)
            params.append(s)
        bad = offending(graph, points, limit)
        if not bad.any():
            return Guarded(
                Solved(points, params, solved.monitor, solved.steps), share, kept, rounds
            )
        kept = kept * (1.0 - (1.0 - LOWER) * _round(graph, bad))
    return Guarded(
        Solved(graph.points.copy(), start_params, solved.monitor, 0), share * 0, kept * 0, rounds
    )
