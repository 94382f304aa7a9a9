"""The adaptation of a 2D grid's blocks to a field (SPEC 14): the monitor's strength tried
and weakened, each try's grid guarded, the one that carries the field best kept, and its
report."""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from pinn_engine.adapt.error import interpolation_error
from pinn_engine.adapt.field import Field
from pinn_engine.adapt.guard import GUARD_DEGREES, guarded
from pinn_engine.adapt.monitor import equidistribution, gradient_size, monitor_values
from pinn_engine.adapt.nodes import NodeGraph, node_graph
from pinn_engine.adapt.parametric import ParameterSpace
from pinn_engine.quality import cell_quality
from pinn_engine.settings import ADAPT_STRENGTH

DEFAULT_STRENGTH = ADAPT_STRENGTH  # the default strength beta (settings, measured there)
# Each form's strengths: the one asked times WEAKER**k, k = 0 to STRENGTHS - 1, strongest
# first, stopping at the first no better than the form's last try (past its best); the
# lowest interpolation error of all wins, else the unadapted grid. A sixteenth is reached:
# the guard binds at about beta 2 to 5 (docs/adaptation.md)
STRENGTHS = 5
WEAKER = 0.5
# The tensor's forms (curvature, isotropic, joined): the gradient's monitor across a front
# only (a front, a layer), a multi-block grid's blocks joined for it (its junctions and
# interfaces move with the front); Winslow's isotropic 1/M (a feature a few cells wide
# every way, a vortex's core); the interpolation error's curvature metric, anisotropic and
# isotropic (a front's flanks, where linear interpolation errs)
FORMS = ((False, False, True), (False, True, False), (True, False, False), (True, True, False))


@dataclass
class Adapted:
    """Each block's adapted grid (nj, ni, 2), its monitor at the nodes (nj, ni) and the
    report of SPEC 14 (strength asked and used, equidistribution before and after, the
    largest node move, the worst cell before and after)."""

    grids: list[np.ndarray]
    monitor: list[np.ndarray]
    report: dict


def _worst(graph: NodeGraph, points: np.ndarray) -> tuple[float, int]:
    """The worst MaxIncludedAngle of the cells that do not fold (the guard's base) and the
    folded cells of the blocks at ``points``."""
    cells = [cell_quality(g) for g in graph.grids(points)]
    return (
        max(float(c["MaxIncludedAngle"][~c["Folded"]].max(initial=0.0)) for c in cells),
        sum(int(c["Folded"].sum()) for c in cells),
    )


def adapt_grids(
    grids: list[np.ndarray],
    field: Field,
    strength: float = DEFAULT_STRENGTH,
    held: list[np.ndarray] | None = None,
) -> Adapted:
    """``grids`` (each block (nj, ni, 2)) adapted to ``field`` with the monitor's
    ``strength`` beta; ``held``: per block, a mask (nj, ni) of nodes that stay (a wall's
    nodes and its first row, where a first edge or wall angle was asked)."""
    began = time.perf_counter()
    graph = node_graph([np.asarray(g, dtype=float) for g in grids], held)
    field.check_covers(graph.points)

    def sample(points: np.ndarray) -> np.ndarray:
        return field.sample(points)

    start = graph.points
    gradient = gradient_size(start, graph.cells, sample(start))
    largest = float(gradient.max())
    worst0, folded0 = _worst(graph, start)
    limit = worst0 + GUARD_DEGREES
    error0 = interpolation_error(start, graph.cells, sample)
    space = ParameterSpace(graph, sample, limit)
    points, share, rounds, error, used = start, np.zeros(len(start)), [], error0, 0.0
    form, moved = "unadapted", False
    # each form's first solve (the strength asked) is made before any is guarded, and the
    # forms are tried in the order of its error, least first: the best grid found early
    # bounds the others' guard (a candidate carrying the field no better is not drawn back)
    firsts = {}
    for curvature, isotropic, joined in FORMS if largest > 0 else ():
        solved = space.solve(np.full(len(start), strength), isotropic, False, curvature, joined)
        firsts[curvature, isotropic, joined] = (
            solved,
            interpolation_error(solved.points, graph.cells, sample),
        )
    order = sorted(firsts, key=lambda f: firsts[f][1])
    for curvature, isotropic, joined in order:
        last = np.inf
        name = ("joined " if joined and space.joined else "") + ("curvature " if curvature else "")
        name += "isotropic" if isotropic else "anisotropic"
        for k in range(STRENGTHS):
            beta = strength * WEAKER**k
            first = firsts[curvature, isotropic, joined] if k == 0 else None
            found = guarded(
                graph, space, beta, limit, isotropic, error, curvature, joined, first, error0
            )
            rounds.append(
                {"form": name, "strength": beta, "error": found.error, "solves": found.rounds}
            )
            if found.within and found.error < error:
                points, share, error = found.solved.points, found.share * found.kept, found.error
                used, form, moved = beta, name, found.moved
            if found.error >= last:
                break
            last = found.error
    final = gradient_size(points, graph.cells, sample(points))
    m_used = monitor_values(final, strength * share, largest)
    m_start = monitor_values(gradient, strength, largest)
    m_after = monitor_values(final, strength, largest)
    worst, folded = _worst(graph, points)
    moves = np.linalg.norm(points - start, axis=1)
    report = {
        "field": field.source,
        "array": field.array,
        "method": "elliptic",
        "strength": strength,
        "strength_used": used,
        "form": form,
        "adapted_less": bool(used < strength or (share < 1.0).any() or moved),
        "moved_within_bound": moved,
        "strength_share": {
            "min": float(share.min()),
            "mean": float(share.mean()),
            "nodes_below_full": int((share < 1.0).sum()),
        },
        "equidistribution_cv": {
            "before": equidistribution(start, graph.cells, m_start),
            "after": equidistribution(points, graph.cells, m_after),
        },
        "largest_node_move": float(moves.max()),
        "largest_node_move_share": float(moves.max() / graph.diagonal),
        "worst_max_angle": {"before": worst0, "after": worst, "limit": limit},
        "folded_cells": {"before": folded0, "after": folded},
        "interpolation_error": {"before": error0, "after": error},
        "tries": rounds,
        "held_nodes": int(graph.held.sum()),
        "seconds": time.perf_counter() - began,
    }
    return Adapted(graph.grids(points), [m_used[ids] for ids in graph.ids], report)
