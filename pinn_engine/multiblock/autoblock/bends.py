"""Cuts where a wall's straight run meets its bend (SPEC 13): the places a careful user
blocks a bend apart from its legs.

A bend drawn as sampled arcs between straight legs is four-sided when its legs end square,
so it is one block: its grid lines then spread the bend's unequal inner and outer walls
over the whole length of the legs, and its cells shear. Where a straight run of a wall
(``FILLET_SPAN`` of the diagonal or longer, as a rounded corner's span) meets a run of
weak turns, the wall has a *junction*; two junctions that see each other across the
domain along a line leaving both walls at a block corner's angle or more give a cut. The
search then meshes the layouts with and without each cut and keeps the best-ranked, as it
chooses among reflex vertices' edges.

A *kink*, one vertex turning weakly between two straight runs, is a bend of one vertex (a
Y's inlet meeting the walls that widen to its arms: a mouth). Where the search finds no
layout that meshes, it searches again with the cuts between junctions and kinks in every
domain, each cut taken or not beside the edges from reflex vertices.
"""

from __future__ import annotations

import itertools

import numpy as np
from shapely.geometry import LineString, Polygon

from pinn_engine.geometry.boundary import turning_angles
from pinn_engine.multiblock.autoblock.corners import FILLET_SPAN
from pinn_engine.multiblock.blocks import CORNER_TURN

BEND_TURN = 1.0  # degrees: a vertex turning less is on a straight run (a sampled bend turns
# more at each of its points)
MAX_CUTS = 3  # cuts whose subsets are all searched (2 ** 3 layouts); more: none or all


def junctions(ring: np.ndarray, diagonal: float) -> list[int]:
    """The vertices of ``ring`` where a straight run at least FILLET_SPAN of the
    ``diagonal`` long meets a run of weak turns (a bend's first and last points)."""
    turns = np.abs(turning_angles(ring))
    curved = (turns >= BEND_TURN) & (turns < CORNER_TURN)
    n = len(ring)
    out = []
    for i in np.flatnonzero(curved):
        for step in (-1, 1):
            if not curved[(i + step) % n]:
                continue
            length, k = 0.0, i
            while True:  # the straight run on the other side, to its first turning vertex
                j = (k - step) % n
                length += float(np.linalg.norm(ring[j] - ring[k]))
                if turns[j] >= BEND_TURN or j == i:
                    break
                k = j
            if length >= FILLET_SPAN * diagonal:
                out.append(int(i))
                break
    return out


def kinks(ring: np.ndarray) -> list[int]:
    """The vertices of ``ring`` that turn weakly (BEND_TURN to a corner's turn) between two
    that do not turn: bends of one vertex."""
    turns = np.abs(turning_angles(ring))
    curved = (turns >= BEND_TURN) & (turns < CORNER_TURN)
    return [int(i) for i in np.flatnonzero(curved & ~np.roll(curved, 1) & ~np.roll(curved, -1))]


def bend_cuts(
    rings: list[np.ndarray], diagonal: float, with_kinks: bool = False
) -> list[np.ndarray]:
    """The cuts (2, 2) between junctions of the outer ring (``rings[0]``), and ``with_kinks``
    its kinks, that see each other inside the domain, each cut to the nearest one whose
    line leaves both walls at a block corner's angle or more (mutual nearest only)."""
    ring = rings[0]
    found = sorted(set(junctions(ring, diagonal) + (kinks(ring) if with_kinks else [])))
    domain = Polygon(ring, [r for r in rings[1:]])
    n = len(ring)
    tangent = {i: ring[(i + 1) % n] - ring[i - 1] for i in found}
    steep = np.cos(np.radians(CORNER_TURN))

    def leaves(i: int, d: np.ndarray) -> bool:
        t = tangent[i]
        return abs(t @ d) <= steep * np.linalg.norm(t) * np.linalg.norm(d)

    nearest = {}
    for i in found:
        best = None
        for j in found:
            d = ring[j] - ring[i]
            if j == i or not (leaves(i, d) and leaves(j, d)):
                continue
            if not domain.buffer(1e-9 * diagonal).contains(LineString([ring[i], ring[j]])):
                continue
            if best is None or np.linalg.norm(d) < np.linalg.norm(ring[best] - ring[i]):
                best = j
        nearest[i] = best
    pairs = {tuple(sorted((i, j))) for i, j in nearest.items() if j is not None and nearest[j] == i}
    return [np.array([ring[i], ring[j]]) for i, j in sorted(pairs)]


def cut_choices(cuts: list[np.ndarray]) -> list[list[np.ndarray]]:
    """The sets of ``cuts`` the search tries: every subset of up to MAX_CUTS, else none
    and all."""
    if len(cuts) > MAX_CUTS:
        return [[], cuts]
    return [list(c) for k in range(len(cuts) + 1) for c in itertools.combinations(cuts, k)]
