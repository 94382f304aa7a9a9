"""Where an O- or C-grid's network cannot win, and the grid it keeps then.

A body's network corrects its elliptic start by a bubble eta^3 (1 - eta) times a smooth
function of the grid's indices, and its guard keeps only a grid with no more folds and mean
and worst angles no worse than the start's. Where the first layer off the wall is much thinner
than the wall's spacing along it (a boundary-layer grid: ``THIN_WALL``), no correction the
bubble allows has improved the outer cells without shearing the thin ones near the wall, and
the guard has kept the start on every airfoil measured (docs/speed.md); :func:`body_cannot_win`
says so before torch is imported, and :func:`body_start` is the report of the start kept.
"""

from __future__ import annotations

import time

import numpy as np

from pinn_engine.quality import guard_figures
from pinn_engine.settings import Settings

# A body's wall cells (spacing along the wall over the first layer's height) at least this
# stretched: measured (benchmarks/body_training.py), no trained state passed the guard on such
# grids, on the real airfoils and NACA sections; below, some did (a NACA 0012 C-grid at the
# default first layer, aspect 2: worst angle 107.93 -> 106.80 degrees)
THIN_WALL = 20.0
THIN = "its wall cells, of aspect ratio 20 or more, are too thin for its correction"
# Under the default objective a body's network is not trained at all: measured on the NACA
# 0012 at the default size (41 x 21, default first layer), the C-grid's guard kept the start
# after 1.3 s of training, and the O-grid's kept a grid of lower worst angle (149.2 against
# 167.9 degrees) whose grid lines leave the wall up to 17 degrees off 90, where the elliptic
# grid's leave it at 90 (--objective winslow still trains it)
WALL = "its kept grids left the wall off 90 degrees, where the elliptic grid's leave it at 90"

# A body grid's rows its node optimisation holds: the wall's and the first layer's, which fix
# the first edges off the wall and the angles at which grid lines leave it (90 degrees)
BODY_HELD_ROWS = 2
# and every row of a boundary layer: cells this stretched (median width along the wall over
# height) are a layer the wall's spacing grades, and optimising them sheared their faces (NACA
# 0012 and 4412 C-grids at a 1e-5 chord first layer: 36-40 degrees non-orthogonal, against 20)
LAYER_ASPECT = 20.0
# A boundary-layer grid (``THIN``) of more nodes keeps its elliptic grid: the optimisation
# costs about 0.12 ms of CPU a node (a NACA 0006 C-grid at 300 x 80, first layer 1e-5 chord:
# 2.9 s against the elliptic command's 0.9 s), beyond the 3x bound against Construct2D there
LAYER_OPTIMISED_NODES = 4000


def body_cannot_win(settings: Settings, wall_aspect: float) -> str | None:
    """Why a body grid's network cannot beat its elliptic start under ``settings``, or None
    where it may: its wall cells' aspect ratio (bodygrid.Layout.wall_aspect) is at least
    ``THIN_WALL``, or the objective is the default's (``WALL``), and neither the TFI start
    (``warm_start`` none) nor Adam epochs (a schedule that trains whatever it wins) are
    asked."""
    if settings.method != "pinn" or settings.warm_start != "elliptic" or settings.adam_epochs:
        return None
    if wall_aspect >= THIN_WALL:
        return THIN
    return WALL if settings.objective == "best" else None


def held_rows(grid: np.ndarray) -> int:
    """The rows of a body's grid (nj, ni, 2) from the wall (j = 0) that its node optimisation
    holds: the wall's and the first layer's (``BODY_HELD_ROWS``), and the top of every row of
    cells of the boundary layer (median aspect at least ``LAYER_ASPECT``) next to the wall."""
    along = np.linalg.norm(np.diff(grid, axis=1), axis=2)
    across = np.linalg.norm(np.diff(grid, axis=0), axis=2)
    aspect = np.median((along[:-1] + along[1:]) / (across[:, :-1] + across[:, 1:]), axis=1)
    layer = int(np.argmin(np.append(aspect, 0.0) >= LAYER_ASPECT))
    return max(BODY_HELD_ROWS, layer + 1)


def held_worst(grid: np.ndarray, held: int = BODY_HELD_ROWS) -> float:
    """The worst angle of the cells between a body grid's first ``held`` rows, which its node
    optimisation keeps: a lower bound of the worst angle of any grid it makes."""
    return guard_figures(grid[:held])["worst_max_angle"]


def body_start(
    start: np.ndarray, reason: str, optimize: bool, seam: bool
) -> tuple[np.ndarray, dict]:
    """The grid and the body report's ``training`` where its network is not trained
    (``reason``): the elliptic ``start``, or with ``optimize`` (any objective but Winslow's)
    the better of it and its nodes beyond its held rows optimised (:func:`held_rows`,
    ``quality_start.body_quality_start``; ``seam``: an O-grid's), with the guard figures. No
    optimisation is run where the worst cell lies between the held rows (none can lower it),
    nor on a boundary-layer grid of more than ``LAYER_OPTIMISED_NODES``."""
    began = time.perf_counter()
    figures = guard_figures(start)
    grid, name = start, "elliptic"
    optimize &= reason != THIN or start.size // 2 <= LAYER_OPTIMISED_NODES
    held = held_rows(start) if optimize else BODY_HELD_ROWS
    if optimize and held_worst(start, held) < figures["worst_max_angle"]:
        from pinn_engine.starts.quality_start import body_quality_start

        grid, name = body_quality_start(start, seam, held)
    return grid, {
        "result": "start",
        "start": name,
        "skipped": reason,
        "largest_node_move": 0.0,
        "adam_epochs": 0,
        "lbfgs_iterations": 0,
        "warm_start": "elliptic",
        "guard": {"kept": guard_figures(grid), "elliptic": figures},
        "timings": {"start": time.perf_counter() - began, "training": 0.0},
    }
