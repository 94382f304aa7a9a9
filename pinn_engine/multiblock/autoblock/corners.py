"""The boundary's vertices that automatic blocking cuts from (SPEC 13): reflex vertices,
where the domain's outline turns the wrong way.

A block's outline may only turn left at its corners; a vertex whose interior angle exceeds
180 + ``CORNER_TURN`` degrees cannot be any block's corner or flat point, so at least one
block edge must leave it (the concave-corner rule of block decomposition): it is
``needed``. One that turns the wrong way by ``MILD_TURN`` or more (a Y's mouth, a
diverging wall) may emit an edge, where that makes better blocks.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pinn_engine.geometry.boundary import turning_angles
from pinn_engine.multiblock.blocks import CORNER_TURN

MILD_TURN = 12.0  # degrees: a vertex turning the wrong way by this much may emit an edge
# (below it a sampled curve's vertices, which stay inside blocks)
FILLET_SPAN = 0.05  # share of the diagonal: weaker turns this close together are one corner
# (a rounded corner; a bend's inner wall or a bump spans more)


@dataclass(frozen=True)
class Reflex:
    """A vertex ``point`` that a block edge must leave: ``d_in`` the unit direction of the
    outline arriving there, ``d_out`` leaving it (the domain on the outline's left),
    ``angle`` the interior angle (degrees, over 180) and whether an edge must leave it."""

    point: np.ndarray
    d_in: np.ndarray
    d_out: np.ndarray
    angle: float
    needed: bool


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _fillets(turns: np.ndarray, ring: np.ndarray, span: float) -> list[np.ndarray]:
    """Runs of consecutive vertices that each turn the wrong way by less than MILD_TURN,
    within ``span`` of each other end to end: a rounded concave corner drawn as an arc."""
    weak = (turns < 0) & (turns > -MILD_TURN)
    if weak.all() or not weak.any():
        return []
    start = int(np.flatnonzero(~weak)[0])  # walk the ring from a vertex outside every run
    order = np.roll(np.arange(len(ring)), -start)
    runs, run = [], []
    for i in [*order, order[0]]:
        # a run ends at a vertex that is not weak, or one a straight stretch away
        if run and (not weak[i] or np.linalg.norm(ring[i] - ring[run[-1]]) > 0.5 * span):
            runs.append(np.array(run))
            run = []
        if weak[i]:
            run.append(i)
    return [r for r in runs if len(r) > 1 and np.linalg.norm(ring[r[-1]] - ring[r[0]]) <= span]


def reflex_vertices(rings: list[np.ndarray], diagonal: float) -> list[Reflex]:
    """The vertices of ``rings`` turning the wrong way by MILD_TURN or more (each ring with
    the domain on its left: the outer ring counter-clockwise, holes clockwise), and the
    middles of rounded concave corners (runs of weaker turns within FILLET_SPAN of the
    ``diagonal``) that turn as much in all, with the directions arriving at and leaving the
    run."""
    out = []
    for ring in rings:
        turns = turning_angles(ring)
        d_in = _unit(ring - np.roll(ring, 1, axis=0))
        d_out = _unit(np.roll(ring, -1, axis=0) - ring)
        for i in np.flatnonzero(turns <= -MILD_TURN):
            needed = bool(turns[i] <= -CORNER_TURN)
            out.append(Reflex(ring[i].copy(), d_in[i], d_out[i], 180.0 - turns[i], needed))
        for run in _fillets(turns, ring, FILLET_SPAN * diagonal):
            total = float(turns[run].sum())
            if total <= -MILD_TURN:
                middle = run[len(run) // 2]
                needed = total <= -CORNER_TURN
                out.append(
                    Reflex(ring[middle].copy(), d_in[run[0]], d_out[run[-1]], 180.0 - total, needed)
                )
    return out


def corner_points(ring: np.ndarray) -> np.ndarray:
    """The points of ``ring`` where it turns by CORNER_TURN or more either way: where a
    block edge may end without leaving a sliver."""
    return ring[np.abs(turning_angles(ring)) >= CORNER_TURN]
