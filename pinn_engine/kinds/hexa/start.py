"""The start of a six-faced 3D domain's pinn (SPEC 11): the converged 3D Winslow grid on the
same face nodes, on the grid's own lattice or a coarser one of the same shape, with what the
training adds to it (a spacing's node parameters, orthogonal patches)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from pinn_engine.hexa import quality, volume
from pinn_engine.quality import ranks_above
from pinn_engine.starts.warmstart import lattice_for

# The Winslow start is solved on at most this many nodes (larger grids start from a coarser
# lattice of the same shape, starts/warmstart.py): 41^3 takes about 1.4 s and 0.26 GiB, 81^3
# about 14 s and 0.85 GiB more (docs/hexa.md, "Speed and memory").
MAX_LATTICE_NODES = 41**3


@dataclass
class Start:
    """What the network starts from: ``tfi`` (the map's base, its faces the face grids),
    ``grid`` (the converged Winslow grid on the same faces: the start and the guard's
    reference) and, for a spacing, the nodes' ``params`` (their control terms join the loss)
    and ``spacing_error(grid)`` (the first edges' largest relative error, which the guard
    keeps within ``SPACING_GUARD``)."""

    tfi: np.ndarray
    grid: np.ndarray
    params: np.ndarray | None = None
    spacing_error: Callable[[np.ndarray], float] | None = None
    walls: tuple[tuple[int, float], ...] = ()
    wall_angle: Callable[[np.ndarray], float] | None = None
    name: str = "elliptic"  # which grid ``grid`` is (the report's start)


def winslow_start(tfi_of: Callable[[tuple[int, ...]], np.ndarray], size: tuple[int, ...]) -> Start:
    """The converged Winslow grid on the lattice of ``size`` (``lattice_for``), from
    ``tfi_of(shape)``, the 3D TFI of the face grids with ``shape`` nodes."""
    coarse = lattice_for(*size, most=MAX_LATTICE_NODES)
    # at least 3 nodes a direction, as the grid has: the Winslow start needs an interior
    tfi = tfi_of(tuple(max(m, min(n, 3)) for m, n in zip(coarse, size, strict=True)))
    return Start(tfi, volume.winslow(tfi)[0])


def _figures(grid: np.ndarray) -> dict[str, float]:
    """A start's folded cells, worst and mean MaxIncludedAngle (``quality.ranks_above``)."""
    largest = quality.included_angles(grid)[0]
    return {
        "folded_cells": int(quality.folded(grid).sum()),
        "worst_max_angle": float(largest.max()),
        "mean_max_angle": float(largest.mean()),
    }


def better_start(start: Start) -> Start:
    """``start`` (a Winslow start), or its TFI grid where that ranks above it
    (``quality.ranks_above``: no more folds, the lower worst MaxIncludedAngle, the mean within
    the default's bound): TFI keeps a polar bend's grid polar, orthogonal everywhere, where
    the Winslow grid bends its arcs toward the inner wall."""
    if ranks_above(_figures(start.tfi), _figures(start.grid)):
        return Start(start.tfi, start.tfi, name="tfi")
    return start
