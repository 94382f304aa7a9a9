"""Training only where the network can win: the decision, and the map it leaves untrained.

The default pinn's network starts as its start grid and trains the Winslow equations, plus
the terms the user asked for: auxiliary lines to follow, orthogonal sides, a spacing. The
start already solves the Winslow equations on its nodes (the converged elliptic grid, or it
untangled, where nothing better exists on those nodes without folds), and under the quality
objective it is that objective's own optimum on the nodes. Without another term the network
has nothing to win, and its guard has always ended with the start, or with a state that moves
nodes by discretisation error only (docs/speed.md). :func:`cannot_win` says so before any
network is built or torch imported; the block's map is then its start (:class:`StartModel`,
:class:`VolumeStartModel` for a six-faced 3D block, whose network trains the 3D Winslow
equations alone unless a patch has a spacing or is orthogonal), the map a trained model has
with its output layer at zero.

A body's (O- or C-grid's) network corrects its elliptic start by a bubble eta^3 (1 - eta)
times a smooth function of the grid's indices, and its guard keeps only a grid with no more
folds and mean and worst angles no worse than the start's. Where the first layer off the wall
is much thinner than the wall's spacing along it (a boundary-layer grid: ``THIN_WALL``), no
correction the bubble allows has improved the outer cells without shearing the thin ones
near the wall, and the guard has kept the start on every airfoil measured (docs/speed.md);
:func:`body_cannot_win` says so before torch is imported, and :func:`body_start` is the report
of the start kept.

Every kind runs the same sequence once its start is known, :func:`start_or_train`: where the
network cannot win, the start is kept; else the kind's training module (torch) is imported and
the network trained from the start under the kind's guard (``neural.session.train_network``).
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, TypeVar

import numpy as np

from pinn_engine.classical.tfi import tfi_grid
from pinn_engine.classical.warm import WarmStart
from pinn_engine.geometry.auxlines import AuxLine
from pinn_engine.geometry.boundary import Boundary
from pinn_engine.geometry.boundary_fit import ArcLengthFit
from pinn_engine.hexa.field import LatticeField
from pinn_engine.quality import guard_figures
from pinn_engine.settings import Settings
from pinn_engine.starts.quad_start import quad_start
from pinn_engine.starts.untangle import untangle, untangled_report
from pinn_engine.starts.warmstart import lattice_for

if TYPE_CHECKING:
    from pinn_engine.kinds.hexa.start import Start

Map = TypeVar("Map")  # what a kind's pinn leaves: its map, or its grid and report

WINSLOW = "the start already solves the Winslow equations the network trains on"
QUALITY = "the start is the quality objective's own optimum on these nodes"
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
# (The default then optimises the elliptic grid's nodes beyond the first layer,
# quality_start.body_quality_start; not on THIN walls: on the NACA 0012 and 4412 C-grids with a
# first layer of 1e-5 chord that left faces up to 36-40 degrees non-orthogonal, against 20.)


def cannot_win(settings: Settings, aux: Sequence[AuxLine] = ()) -> str | None:
    """Why the pinn's network cannot beat its start under ``settings`` with the auxiliary
    lines ``aux``, or None where it may (under the Winslow equations: lines to follow,
    orthogonal sides, a spacing; no warm start: the network is the map) or where Adam epochs
    are asked (a schedule that trains the network whatever it wins).

    The quality objective's start is its optimum on the nodes, with the lines followed: on
    the tuning set's shapes with lines its trained network never ranked better
    (docs/quality_objective.md), so it is not trained there either."""
    if settings.method != "pinn" or settings.warm_start != "elliptic" or settings.adam_epochs:
        return None
    if settings.boundary_mode != "hard" or settings.orthogonal or settings.spacing:
        return None
    if settings.quality_objective:
        return QUALITY
    return None if aux else WINSLOW


def start_or_train(reason: str | None, keep: Callable[[str], Map], train: Callable[[], Map]) -> Map:
    """The one sequence of every kind's pinn, start -> skip -> train -> guard: where its
    network cannot win (``reason``, from :func:`cannot_win` or :func:`body_cannot_win`), the
    start kept, ``keep(reason)``, with no network built and no torch imported; else
    ``train()``, which imports the kind's training module and trains the network from the
    start under the kind's guard, the start kept unless a trained state is no worse."""
    return keep(reason) if reason else train()


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


def body_start(
    start: np.ndarray, reason: str, optimize: bool, seam: bool
) -> tuple[np.ndarray, dict]:
    """The grid and the body report's ``training`` where its network is not trained
    (``reason``): the elliptic ``start``, or with ``optimize`` (the default objective) the
    better of it and its nodes off the wall and first layer optimised
    (``quality_start.body_quality_start``; ``seam``: an O-grid's), with the guard figures."""
    began = time.perf_counter()
    figures = guard_figures(start)
    grid, name = start, "elliptic"
    if optimize:
        from pinn_engine.starts.quality_start import body_quality_start

        grid, name = body_quality_start(start, seam)
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


def _start_info(start: str, reason: str, guard: dict, seconds: float) -> dict:
    """What the report says of a block whose network is not trained: its ``start``, why
    (``reason``), the ``guard``'s figures and the start's ``seconds``."""
    return {
        "result": "start",
        "start": start,
        "skipped": reason,
        "largest_node_move": 0.0,
        "adam_epochs": 0,
        "lbfgs_iterations": 0,
        "guard": guard,
        "timings": {"start": seconds, "training": 0.0},
    }


@dataclass
class StartModel:
    """A four-sided block's map where its network is not trained: the TFI base plus the
    start's correction, the network's part zero."""

    boundary: Boundary
    warm: WarmStart
    settings: Settings
    info: dict
    history: dict = field(default_factory=dict)

    @classmethod
    def of(cls, boundary: Boundary, aux: Sequence[AuxLine], settings: Settings, reason: str):
        """The start of ``boundary`` (working frame) on ``settings.lattice``, and what the
        report says about it: not trained, and why (``reason``)."""
        began = time.perf_counter()
        lattice = lattice_for(*settings.lattice)
        begin = quad_start(boundary, settings, lattice, aux)
        guard = {"lattice": list(lattice), "elliptic": guard_figures(begin.reference)}
        info = _start_info(begin.warm.start, reason, guard, time.perf_counter() - began)
        if begin.winslow is not None:
            info["untangled"] = untangled_report(begin.winslow, begin.reference)
        return cls(boundary, begin.warm, settings, info)

    def grid(self, ni: int, nj: int) -> np.ndarray:
        """Grid (nj, ni, 2) in the working frame: the start, between the lattice's nodes its
        spline."""
        return tfi_grid(ArcLengthFit(self.boundary).sample, ni, nj) + self.warm.grid(ni, nj)

    def save(self, path: str | os.PathLike) -> Path:
        """Saved as the trained model it equals: the seeded network, its output layer zero."""
        from pinn_engine.kinds.four_sided.problem import untrained_model

        return untrained_model(self.boundary, self.warm, self.settings, self.info).save(path)


@dataclass
class VolumeStartModel:
    """A six-faced block's map where its network is not trained: the 3D TFI of the face
    grids plus the start's correction (a spline through it where the grid is finer than the
    start's lattice), the network's part zero."""

    correction: LatticeField
    settings: Settings
    info: dict
    surface_key: str
    history: dict = field(default_factory=dict)

    @classmethod
    def of(cls, start: Start, settings: Settings, surface_key: str, reason: str, seconds: float):
        """The map of ``start`` (the Winslow grid of the surface of ``surface_key``, solved in
        ``seconds``) and what the report says about it: not trained, and why (``reason``)."""
        info = _start_info("elliptic", reason, {"lattice": list(start.grid.shape[:3])}, seconds)
        return cls(LatticeField(start.grid - start.tfi), settings, info, surface_key)

    def grid(self, tfi: np.ndarray) -> np.ndarray:
        """The grid (ni, nj, nk, 3) whose faces are those of ``tfi`` (the 3D TFI of the face
        grids at the wanted size)."""
        return tfi + self.correction.at_nodes(tfi.shape[:3])

    def save(self, path: str | os.PathLike) -> None:
        """Saved as the trained model it equals: the seeded network, its output layer zero."""
        from pinn_engine.kinds.hexa.problem import untrained_model

        untrained_model(self.correction, self.settings, self.info, self.surface_key).save(path)


def start_block(start: np.ndarray, reason: str) -> tuple[np.ndarray, dict]:
    """A multi-block grid's block whose network cannot win: its elliptic grid ``start``,
    untangled where it folds (its side nodes bit for bit), and the block's report."""
    began = time.perf_counter()
    grid = untangle(start)
    report = {"result": "start", "skipped": reason, "largest_node_move": 0.0}
    if grid is not start:
        report["untangled"] = untangled_report(start, grid)
    report.update(seconds=time.perf_counter() - began, lbfgs_iterations=0)
    return (grid if grid is not start else start.copy()), report


def blocks_report(blocks: list[dict], began: float) -> dict:
    """The multi-block report's ``training`` from each block's report: the seconds since
    ``began`` (``time.perf_counter``), the blocks whose network's grid was kept, the blocks."""
    return {
        "seconds": time.perf_counter() - began,
        "network_blocks": sum(b["result"] == "network" for b in blocks),
        "blocks": blocks,
    }


def untrained_blocks(grids: list[np.ndarray], reason: str) -> tuple[list[np.ndarray], dict]:
    """Every block of a multi-block grid at its start (:func:`start_block`), where no block's
    network can win; the grids and the report's ``training``."""
    began = time.perf_counter()
    done = [start_block(grid, reason) for grid in grids]
    return [grid for grid, _ in done], blocks_report([block for _, block in done], began)
