"""Where a four-sided block's network starts (kinds.four_sided.problem): the start grid on
the lattice, the guard's reference, and what the quality objective ranks by (its start in
NumPy: no torch)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from pinn_engine.blas import one_thread
from pinn_engine.classical.spacing import classical_grid, working_spacing
from pinn_engine.classical.warm import WarmStart
from pinn_engine.geometry.auxlines import AuxLine
from pinn_engine.geometry.boundary import Boundary
from pinn_engine.settings import Settings
from pinn_engine.starts.untangle import untangled_start
from pinn_engine.starts.warmstart import elliptic_start, orthogonal_start

if TYPE_CHECKING:
    from pinn_engine.starts.quality_start import Ranking


@dataclass
class QuadStart:
    """Where a four-sided block's training starts, on the lattice: the ``warm`` start, the
    guard's ``reference`` grid, the quality objective's ``start`` grid and ``ranking``, the
    lattice's node parameters ``params`` (a spacing), and the folded ``winslow`` grid that
    the start untangles (untangle.py)."""

    warm: WarmStart
    reference: np.ndarray
    start: np.ndarray | None = None
    params: np.ndarray | None = None
    ranking: Ranking | None = None
    winslow: np.ndarray | None = None


def quad_start(
    boundary: Boundary, settings: Settings, lattice: tuple[int, int], aux: Sequence[AuxLine]
) -> QuadStart:
    """The start on ``lattice``. The reference is the converged elliptic grid (untangled
    where it folds, untangle.py), under the spacing if one is set (its node parameters,
    spacing.py), or the orthogonal start grid itself under ``--orthogonal``
    (orthogonal.py)."""
    spacing = working_spacing(settings.spacing, boundary) if settings.spacing else {}
    params = reference = None
    if spacing:
        params, reference = classical_grid(boundary, *lattice, "elliptic", spacing)
    if settings.orthogonal:
        heights = {s: h for s, h in spacing.items() if s in settings.orthogonal}
        warm, reference = orthogonal_start(boundary, *lattice, settings.orthogonal, params, heights)
        lattice_params = None if warm.nodes is None else np.stack(np.meshgrid(*warm.nodes), -1)
        return QuadStart(warm, reference, params=lattice_params)
    warm, elliptic = elliptic_start(boundary, *lattice)
    if settings.method != "pinn":
        return QuadStart(warm, elliptic if reference is None else reference, params=params)
    if settings.quality_objective:
        from pinn_engine.starts.quality_start import Ranking, quality_start

        tfi = elliptic - warm.correction  # the TFI base plus the new start's correction
        ranking = Ranking.of(elliptic, aux, boundary.diagonal)
        with one_thread():  # its L-BFGS, as _lbfgs's
            warm, ranking = quality_start(warm, elliptic, ranking)
        start = tfi + warm.correction
        return QuadStart(warm, elliptic if reference is None else reference, start, params, ranking)
    if reference is None:
        untangled = untangled_start(warm, elliptic)
        if untangled is not None:
            return QuadStart(*untangled, winslow=elliptic)
    return QuadStart(warm, elliptic if reference is None else reference, params=params)
