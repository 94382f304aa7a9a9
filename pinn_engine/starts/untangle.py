"""A fold-free grid on the same boundary nodes where the Winslow grid folds.

Where a boundary turns sharply into the domain (a deep notch, a forward step, a spike) the
converged elliptic (Winslow) grid folds cells. :func:`untangle` moves the interior nodes near
the folds to minimise an energy summed over the four corners of every cell, with the
corner's Jacobian J replaced by the regularised chi(J, eps) = (J + sqrt(eps^2 + J^2)) / 2
(Garanzha, Kaporin, Kudryavtseva, Protais, Ray, Sokolov: "Foldover-free maps in 50 lines of
code", 2021): an angle term 2 |a| |b| / chi(J) (2 / sin of the corner's angle once J > 0)
and an area term (J^2 + 1) / chi(J) that holds each cell near the Winslow grid's size there.
chi is positive for any J, so a folded grid has a finite energy to start from; eps shrinks
after each round of L-BFGS as the smallest Jacobian allows, and as eps goes to zero the
energy gets a barrier at J = 0: once every corner is positive none turns negative again.
Only the nodes near the folded cells move (a band of rings around them, widened while folds
remain), so the rest of the grid stays the Winslow grid. :func:`fold_forced` says where the
boundary nodes themselves leave no fold-free grid.
"""

from __future__ import annotations

import numpy as np

from pinn_engine.blas import one_thread
from pinn_engine.classical.warm import WarmStart
from pinn_engine.quality import (
    DBL_MIN,
    boundary_angles,
    folded_cells,
    guard_figures,
    largest_area_ratio,
    orientation,
)

# Rings of nodes around the folded cells that move: the first band, and the widest before
# the whole grid moves (each failing round doubles the band)
FIRST_RINGS = 3
ROUNDS = 4
# Rounds of L-BFGS at one eps, and L-BFGS iterations in each (the energy is smooth; a few
# hundred iterations unfold the grids of the hard-shape set at 161 x 81)
EPS_ROUNDS = 20
LBFGS_ITERATIONS = 200
# eps to start from: this share of the most negative corner Jacobian (Garanzha et al.), at
# least the floor (Jacobians are in cell areas) so that a grid with a zero corner can move
START_SHARE = 0.2
EPS_FLOOR = 1e-6
# eps once every corner is positive (the barrier proper), in cell areas
BARRIER_EPS = 1e-9
# The energy's relative decrease below which a fold-free round ends the rounds
CONVERGED = 1e-6
# The area term's share of the energy (the angle term has the rest), and the Jacobi sweeps
# that fill the areas to hold across the folds (a fold is a few cells across)
AREA_SHARE = 0.5
FILL_SWEEPS = 50
# An untangled grid is kept only with its mean MaxIncludedAngle at most MEAN_TOL degrees
# above the Winslow grid's and its largest area ratio between neighbouring cells at most
# AREA_RATIO_TOL times the Winslow grid's: the folds go, the grid stays the Winslow grid
MEAN_TOL = 1.0
AREA_RATIO_TOL = 1.5
# Degrees within which a side node's boundary edges lie on one another (a needle: both its
# cells would have a flat or zero corner there)
NEEDLE = 1e-9
# The least share of chi(J) that the next eps keeps below the smallest corner Jacobian
# (Garanzha et al.'s sigma floor)
SIGMA_FLOOR = 0.1


class _Corners:
    """The regularised energy over the cell corners of a grid (nj, ni, 2) with some interior
    nodes ``free``: ``1 - AREA_SHARE`` of the angle term 2 |a| |b| / chi(J) (|a|, |b| the
    corner's edges: 2 / sin of its angle where J > 0, least at 90 degrees), plus
    ``AREA_SHARE`` of Garanzha et al.'s area term (J^2 + 1) / chi(J), which holds each cell
    near its ``area`` in the start. Each corner's Jacobian J is measured in its cell's
    ``area``."""

    def __init__(self, grid: np.ndarray, free: np.ndarray, area: np.ndarray) -> None:
        self.grid = np.array(grid, dtype=float)
        self.free = free
        self.turn = orientation(grid)
        # only the cells with a free corner change: the four corners' node indices of each
        moving = np.logical_or.reduce(_corners(free))
        nodes = np.arange(free.size).reshape(free.shape)
        self.index = np.stack([corner[moving] for corner in _corners(nodes)])
        self.area = area[moving]
        self.free_nodes = np.flatnonzero(free)

    def with_free(self, x: np.ndarray) -> np.ndarray:
        g = self.grid.copy()
        g[self.free] = x.reshape(-1, 2)
        return g

    def _edges(self, g: np.ndarray) -> tuple[np.ndarray, ...]:
        """At the four corners k (axis 0) of every cell with a free corner: the edges a (to
        corner k + 1) and b (to corner k - 1), each as its x and y, and the Jacobian det(a,
        b) in cell areas."""
        flat = g.reshape(-1, 2)
        px, py = flat[:, 0][self.index], flat[:, 1][self.index]
        ax, ay = px[_NEXT] - px, py[_NEXT] - py
        bx, by = px[_PREVIOUS] - px, py[_PREVIOUS] - py
        return ax, ay, bx, by, self.turn * (ax * by - ay * bx) / self.area

    def least(self, x: np.ndarray) -> float:
        """The smallest corner Jacobian (in cell areas)."""
        return float(self._edges(self.with_free(x))[-1].min())

    def energy(self, x: np.ndarray, eps: float) -> tuple[float, np.ndarray]:
        """The regularised energy and its gradient in the free nodes' coordinates."""
        ax, ay, bx, by, det = self._edges(self.with_free(x))
        root = np.sqrt(eps * eps + det * det)
        chi = _chi(det, root, eps)
        la = np.maximum(np.hypot(ax, ay), DBL_MIN)
        lb = np.maximum(np.hypot(bx, by), DBL_MIN)
        top = (1 - AREA_SHARE) * 2 * la * lb / self.area + AREA_SHARE * (det * det + 1)
        d_shape = (1 - AREA_SHARE) * 2 / (chi * self.area)
        d_det = self.turn * (AREA_SHARE * 2 * det / chi - top / (chi * root)) / self.area
        along_a, along_b = d_shape * lb / la, d_shape * la / lb
        # the gradients by a and b: along themselves, and d_det times (b_y, -b_x), (-a_y, a_x)
        ga = (along_a * ax + d_det * by, along_a * ay - d_det * bx)
        gb = (along_b * bx - d_det * ay, along_b * by + d_det * ax)
        # a runs to corner k + 1, b to corner k - 1: each corner gets its own and its
        # neighbours' parts
        size, out = self.free.size, np.empty((self.free_nodes.size, 2))
        for c in (0, 1):
            per_corner = ga[c][_PREVIOUS] + gb[c][_NEXT] - ga[c] - gb[c]
            out[:, c] = np.bincount(self.index.ravel(), per_corner.ravel(), size)[self.free_nodes]
        return float((top / chi).sum()), out.ravel()


# The corner after and before each of a cell's four (axis 0 of _Corners' arrays)
_NEXT = [1, 2, 3, 0]
_PREVIOUS = [3, 0, 1, 2]


def _corners(g: np.ndarray) -> list[np.ndarray]:
    """The four corners of every cell, counter-clockwise in (i, j), as views of ``g``."""
    return [g[:-1, :-1], g[:-1, 1:], g[1:, 1:], g[1:, :-1]]


def _chi(det: np.ndarray, root: np.ndarray, eps: float) -> np.ndarray:
    """(det + root) / 2 with root = sqrt(eps^2 + det^2), without cancellation for det < 0."""
    with np.errstate(divide="ignore"):
        return np.where(det >= 0, 0.5 * (det + root), 0.5 * eps * eps / (root - det))


def _areas(grid: np.ndarray, unsure: np.ndarray) -> np.ndarray:
    """The cells' areas to hold: each cell's own, but in the ``unsure`` cells (the folds and
    the cells beside them, whose own area says nothing) the smooth continuation of the
    others' (their logarithm's harmonic fill, ``FILL_SWEEPS`` Jacobi sweeps)."""
    p = _corners(grid)
    d1, d2 = p[2] - p[0], p[3] - p[1]
    area = 0.5 * np.abs(d1[..., 0] * d2[..., 1] - d1[..., 1] * d2[..., 0])
    log = np.log(np.maximum(area, 1e-300))
    known = ~unsure
    if not known.any():
        return area
    log[unsure] = log[known].mean()
    for _ in range(FILL_SWEEPS):
        padded = np.pad(log, 1, mode="edge")
        mean = 0.25 * (padded[:-2, 1:-1] + padded[2:, 1:-1] + padded[1:-1, :-2] + padded[1:-1, 2:])
        log = np.where(unsure, mean, log)
    return np.exp(log)


def _minimise(corners: _Corners) -> np.ndarray:
    """The grid after rounds of L-BFGS at a shrinking eps (Garanzha et al.'s rule)."""
    from scipy.optimize import minimize  # only a folded grid gets here

    x = corners.grid[corners.free].ravel()
    least = corners.least(x)
    eps = max(START_SHARE * max(-least, 0.0), EPS_FLOOR)
    # a step far off (an edge of length ~0) overflows the energy: the line search steps
    # back from it, a round that ends there leaves a fold the caller sees, and no warning
    # reaches the user
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        for _ in range(EPS_ROUNDS):
            before = corners.energy(x, eps)[0]
            x = minimize(
                corners.energy,
                x,
                args=(eps,),
                jac=True,
                method="L-BFGS-B",
                options={"maxiter": LBFGS_ITERATIONS, "gtol": 1e-12, "ftol": 1e-15},
            ).x
            after = corners.energy(x, eps)[0]
            least = corners.least(x)
            if least > 0 and before - after <= CONVERGED * abs(after):
                break
            sigma = max(1 - after / before, SIGMA_FLOOR)
            mu = (1 - sigma) * float(_chi(np.array(least), np.hypot(eps, least), eps))
            eps = 2 * np.sqrt(mu * (mu - least)) if least < mu else BARRIER_EPS
    return corners.with_free(x)


def _move(grid: np.ndarray, free: np.ndarray) -> np.ndarray:
    """``grid`` with the ``free`` nodes moved by :func:`_minimise`: the areas to hold are
    filled on the smallest box of cells around them, the energy counts the cells with a free
    corner (the others' does not change)."""
    rows, cols = np.nonzero(free)
    j0, j1 = rows.min() - 1, rows.max() + 2
    i0, i1 = cols.min() - 1, cols.max() + 2
    from scipy.ndimage import binary_dilation  # only a folded grid gets here

    box = grid[j0:j1, i0:i1]
    out = np.array(grid, dtype=float)
    unsure = binary_dilation(folded_cells(box), np.ones((3, 3), dtype=bool))
    out[j0:j1, i0:i1] = _minimise(_Corners(box, free[j0:j1, i0:i1], _areas(box, unsure)))
    return out


def _band(folded: np.ndarray, rings: int) -> np.ndarray:
    """The interior nodes within ``rings`` rings of the nodes of ``folded`` cells."""
    from scipy.ndimage import binary_dilation  # only a folded grid gets here

    nj, ni = folded.shape[0] + 1, folded.shape[1] + 1
    nodes = np.zeros((nj, ni), dtype=bool)
    for dj in (0, 1):
        for di in (0, 1):
            nodes[dj : dj + nj - 1, di : di + ni - 1] |= folded
    band = binary_dilation(nodes, np.ones((3, 3), dtype=bool), iterations=rings)
    band[[0, -1], :] = band[:, [0, -1]] = False
    return band


def untangle(grid: np.ndarray) -> np.ndarray:
    """``grid`` (nj, ni, 2) with its folded cells undone, its boundary nodes fixed: the nodes
    within ``FIRST_RINGS`` rings of the folds move first, in twice as many rings while folds
    remain or the grid is not :func:`acceptable` against ``grid`` (``ROUNDS`` times), then
    every interior node. Of the grids met, the one with the fewest folded cells, of those
    one that is acceptable if any (a fold-free grid outside the bounds is still one that a
    solver takes); ``grid`` itself if none folds fewer."""
    folds = int(folded_cells(grid).sum())
    if not folds or min(grid.shape[:2]) < 3:
        return grid
    with one_thread():  # L-BFGS-B's small products: threads cost more than they save
        return _untangled(grid, folds)


def acceptable(grid: np.ndarray, winslow: np.ndarray) -> bool:
    """Whether an untangled ``grid`` keeps close to the ``winslow`` grid it came from: mean
    MaxIncludedAngle at most ``MEAN_TOL`` above its, and the largest area ratio of
    neighbouring cells at most ``AREA_RATIO_TOL`` times its."""
    mean = guard_figures(grid)["mean_max_angle"]
    return mean <= guard_figures(winslow)["mean_max_angle"] + MEAN_TOL and largest_area_ratio(
        grid
    ) <= AREA_RATIO_TOL * largest_area_ratio(winslow)


def _untangled(grid: np.ndarray, folds: int) -> np.ndarray:
    """:func:`untangle`'s rounds: each moves the band around the folds of the best acceptable
    grid so far; ``fewest`` is the grid with the fewest folds met, acceptable or not."""
    best, rings = grid, FIRST_RINGS
    fewest, fewest_folds = grid, folds
    for attempt in range(ROUNDS + 1):
        folded = folded_cells(best)
        free = _band(folded, rings) if attempt < ROUNDS else _band(folded, max(grid.shape))
        moved = _move(best, free)
        if np.isfinite(moved).all():
            moved_folds = int(folded_cells(moved).sum())
            if moved_folds < folds and acceptable(moved, grid):
                best, folds = moved, moved_folds
            if moved_folds < fewest_folds:
                fewest, fewest_folds = moved, moved_folds
        if not folds:
            break
        rings *= 2
    return best if folds <= fewest_folds else fewest


def untangled_start(warm: WarmStart, winslow: np.ndarray) -> tuple[WarmStart, np.ndarray] | None:
    """The start ``warm`` from the folded ``winslow`` grid moved to :func:`untangle`'s grid,
    and that grid (``warm`` and ``winslow`` themselves where untangling does not help); None
    where the Winslow grid does not fold."""
    grid = untangle(winslow)
    if grid is winslow:
        return (warm, winslow) if folded_cells(winslow).any() else None
    return WarmStart(warm.correction + (grid - winslow), start="untangled"), grid


def untangled_report(winslow: np.ndarray, grid: np.ndarray) -> dict:
    """The report's ``untangled``: folded cells of the Winslow grid and of its untangling,
    whether that keeps :func:`acceptable` and, where it still folds and the boundary nodes
    force a fold, why (:func:`fold_forced`)."""
    report = {
        "winslow_folded_cells": int(folded_cells(winslow).sum()),
        "folded_cells": int(folded_cells(grid).sum()),
        "within_bounds": bool(acceptable(grid, winslow)),
    }
    forced = fold_forced(winslow) if report["folded_cells"] else None
    if forced:
        report["forced"] = forced
    return report


def fold_forced(grid: np.ndarray) -> str | None:
    """Why every grid on the boundary nodes of ``grid`` folds a cell, or None where they do
    not force one: a domain corner whose boundary edges make 180 degrees or more (its one
    cell has that angle), or a side node whose two edges lie on one another (its two cells
    share an angle of 0 or 360 degrees, so one has a corner of 0 or 180)."""
    nj, ni = grid.shape[:2]
    _, angle, corners = boundary_angles(grid)
    ij = [(i, 0) for i in range(ni - 1)] + [(ni - 1, j) for j in range(nj - 1)]
    ij += [(i, nj - 1) for i in range(ni - 1, 0, -1)] + [(0, j) for j in range(nj - 1, 0, -1)]
    reflex = np.flatnonzero(corners & (angle >= 180.0))
    if reflex.size:
        k = int(reflex[np.argmax(angle[reflex])])
        return (
            f"the boundary edges at the domain corner (i, j) = {ij[k]} make {angle[k]:.1f} "
            f"degrees, and its one cell cannot have a corner of 180 or more"
        )
    needle = np.flatnonzero(~corners & ((angle < NEEDLE) | (angle > 360.0 - NEEDLE)))
    if needle.size:
        return (
            f"the boundary edges at the node (i, j) = {ij[int(needle[0])]} lie on one "
            f"another, so one of its two cells has a flat corner there"
        )
    return None
