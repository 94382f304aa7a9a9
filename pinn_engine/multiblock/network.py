"""The multi-block ``pinn`` (SPEC 10, issue 24 item 2): the four-sided PINN block kind
(:mod:`pinn_engine.blocks.quad`) trained on each block of the multi-block elliptic grid.

The elliptic grid is solved first, on all blocks at once (interfaces free, as
:func:`pinn_engine.multiblock.elliptic.winslow`). Then each block's map starts as that
block's grid (the warm start's correction, ``classical/warm.py``) with its four sides held
at the block's side nodes (hard mode), so nodes on shared sides stay the same point in both
blocks and the interfaces are crossed as smoothly as in the elliptic grid. The block's guard
keeps the elliptic block unless a trained state is no worse in folds, mean and worst
MaxIncludedAngle: the multi-block grid is never worse than the elliptic one. The trainer
knows nothing of blocks; the guard and its reference are this module's.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np
import torch

from pinn_engine.blocks.quad import QuadProblem
from pinn_engine.classical.tfi import node_params, tfi_grid
from pinn_engine.classical.warm import WarmStart
from pinn_engine.errors import STOP, TrainingCancelled
from pinn_engine.geometry.boundary import Boundary, Frame, Polyline
from pinn_engine.geometry.boundary_fit import ArcLengthFit
from pinn_engine.neural.mapping import Mapping
from pinn_engine.neural.networks import CoordinateNet
from pinn_engine.neural.trainer import Guard, Progress, fit, pick_device, training_process
from pinn_engine.quality import guard_figures, no_worse
from pinn_engine.settings import Settings

# A block's trained state is kept only if it is no worse than the block's elliptic grid in
# mean and worst MaxIncludedAngle (degrees above it allowed): block by block no worse, so
# the whole grid's mean (a cell-weighted mean of the blocks') and worst are no worse either
GUARD_TOL = (0.0, 0.0)


class NodeSide(Polyline):
    """A side polyline through a block's side nodes, parametrised by node index: node k of
    n is at t = k / (n - 1), so that the map's boundary nodes on the uniform lattice are the
    block's side nodes exactly (arc length would put them elsewhere where the side nodes
    are not evenly spaced)."""

    def __init__(self, points: np.ndarray) -> None:
        super().__init__(points)
        self.t = node_params(len(self.points))


@dataclasses.dataclass(frozen=True)
class BlockBoundary(Boundary):
    """A block's four sides as a :class:`Boundary` in its working frame, the sides
    parametrised by node index (:class:`NodeSide`)."""

    def side(self, name: str) -> NodeSide:
        return NodeSide(super().side(name).points)


def block_boundary(grid: np.ndarray) -> BlockBoundary:
    """The boundary of a block grid (nj, ni, 2), in the working frame around it: ring from
    corner 0 along bottom, right, top and left (SPEC 1's side order)."""
    nj, ni = grid.shape[:2]
    ring = np.concatenate([grid[0, :-1], grid[:-1, -1], grid[-1, :0:-1], grid[:0:-1, 0]])
    frame = Frame.around(ring)
    corners = (0, ni - 1, ni + nj - 2, 2 * ni + nj - 3)
    return BlockBoundary(ring=frame.to_unit(ring), corners=corners, frame=frame)


@dataclasses.dataclass
class BlockTraining:
    """One block's result: its grid (the start's side nodes, bit for bit), whether the
    network's state or the start was kept, and the training's report."""

    grid: np.ndarray
    result: str
    seconds: float
    info: dict


def train_block(
    start: np.ndarray, settings: Settings, progress: Progress | None = None
) -> BlockTraining:
    """Train the four-sided PINN block on the elliptic block grid ``start`` (nj, ni, 2):
    warm-started from it, its sides held at its side nodes, guarded by it."""
    began = time.perf_counter()
    nj, ni = start.shape[:2]
    boundary = block_boundary(start)
    unit = boundary.frame.to_unit(start)
    settings = dataclasses.replace(settings, lattice=(ni, nj))
    dtype = {"float64": torch.float64, "float32": torch.float32}[settings.dtype]
    device = pick_device(settings.device)
    with training_process(device):
        torch.manual_seed(settings.seed)
        net = CoordinateNet(
            "shortcut", settings.hidden_layers, settings.neurons, settings.activation
        )
        net = net.to(device=device, dtype=dtype)
        with torch.no_grad():  # the map starts as the block's elliptic grid
            net.w_out.zero_()
        base = tfi_grid(ArcLengthFit(boundary).sample, ni, nj)
        mapping = Mapping(net, boundary, "hard", WarmStart(unit - base))
        problem = QuadProblem(mapping, boundary, (), settings, dtype, device)
        reference = guard_figures(unit)
        guard = Guard(
            net,
            lambda: mapping.grid(ni, nj),
            guard_figures,
            lambda q, kept: no_worse(q, reference, *GUARD_TOL),
            reference,
            boundary.diagonal,
        )
        _, info = fit(problem, settings, guard, progress)
    grid = start.copy()
    if info["result"] == "network":
        grid[1:-1, 1:-1] = boundary.frame.to_user(guard.kept_grid[1:-1, 1:-1])
    return BlockTraining(grid, info["result"], time.perf_counter() - began, info)


def train_blocks(
    grids: list[np.ndarray], settings: Settings, progress: Progress | None = None
) -> tuple[list[np.ndarray], dict]:
    """Each block of the elliptic grid ``grids`` trained by :func:`train_block`; returns the
    grids and the report's ``training``: per block the result kept and the seconds, and the
    total. ``progress`` hears a ``prepare`` stage as each block starts, then the trainer's
    steps with ``block`` and ``blocks`` added; once it answers ``errors.STOP`` the blocks
    left keep their elliptic grids, and True cancels (:class:`TrainingCancelled`)."""
    out, blocks = [], []
    heard = _BlockProgress(progress, len(grids))
    began = time.perf_counter()
    for k, start in enumerate(grids):
        heard.block = k
        if not heard.stopped and heard(_stage(k, len(grids))) and not heard.stopped:
            raise TrainingCancelled(f"training cancelled before block {k + 1} of {len(grids)}")
        if heard.stopped:
            out.append(start)
            blocks.append({"result": "start", "seconds": 0.0, "stopped": True})
            continue
        trained = train_block(start, settings, heard if progress is not None else None)
        out.append(trained.grid)
        blocks.append(
            {
                "result": trained.result,
                "seconds": trained.seconds,
                "lbfgs_iterations": trained.info["lbfgs_iterations"],
                "largest_node_move": trained.info["largest_node_move"],
            }
        )
    report = {
        "seconds": time.perf_counter() - began,
        "network_blocks": sum(b["result"] == "network" for b in blocks),
        "blocks": blocks,
    }
    return out, report


def _stage(k: int, n: int) -> dict:
    """The progress of block ``k`` of ``n`` starting (a stage, as a body's before training)."""
    return {"phase": "prepare", "stage": f"training block {k + 1} of {n}", "step": k, "total": n}


class _BlockProgress:
    """The caller's progress with ``block`` and ``blocks`` added to what it hears; notes an
    ``errors.STOP`` answer (``stopped``), which the blocks after this one obey."""

    def __init__(self, progress: Progress | None, blocks: int) -> None:
        self.progress, self.blocks, self.block, self.stopped = progress, blocks, 0, False

    def __call__(self, info: dict) -> object:
        if self.progress is None:
            return None
        answer = self.progress({**info, "block": self.block, "blocks": self.blocks})
        if isinstance(answer, str) and answer == STOP:
            self.stopped = True
        return answer
