"""A four-sided block's network trained at one size and asked for another: resolution as a
family (docs/family.md). The map the network learned is continuous in (xi, eta), so any node
counts are one forward pass of it. The grid is kept where it passes the guard that the asked
size's own training applies to each of its states (``problem.guard_rule``, against the start
on that size's lattice: no more folded cells, mean and worst angles within ``GUARD_TOL``,
the wall angles and the untangled grid's bounds) and folds no cell; otherwise the asked
size's own run trains (``cache.MeshCache.fitted``). A size change in ParaView or pyvista thus
costs the start's solve (the grid the guard compares with, which that size's own run trains
from) and a forward pass, not a training, and returns a grid that run's guard would accept.
"""

from __future__ import annotations

import copy
import time
from collections.abc import Sequence
from typing import TYPE_CHECKING

from pinn_engine.geometry.auxlines import AuxLine
from pinn_engine.quality import guard_figures
from pinn_engine.result import MeshResult
from pinn_engine.settings import Settings
from pinn_engine.starts.quad_start import quad_start
from pinn_engine.starts.warmstart import lattice_for

if TYPE_CHECKING:
    from pinn_engine.kinds.four_sided.mesher import Mesher


def resized(
    mesher: Mesher, aux: Sequence[AuxLine], settings: Settings, ni: int, nj: int
) -> tuple[MeshResult | None, dict]:
    """The grid at ``ni`` x ``nj`` of ``mesher``'s network, trained at another lattice, under
    ``settings`` (the asked size's), and what the report says of it (``resized``); the grid
    is None where it fails the guard (the caller then runs that size's own training)."""
    from pinn_engine.kinds.four_sided.problem import guard_rule  # torch: the network's own

    began = time.perf_counter()
    lattice = lattice_for(*settings.lattice)
    begin = quad_start(mesher.boundary_, settings, lattice, aux)
    figures, accept, kept, ref = guard_rule(
        begin.reference, begin.start, settings.orthogonal, begin.ranking, begin.winslow
    )
    started = time.perf_counter()
    size = begin.reference.shape[1], begin.reference.shape[0]
    grid = mesher.model_.mapping.grid(*size, params=begin.params)
    checked = figures(grid)
    at_size = copy.copy(mesher)
    at_size.settings = settings  # the asked size's settings in its report
    same = size == (ni, nj) and begin.params is None  # the grid checked is the one asked
    result = at_size.predict(ni, nj, unit=grid if same else None)
    folds = result.report["quality"]["folded_cells"]
    start_folds = guard_figures(begin.reference)["folded_cells"]
    passed = accept(checked, kept) and folds <= start_folds
    info = {
        "trained_at": list(mesher.settings.lattice),
        "size": [ni, nj],
        "result": "network" if passed else "trained anew",
        "guard": {"network": _plain(checked), "start": _plain(ref), "lattice": list(size)},
        "timings": {"start": started - began, "guard": time.perf_counter() - started},
    }
    if not passed:
        info["why"] = (
            f"{folds} folded cells" if folds > start_folds else "outside the guard's bounds"
        )
        return None, info
    noted(result, info)
    return result, info


def noted(result: MeshResult, info: dict) -> None:
    """``result``'s report with what a size change did (``info``) and its summary line."""
    from pinn_engine.errors import network_effect

    result.report["resized"] = info
    result.report["choice"] = network_effect(result.report)


def _plain(figures: dict) -> dict:
    """Figures as JSON numbers (the report's)."""
    return {k: float(v) for k, v in figures.items() if isinstance(v, (int, float))}
