"""Cell counts of a multi-block domain (SPEC 10): opposite sides of every block get the
same number of cells, each piece about ``cell_size`` long cells.

Where every side is one piece this is SPEC 10's chain rule (union-find over opposite
sides gives the same: each chain takes its longest side over H, rounded up). A side of
several pieces (an edge ending on a straight stretch of another side, a T-junction) needs
sums instead, so counts start at each piece's length over H and the smaller of two
opposite sides gains cells, on its coarsest piece, until every block agrees.
"""

from __future__ import annotations

import numpy as np

from pinn_engine.errors import InputError
from pinn_engine.multiblock.blocks import Topology

MIN_SIDE_CELLS = 2  # SPEC 10: a chain has at least 2 cells
DIAGONAL_CELLS = 40  # SPEC 10: the default cell size is the domain's diagonal over this
# Cells added in all before the counts are declared impossible to match (a block whose
# opposite sides share pieces in a way no counts satisfy would otherwise add cells forever)
MAX_ADDED = 200_000


def cell_counts(topo: Topology, cell_size: float) -> np.ndarray:
    """Cells per piece of ``topo`` for cells about ``cell_size`` long."""
    lengths = np.array([p.length for p in topo.pieces])
    counts = np.maximum(1, np.ceil(lengths / cell_size - 1e-9)).astype(int)

    def total(side) -> int:
        return int(sum(counts[p] for p, _ in side))

    def refine(side, to: int) -> None:
        while total(side) < to:
            coarse = max(side, key=lambda q: lengths[q[0]] / counts[q[0]])[0]
            counts[coarse] += 1

    for block in topo.blocks:
        for side in block.sides:
            refine(side, MIN_SIDE_CELLS)
    added, changed = 0, True
    while changed:
        changed = False
        for block in topo.blocks:
            for a, b in ((0, 2), (1, 3)):
                na, nb = total(block.sides[a]), total(block.sides[b])
                if na != nb:
                    added += abs(na - nb)
                    refine(block.sides[a] if na < nb else block.sides[b], max(na, nb))
                    changed = True
            if added > MAX_ADDED:
                x, y = block.inside
                raise InputError(
                    f"no cell counts give the block at ({x:.4g}, {y:.4g}) equal opposite "
                    "sides; move the block edges that end on its sides"
                )
    return counts


def default_cell_size(diagonal: float) -> float:
    """SPEC 10's default cell size for a domain of this ``diagonal``."""
    return diagonal / DIAGONAL_CELLS
