"""A layout judged by its grid (SPEC 13): the elliptic multi-block grid of the boundary cut by
the layout's edges, at the cell size the run asks (SPEC 10's default where it asks none), its
quality and interface kinks weighed into one figure (lower is better). A layout is judged as
it will be meshed: at the run's size (one clean at the default size may fold at a finer one,
a diamond near a floor, or rank differently, a wide leaning tee) and, where the run asks a
wall spacing, with it (a reflex corner left inside a block's side carries the spacing
through that block, which suits one of an open cavity's two mirror-image layouts and
shears the other), a grid with a face checkMesh finds too skewed, or with first edges off
the spacing beyond SPEC 7's tolerance, out, as the run would refuse to write it.

The solve stops after ``SCORE_ITERATIONS`` Picard steps: the examples converge in under 100,
and a layout whose sliding ends still move after that is judged where they are.
"""

from __future__ import annotations

import numpy as np

from pinn_engine.blocks3d.checks import SKEW_LIMIT, planar_figures
from pinn_engine.errors import InputError
from pinn_engine.multiblock.autoblock.faces import place
from pinn_engine.multiblock.blocks import topology
from pinn_engine.multiblock.counts import cell_counts, default_cell_size
from pinn_engine.multiblock.elliptic import crossings, winslow
from pinn_engine.multiblock.graph import linework
from pinn_engine.multiblock.mesh import interface_kinks, layout_checked, mesh_blocks
from pinn_engine.multiblock.walls import Walls, first_edges_refusal
from pinn_engine.quality import cell_quality
from pinn_engine.settings import make_settings

SCORE_ITERATIONS = 200  # Picard steps at most for a layout's grid
# a degree of the worst MaxIncludedAngle against one of the mean, tuned on the tuning tees
# of benchmarks/autoblock_users.py: no layout buys a better mean with a worst cell beyond
# SPEC 13's 10 degrees over a careful hand blocking's
WORST_WEIGHT = 0.25
KINK_WEIGHT = 1.5  # a degree of mean interface kink against one of mean MaxIncludedAngle
BLOCK_WEIGHT = 0.25  # degrees of mean MaxIncludedAngle one block fewer is worth
KINK_BOUND = 3.0  # SPEC 13's bound on the mean interface kink (degrees), whatever the hand
# a degree of mean kink beyond KINK_BOUND counts this many degrees of mean MaxIncludedAngle
# more: a layout over the bound must be that much better elsewhere (one block of a round
# U-bend, 26 degrees worse on the mean than its three blocks just over the bound, stays out)
OVER_BOUND = 3.0
# layouts are judged no finer than the default cell size over this: search.MAX_MESHED (8)
# solves of at most 16 times the default's cells bound the search's time
FINEST = 4.0


class Rejected(Exception):
    """A layout whose grid the run would not write, and why, a verb's phrase ("folds 2
    cells ..."): a refusal names the nearest to meshing."""

    def __init__(self, reason: str, folds: float = np.inf) -> None:
        super().__init__(reason)
        self.folds = folds  # folded cells (the nearest to meshing folds fewest); inf: no grid


def scoring_size(diagonal: float, cell_size: float = 0.0) -> float:
    """The cell size a layout is judged at: the run's ``cell_size`` (0: SPEC 10's default),
    no finer than the default over ``FINEST``."""
    default = default_cell_size(diagonal)
    return default if cell_size <= 0 else max(cell_size, default / FINEST)


def score(
    rings: list[np.ndarray],
    edges: list[np.ndarray],
    cell_size: float = 0.0,
    walls: Walls | None = None,
    patches: tuple = (),
    exact: bool = False,
    bounded: bool = True,
) -> float:
    """The grid's mean MaxIncludedAngle at ``scoring_size(cell_size)``, with the worst, the
    mean interface kink and the block count weighed in; Rejected, with the reason, when it
    folds or cannot be meshed. With a spacing in ``walls`` (on the ``patches`` the run
    names), the grid is the run's own: meshed with the spacing. ``exact``: at ``cell_size``
    itself, however fine. ``bounded``: a mean kink beyond SPEC 13's bound weighed more (a
    run without a wall spacing, as the bound is measured: with one, the kinks are the wall
    rows' stretching across the interfaces, 50 to 100 degrees whatever the layout)."""
    names = [f"edge {k}" for k in range(len(edges))]
    try:
        lines = linework(rings, edges, names, "auto")
        h = cell_size if exact and cell_size > 0 else scoring_size(lines.diagonal, cell_size)
        if walls is not None and walls.spacing:
            settings = make_settings("elliptic", cell_size=h)
            result = mesh_blocks(rings, edges, names, settings, "auto", patches, walls)
            skew = planar_figures(result.grids).max_skewness
            if skew > SKEW_LIMIT:  # the run would refuse to write it (job.cover)
                raise Rejected(f"has a face skewed {skew:.3g} (checkMesh's limit {SKEW_LIMIT:g})")
            off = first_edges_refusal(result.report)
            if off is not None:  # the run would refuse to write it (job.cover)
                raise Rejected(f"misses the spacing asked: {off}")
            kink = result.report["interface_kink"]["mean"]
            return _weighed(result.grids, kink, bounded, h)
        topo = topology(lines)
        lay = layout_checked(topo, cell_counts(topo, h), h)
        points, _ = winslow(topo, lay, True, SCORE_ITERATIONS)
    except InputError as exc:
        raise Rejected(f"is refused ({exc.template})") from exc  # in the route's words
    except (ArithmeticError, RuntimeError, np.linalg.LinAlgError) as exc:
        raise Rejected("breaks its elliptic solve down (a singular system)") from exc
    kinks = interface_kinks(crossings(topo, lay), lay, points)
    grids = [points[ids] for ids in lay.ids]
    return _weighed(grids, float(kinks.mean()) if kinks.size else 0.0, bounded, h)


def _weighed(grids: list[np.ndarray], kink: float, bounded: bool, h: float) -> float:
    """The score of the blocks' ``grids`` at cell size ``h`` and their mean interface
    ``kink``, a kink beyond SPEC 13's bound weighed more where ``bounded``; Rejected, naming
    the first folded cell, when a cell folds."""
    cells = [cell_quality(grid) for grid in grids]
    folds = sum(int(c["Folded"].sum()) for c in cells)
    if folds:
        grid, c = next((g, c) for g, c in zip(grids, cells) if c["Folded"].any())
        j, i = np.argwhere(c["Folded"])[0]
        where = place(np.asarray(grid)[j : j + 2, i : i + 2, :2].reshape(-1, 2).mean(axis=0), h)
        cells_folded = f"{folds} cell{'s' * (folds > 1)}"
        raise Rejected(f"folds {cells_folded} at cell size {h:.4g}, at {where}", folds)
    angles = np.concatenate([c["MaxIncludedAngle"].ravel() for c in cells])
    return (
        float(angles.mean())
        + WORST_WEIGHT * float(angles.max())
        + KINK_WEIGHT * kink
        + BLOCK_WEIGHT * len(grids)
        + OVER_BOUND * max(kink - KINK_BOUND, 0.0) * bounded
    )
