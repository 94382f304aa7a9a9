"""The elliptic warm start of the default PINN: the map starts as the converged Winslow grid.

The converged elliptic grid E on a lattice of ni x nj nodes differs from the polyline TFI T
on the same boundary nodes by D = E - T, which is zero on the boundary. A bicubic spline
through D (zero along the four sides, since it interpolates zeros there) is added to the TFI
base of the hard-boundary map, so that with the network's output layer at zero the map *is*
the elliptic grid at the lattice nodes, and a smooth interpolant of it between them. Training
on the Winslow and auxiliary-line losses then starts where the classical method ends, not at
TFI: on shapes with sharp features the PINN from TFI stalls halfway or folds, the warm start
does not, and it needs tens of L-BFGS iterations instead of thousands of Adam epochs.
"""

from __future__ import annotations

import math

import numpy as np

from pinn_engine.classical.elliptic import controlled_solve, winslow_solve
from pinn_engine.classical.tfi import tfi_at, tfi_grid
from pinn_engine.classical.warm import WarmStart
from pinn_engine.errors import TrainingError
from pinn_engine.geometry.boundary import Boundary
from pinn_engine.geometry.boundary_fit import ArcLengthFit
from pinn_engine.settings import MAX_LATTICE_NODES


def lattice_for(*nodes: int, most: int = MAX_LATTICE_NODES) -> tuple[int, ...]:
    """The warm start's lattice for a grid of ``nodes`` per direction (ni, nj or ni, nj, nk):
    the grid itself up to about ``most`` nodes, else a coarser one with the same ratio of
    cells per side."""
    if math.prod(nodes) <= most:
        return tuple(nodes)
    scale = (most / math.prod(nodes)) ** (1 / len(nodes))
    return tuple(max(2, int((n - 1) * scale) + 1) for n in nodes)


def _finite(grid: np.ndarray) -> np.ndarray:
    if not np.isfinite(grid).all():
        raise TrainingError(
            "the elliptic grid of the warm start is not finite; train "
            "from TFI instead (warm start none)"
        )
    return grid


def elliptic_start(boundary: Boundary, ni: int, nj: int) -> tuple[WarmStart, np.ndarray]:
    """The warm start from the converged elliptic grid on ``ni`` x ``nj`` nodes; also
    returns that grid (working frame), the reference the training is checked against."""
    base = tfi_grid(ArcLengthFit(boundary).sample, ni, nj)
    grid = _finite(winslow_solve(base)[0])
    return WarmStart(grid - base), grid


def orthogonal_start(
    boundary: Boundary,
    ni: int,
    nj: int,
    sides: tuple[str, ...],
    params: np.ndarray | None = None,
    heights: dict[str, float] | None = None,
) -> tuple[WarmStart, np.ndarray]:
    """The warm start of ``--orthogonal`` (SPEC 7): the elliptic grid with its first rows
    on the normals of ``sides`` (orthogonal.py), and that grid (the guard's reference).

    Under a spacing, ``params`` (nj, ni, 2) are its node parameters (spacing.py; each
    grid line has its own stretching). The grid's nodes then sit at the rectilinear
    lattice of their mean columns and rows (:attr:`nodes`, where the map is evaluated at
    this size): the boundary nodes are there, the interior follows ``params`` through
    the control functions, and the first rows are ``heights`` from the spaced orthogonal
    sides. A spline on a rectilinear lattice keeps the map smooth between the nodes."""
    from pinn_engine.starts.orthogonal import orthogonal_grid  # torch: the default needs none

    if params is None:
        base = tfi_grid(ArcLengthFit(boundary).sample, ni, nj)
        grid = orthogonal_grid(_finite(winslow_solve(base)[0]), sides, tfi=base)
        return WarmStart(_finite(grid) - base, start="orthogonal"), grid
    nodes = params[..., 0].mean(axis=0), params[..., 1].mean(axis=1)
    tfi = tfi_at(boundary)
    base = tfi(np.stack(np.meshgrid(*nodes), axis=-1))
    grid = _finite(controlled_solve(base, params)[0])
    grid = _finite(orthogonal_grid(grid, sides, params, heights, tfi(params)))
    return WarmStart(grid - base, nodes, "orthogonal"), grid
