"""Automatic blocking (SPEC 13): block edges proposed from the boundary and its holes alone.

``propose_edges`` is the entry: O-rings round holes (``orings.py``), cuts where a one-block
domain's bends begin (``bends.py``), one edge from each
reflex vertex of the boundary and the boxes (``rays.py``: a motorcycle graph of the cross
field's separatrices), faces of other than four corners cut round their centres
(``faces.py``), the choice among them (``search.py``) by their elliptic grids' quality
(``score.py``). docs/blocking.md explains the method.
"""

from __future__ import annotations

import itertools
import time
from collections import Counter
from dataclasses import dataclass

import numpy as np
from shapely.geometry import LineString, Point

from pinn_engine.errors import InputError
from pinn_engine.multiblock.autoblock.bends import bend_cuts, cut_choices
from pinn_engine.multiblock.autoblock.corners import corner_points, reflex_vertices
from pinn_engine.multiblock.autoblock.orings import ORing, main_axes, ring_forms
from pinn_engine.multiblock.autoblock.rays import layered, motorcycles, ray_options
from pinn_engine.multiblock.autoblock.score import Rejected, score, scoring_size
from pinn_engine.multiblock.autoblock.search import best_meshed, candidates, ranked
from pinn_engine.multiblock.graph import order_rings
from pinn_engine.multiblock.walls import Walls

ON_WALL = 1e-9  # share of the diagonal: a box corner this close to the outer ring is on it


def _segments(curves: list[np.ndarray], closed: bool) -> np.ndarray:
    out = []
    for c in curves:
        b = np.roll(c, -1, axis=0) if closed else c[1:]
        a = c if closed else c[:-1]
        out.append(np.stack([a, b], axis=1))
    return np.concatenate(out) if out else np.zeros((0, 2, 2))


def propose_edges(
    rings: list[np.ndarray],
    source: str = "boundary",
    layers: bool = False,
    cell_size: float = 0.0,
    walls: Walls | None = None,
    patches: tuple = (),
) -> list[np.ndarray]:
    """Block edges (straight polylines (2, 2)) that cut the domain of ``rings`` (the outer
    boundary and holes, any order and orientation) into four-cornered blocks; none for a
    four-sided domain. With ``layers`` (walls with a first-edge spacing), a reflex vertex
    whose two sides both carry on into the domain (a step's lip, an L's inner corner)
    emits both: each wall's boundary layer then runs on along a block edge, so its spacing
    has a chain to run along on both sides of the corner; where no layout has both at every
    such vertex (a sharp step's lip facing a wall two cells away), the layouts without
    spacing are searched. The layouts are judged by their grids as the run meshes them: at
    its ``cell_size`` (0: SPEC 10's default; ``score.scoring_size``, and where that is
    coarser, the winner meshed again at the run's size, the next best where it folds) and
    with its ``walls``' spacing on its ``patches`` (without it where every layout folds with
    it). Where no layout meshes, the search widens: each subset of the cuts between the
    outer wall's kinks and bends' ends (``bends.bend_cuts``) in every domain. A one-line
    InputError says why when no blocking is found: the commonest reason a layout tried is
    no blocking, or the nearest to meshing of the layouts meshed."""
    rings = order_rings([np.asarray(r, dtype=float)[:, :2] for r in rings], source)
    diagonal = float(np.linalg.norm(np.ptp(rings[0], axis=0)))
    axes = main_axes(rings[0])
    # each hole's rings (free, reaching a wall), close holes' shared ones: every
    # combination is searched
    forms = ring_forms(rings, axes)
    failures: Counter[str] = Counter()  # why each layout tried is no blocking

    def layouts_of(cuts: list[np.ndarray] | None) -> list[tuple[float, list[np.ndarray]]]:
        found = []
        for form in forms:
            found += _layouts(rings, list(form), diagonal, layers, failures, cuts)
        return ranked(found)

    layouts = layouts_of(None)
    if len(rings) == 1 and len(layouts) == 1 and not reflex_vertices(rings, diagonal):
        return layouts[0][1]  # four-sided (or cut round its centre): nothing to choose
    finer = 0 < cell_size < scoring_size(diagonal, cell_size)  # judged coarser than meshed
    bounded = walls is None or not walls.spacing  # SPEC 13's kink bound: no wall spacing

    def judged(layouts: list, spacing: Walls | None) -> list[np.ndarray]:
        return best_meshed(
            layouts,
            lambda edges: score(rings, edges, cell_size, spacing, patches, bounded=bounded),
            (lambda edges: score(rings, edges, cell_size, spacing, patches, True, bounded))
            if finer
            else None,
        )

    def meshed(layouts: list) -> list[np.ndarray]:
        try:
            return judged(layouts, walls)
        except Rejected:
            if walls is None or not walls.spacing:
                raise
        # every layout folds with the spacing before the run untangles its blocks (a body
        # near a wall): judged without it, as the untangling is too dear to try on each
        return judged(layouts, None)

    rejected: list[Rejected] = []
    for widened in (False, True):
        if widened:  # none meshes: the search widens to cuts between the walls' kinks, bends
            cuts = bend_cuts(rings, diagonal, with_kinks=True)
            layouts = layouts_of(cuts) if cuts else []
        if layouts:
            try:
                return meshed(layouts)
            except Rejected as exc:
                rejected.append(exc)
    if not rejected:
        raise InputError(
            f"automatic blocking found no four-cornered blocks ({_commonest(failures)}): "
            "draw the block edges and {blocks}",
            source,
        )
    nearest = min(rejected, key=lambda exc: exc.folds)
    raise InputError(
        f"automatic blocking found no layout that meshes without folds ({nearest}): draw the "
        "block edges and {blocks}",
        source,
    )


def _layouts(
    rings: list[np.ndarray],
    orings: list[ORing],
    diagonal: float,
    layers: bool,
    failures: Counter[str],
    cuts: list[np.ndarray] | None = None,
) -> list[tuple[float, list[np.ndarray]]]:
    """The feasible layouts (cost, edges) of ``rings`` with one ring ``orings`` round each
    hole (each in its O form or, where it has one, its C-shaped form), edges from the
    reflex vertices of the outer ring and the boxes (with ``layers``, both continuations
    where every vertex has them and any layout is found), or cuts where bends begin; with
    ``cuts``, each subset of them in every domain, the rays stopping at them. Why each
    layout tried is no blocking is counted in ``failures``."""
    boxes = [ring.box[::-1] for ring in orings]  # clockwise: the domain outside on its left
    rings_edges = [[r.edges] + ([r.c_shaped] if r.c_shaped is not None else []) for r in orings]
    ring_choices = [sum(choice, []) for choice in itertools.product(*rings_edges)]
    wall = LineString(np.vstack([rings[0], rings[0][:1]]))
    vertices = reflex_vertices([rings[0]], diagonal) + [
        v  # a box corner on the wall (a ring reaching it) is where an edge meets the wall
        for v in reflex_vertices(boxes, diagonal)
        if wall.distance(Point(v.point)) > ON_WALL * diagonal
    ]
    if cuts is None and not vertices and len(rings) == 1:  # one block, unless cut at bends
        cuts = bend_cuts(rings, diagonal)
    fixed_choices = [(ring, cut) for ring in ring_choices for cut in cut_choices(cuts or [])]
    fixed = _segments([rings[0], *boxes], True)
    options = [ray_options(v, fixed, diagonal) for v in vertices]
    # with layers, both continuations where a vertex has them; where no layout has them
    # all, the layouts of no spacing (a reflex corner left inside a block's side carries the
    # spacing through that block: spacing.held_pieces)
    both = [
        ([o for o in opts if len(o) == 2] if layered(v) else []) or opts
        for v, opts in zip(vertices, options)
    ]
    tries = [both, options] if layers and both != options else [options]
    targets = np.vstack(
        [corner_points(rings[0]), *boxes, np.array([v.point for v in vertices]).reshape(-1, 2)]
    )

    def builder(cut: list[np.ndarray]):
        segments = np.concatenate([fixed, _segments(cut, False)])
        return lambda rays: motorcycles(rays, segments, targets, diagonal)

    for choices in tries:
        layouts = [
            layout
            for ring, cut in fixed_choices
            for layout in candidates(vertices, choices, builder(cut), rings, ring + cut, failures)
        ]
        if layouts:
            return layouts
    return []


@dataclass
class Proposal:
    """The edges proposed for a domain, their names in messages, and what the run's report
    says of the blocking (``mode``, ``edges``, ``seconds``)."""

    edges: list[np.ndarray]
    names: list[str]
    report: dict


def proposal(
    rings: list[np.ndarray],
    source: str = "boundary",
    cell_size: float = 0.0,
    walls: Walls | None = None,
    patches: tuple = (),
) -> Proposal:
    """:func:`propose_edges` for a run (its cell size, its walls' spacing on its patches:
    both continuations of a reflex corner sought where it asks a spacing), named and timed
    for its report."""
    start = time.perf_counter()
    layers = walls is not None and bool(walls.spacing)
    edges = propose_edges(rings, source, layers, cell_size, walls, patches)
    seconds = time.perf_counter() - start
    names = [f"proposed edge {k}" for k in range(len(edges))]
    return Proposal(edges, names, {"mode": "automatic", "edges": len(edges), "seconds": seconds})


def _commonest(failures: Counter[str]) -> str:
    """The reason most layouts tried are no blocking, and in how many of them."""
    reason, count = failures.most_common(1)[0]
    total = sum(failures.values())
    return reason if total == 1 else f"{reason}, in {count} of the {total} layouts tried"


__all__ = ["Proposal", "proposal", "propose_edges"]
