"""Cell counts of a multi-block domain (SPEC 10): opposite sides of every block get the
same number of cells, each piece about ``cell_size`` long cells, the chains named by
``--cells X,Y=N`` exactly N, and the chains along a ``--spacing X,Y=H`` grading enough for
it (``chains.py``).

Where every side is one piece this is SPEC 10's chain rule (union-find over opposite
sides gives the same: each chain takes its longest side over H, rounded up). A side of
several pieces (an edge ending on a straight stretch of another side, a T-junction) needs
sums instead, so counts start at each piece's length over H and the smaller of two
opposite sides gains cells, on its coarsest piece not fixed, until every block agrees.
"""

from __future__ import annotations

import numpy as np

from pinn_engine.errors import InputError
from pinn_engine.multiblock.blocks import Topology
from pinn_engine.multiblock.chains import MIN_SIDE_CELLS, SideItem, piece_chains

DIAGONAL_CELLS = 40  # SPEC 10: the default cell size is the domain's diagonal over this
# Cells added in all before the counts are declared impossible to match (a block whose
# opposite sides share pieces in a way no counts satisfy would otherwise add cells forever)
MAX_ADDED = 200_000


def cell_counts(
    topo: Topology,
    cell_size: float,
    fixed: dict[int, SideItem] | None = None,
    minimum: dict[int, tuple[int, SideItem]] | None = None,
) -> np.ndarray:
    """Cells per piece of ``topo`` for cells about ``cell_size`` long; ``fixed``: piece ->
    its ``--cells`` item (the piece's chain gets exactly that count); ``minimum``: piece ->
    (least count, the item asking it) for its chain."""
    lengths = np.array([p.length for p in topo.pieces])
    counts = np.maximum(1, np.ceil(lengths / cell_size - 1e-9)).astype(int)
    chain = piece_chains(topo)
    held = np.zeros(len(counts), dtype=bool)
    why: dict[int, SideItem] = {}  # chain -> the item fixing it
    for piece, item in (fixed or {}).items():
        c = chain[piece]
        if c in why and why[c].value != item.value:
            raise InputError(f"{item.where}: the same chain is given {why[c].value:g} cells")
        why[c] = item
        counts[chain == c], held[chain == c] = int(item.value), True
    for piece, (least, item) in (minimum or {}).items():
        c = chain[piece]
        if c in why and why[c].value < least:
            raise InputError(
                f"{item.where}: the grading needs at least {least} cells along the chain that "
                f"{why[c].where} gives {why[c].value:g}; give it {least} or more"
            )
        counts[chain == c] = np.maximum(counts[chain == c], least)

    def total(side) -> int:
        return int(sum(counts[p] for p, _ in side))

    def refine(side, to: int, block) -> None:
        free = [q for q in side if not held[q[0]]]
        if not free:
            x, y = block.inside
            item = why[chain[side[0][0]]]
            raise InputError(
                f"{item.where}: the block at ({x:.4g}, {y:.4g}) needs {to} cells along a side "
                f"that chain holds at {total(side)}; give it {to}"
            )
        while total(side) < to:
            coarse = max(free, key=lambda q: lengths[q[0]] / counts[q[0]])[0]
            counts[coarse] += 1

    for block in topo.blocks:
        for side in block.sides:
            if total(side) < MIN_SIDE_CELLS:
                refine(side, MIN_SIDE_CELLS, block)
    added, changed = 0, True
    while changed:
        changed = False
        for block in topo.blocks:
            for a, b in ((0, 2), (1, 3)):
                na, nb = total(block.sides[a]), total(block.sides[b])
                if na != nb:
                    added += abs(na - nb)
                    refine(block.sides[a] if na < nb else block.sides[b], max(na, nb), block)
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
