"""The multi-block ``pinn`` (SPEC 10): the four-sided PINN block kind
(:mod:`pinn_engine.kinds.four_sided.problem`) trained on each block of the multi-block
elliptic grid.

The elliptic grid is solved first, on all blocks at once (interfaces free, as
:func:`pinn_engine.multiblock.elliptic.winslow`). Then each block's map starts as that
block's grid (the warm start's correction, ``classical/warm.py``) with its four sides held
at the block's side nodes (hard mode), so nodes on shared sides stay the same point in both
blocks. A block whose elliptic grid folds starts from it untangled (the same side nodes,
``starts/untangle.py``). The block's guard keeps the start unless a trained state is no worse in
folds, mean and worst MaxIncludedAngle, and in how grid lines cross the interfaces (the
kink mean and max of the whole grid, the blocks trained so far at their kept grids): the
multi-block grid is never worse than the elliptic one in those figures. A block with
auxiliary lines inside it (``quadblock.block_lines``) fits them as a four-sided domain's
pinn does, its guard allowing that domain's tolerance above the elliptic block. The trainer
knows nothing of blocks; the guard and its reference are this module's.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Sequence

import numpy as np

from pinn_engine.classical.tfi import tfi_grid
from pinn_engine.classical.warm import WarmStart
from pinn_engine.errors import STOP, TrainingCancelled
from pinn_engine.geometry.auxlines import AuxLine
from pinn_engine.geometry.boundary_fit import ArcLengthFit
from pinn_engine.kinds.blocks.untrained import blocks_report
from pinn_engine.kinds.four_sided.mapping import Mapping
from pinn_engine.kinds.four_sided.problem import GUARD_TOL as QUAD_GUARD_TOL
from pinn_engine.kinds.four_sided.problem import QuadProblem, network
from pinn_engine.multiblock.quadblock import block_boundary
from pinn_engine.neural.session import GuardRule, train_network
from pinn_engine.neural.trainer import Progress
from pinn_engine.quality import guard_figures, no_worse
from pinn_engine.settings import Settings
from pinn_engine.starts.untangle import untangle, untangled_report

# A block's trained state is kept only if it is no worse than the block's elliptic grid in
# mean and worst MaxIncludedAngle, and than the grid before it in the interface kinks' mean
# and max (degrees above allowed): block by block no worse, so the whole grid is no worse
GUARD_TOL = (0.0, 0.0)
# A block with auxiliary lines trades some quality for following them, as a four-sided
# domain's pinn does: its guard's tolerance (0.25 / 1 degree, within the bounds 0.5 / 2)
AUX_GUARD_TOL = QUAD_GUARD_TOL
# Following a line bends the grid lines that leave its block: the guard lets the interface
# kinks' mean and max rise to these bounds (degrees), or stay at the grid's before if higher
AUX_KINK_BOUND = (2.0, 15.0)

# The interface kinks (degrees, ``mesh.interface_kinks``) of a multi-block grid given as its
# blocks' grids
Kinks = Callable[[list[np.ndarray]], np.ndarray]


def kink_figures(kinks: np.ndarray) -> dict[str, float]:
    """The mean and max of interface kinks (0 where there are none) for a guard."""
    if not kinks.size:
        return {"kink_mean": 0.0, "kink_max": 0.0}
    return {"kink_mean": float(kinks.mean()), "kink_max": float(kinks.max())}


def _no_worse(q: dict[str, float], reference: dict[str, float], aux: bool) -> bool:
    """:func:`quality.no_worse` within the guard's tolerance, and the kinks' mean and max
    within theirs (``aux``: the block follows auxiliary lines)."""
    mean, worst = reference["kink_mean"], reference["kink_max"]
    if aux:
        mean, worst = max(mean, AUX_KINK_BOUND[0]), max(worst, AUX_KINK_BOUND[1])
    return (
        no_worse(q, reference, *(AUX_GUARD_TOL if aux else GUARD_TOL))
        and q["kink_mean"] <= mean
        and q["kink_max"] <= worst
    )


@dataclasses.dataclass
class BlockTraining:
    """One block's result: its grid (the start's side nodes, bit for bit), whether the
    network's state or the start was kept, and the training's report."""

    grid: np.ndarray
    result: str
    seconds: float
    info: dict


def train_block(
    start: np.ndarray,
    settings: Settings,
    progress: Progress | None = None,
    aux: Sequence[AuxLine] = (),
    interfaces: Callable[[np.ndarray], dict[str, float]] | None = None,
) -> BlockTraining:
    """Train the four-sided PINN block on the elliptic block grid ``start`` (nj, ni, 2),
    untangled where it folds (untangle.py): warm-started from it, its sides held at its side
    nodes, guarded by it; ``aux``: the
    auxiliary lines inside it, in the working frame of ``block_boundary(start)``
    (``quadblock.block_lines``), fitted as a four-sided domain's are; ``interfaces``: the
    :func:`kink_figures` of the whole grid with this block's grid given (none: no kinks)."""
    began = time.perf_counter()
    winslow, start = start, untangle(start)
    nj, ni = start.shape[:2]
    boundary = block_boundary(start)
    unit = boundary.frame.to_unit(start)
    kinks = interfaces or (lambda grid: kink_figures(np.zeros(0)))

    def user(grid: np.ndarray) -> np.ndarray:
        """A unit-frame grid in user units with the start's side nodes, bit for bit."""
        out = start.copy()
        out[1:-1, 1:-1] = boundary.frame.to_user(grid[1:-1, 1:-1])
        return out

    settings = dataclasses.replace(settings, lattice=(ni, nj))
    reference = {**guard_figures(unit), **kinks(start)}

    def problem(net, dtype, device) -> tuple[QuadProblem, GuardRule]:
        base = tfi_grid(ArcLengthFit(boundary).sample, ni, nj)
        mapping = Mapping(net, boundary, "hard", WarmStart(unit - base))
        return QuadProblem(mapping, boundary, aux, settings, dtype, device), GuardRule(
            lambda: mapping.grid(ni, nj),
            lambda grid: {**guard_figures(grid), **kinks(user(grid))},
            lambda q, kept: _no_worse(q, reference, bool(aux)),
            reference,
            boundary.diagonal,
        )

    training = train_network(
        settings, lambda dtype, device: network(settings, dtype, device), problem, progress
    )
    info, guard = training.info, training.guard
    grid = user(guard.kept_grid) if info["result"] == "network" else start.copy()
    if start is not winslow:
        info["untangled"] = untangled_report(winslow, start)
    return BlockTraining(grid, info["result"], time.perf_counter() - began, info)


def train_blocks(
    grids: list[np.ndarray],
    settings: Settings,
    progress: Progress | None = None,
    aux: Sequence[Sequence[AuxLine]] | None = None,
    kinks: Kinks | None = None,
) -> tuple[list[np.ndarray], dict]:
    """Each block of the elliptic grid ``grids`` trained by :func:`train_block` (with its
    auxiliary lines ``aux[k]``, ``quadblock.block_lines``, if given), in turn, its guard
    judging the ``kinks`` of the whole grid: the blocks before it at their kept grids, those
    after it at their elliptic grids. Returns the grids and the report's ``training``: per
    block the result kept and the seconds, and the total. ``progress`` hears a ``prepare``
    stage as each block starts, then the trainer's steps with ``block`` and ``blocks``
    added; once it answers ``errors.STOP`` the blocks left keep their elliptic grids, and
    True cancels (:class:`TrainingCancelled`)."""
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
        lines = aux[k] if aux is not None else ()
        interfaces = _in_place(kinks, out, grids[k + 1 :]) if kinks is not None else None
        heard_here = heard if progress is not None else None
        trained = train_block(start, settings, heard_here, lines, interfaces)
        out.append(trained.grid)
        blocks.append(
            {
                "result": trained.result,
                "seconds": trained.seconds,
                "lbfgs_iterations": trained.info["lbfgs_iterations"],
                "largest_node_move": trained.info["largest_node_move"],
                **{k: trained.info[k] for k in ("untangled",) if k in trained.info},
            }
        )
    report = blocks_report(blocks, began)
    return out, report


def _in_place(
    kinks: Kinks, before: list[np.ndarray], after: list[np.ndarray]
) -> Callable[[np.ndarray], dict[str, float]]:
    """The :func:`kink_figures` of the whole grid with one block's grid given, between the
    blocks ``before`` it (at their kept grids) and ``after`` it (at their elliptic grids)."""
    before = list(before)
    return lambda grid: kink_figures(kinks([*before, grid, *after]))


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
