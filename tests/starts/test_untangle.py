"""The default's fold-free grids: where the Winslow grid folds, the default pinn starts from
it untangled (starts/untangle.py), a four-sided domain and each block of a multi-block grid."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import EXAMPLES

from pinn_engine.classical.elliptic import winslow_solve
from pinn_engine.classical.pins import pinned_boundary
from pinn_engine.classical.tfi import tfi_grid
from pinn_engine.errors import folded_cells_warning
from pinn_engine.geometry.boundary_fit import ArcLengthFit
from pinn_engine.io.pipeline import load_boundary
from pinn_engine.kinds.blocks.problem import train_block
from pinn_engine.kinds.blocks.untrained import start_block
from pinn_engine.kinds.four_sided.mesher import Mesher
from pinn_engine.kinds.untrained import WINSLOW
from pinn_engine.quality import folded_cells, guard_figures, largest_area_ratio
from pinn_engine.settings import make_settings
from pinn_engine.starts import untangle

SIZE = (41, 21)  # backward_step's Winslow grid folds a cell at the step at this size
MEAN_OVER, RATIO_TIMES = 1.0, 1.5  # the untangled grid's bounds against the Winslow grid


@pytest.fixture(scope="module")
def step():
    return load_boundary(EXAMPLES / "hard" / "backward_step.vtp")


@pytest.fixture(scope="module")
def winslow(step):
    """The Winslow grid on the default's boundary nodes: a node on each sharp vertex of the
    step's sides (``pins.pinned_boundary``)."""
    return winslow_solve(tfi_grid(ArcLengthFit(pinned_boundary(step, *SIZE)).sample, *SIZE))[0]


def _close(grid: np.ndarray, winslow: np.ndarray) -> bool:
    return guard_figures(grid)["mean_max_angle"] <= (
        guard_figures(winslow)["mean_max_angle"] + MEAN_OVER
    ) and largest_area_ratio(grid) <= RATIO_TIMES * largest_area_ratio(winslow)


def test_the_default_is_fold_free_where_the_winslow_grid_folds(step, winslow):
    """The Winslow objective's pinn grid has no fold where the elliptic grid has some, keeps
    its boundary nodes, its mean angle and its cell-size changes, and the report says so;
    the default's (the quality objective's) has none either, its boundary nodes kept, its
    worst cell below the Winslow grid's and its mean at most 0.5 above."""
    assert folded_cells(winslow).sum() > 0
    default = Mesher(make_settings("pinn", lattice=SIZE)).fit(step).predict(*SIZE)
    assert default.quality["folded_cells"] == 0
    reference = guard_figures(winslow)
    assert default.quality["worst_max_angle"] < reference["worst_max_angle"] - 5
    assert default.quality["mean_max_angle"] <= reference["mean_max_angle"] + 0.5
    unit = step.frame.to_unit(default.points)
    for side in (np.s_[0], np.s_[-1], np.s_[:, 0], np.s_[:, -1]):
        np.testing.assert_allclose(unit[side], winslow[side], atol=1e-9)
    settings = make_settings("pinn", lattice=SIZE, objective="winslow")
    result = Mesher(settings).fit(step).predict(*SIZE)
    unit = step.frame.to_unit(result.points)
    assert result.quality["folded_cells"] == 0
    assert _close(unit, winslow)
    for side in (np.s_[0], np.s_[-1], np.s_[:, 0], np.s_[:, -1]):
        np.testing.assert_allclose(unit[side], winslow[side], atol=1e-9)
    training = result.report["training"]
    assert training["start"] == "untangled"
    assert training["untangled"] == {
        "winslow_folded_cells": int(folded_cells(winslow).sum()),
        "folded_cells": 0,
        "within_bounds": True,
    }


def test_untangling_never_folds_more(winslow, monkeypatch):
    """A grid that does not fold comes back as it is; where no untangled grid keeps close
    enough to the Winslow grid, the one with the fewest folds comes back (a solver takes a
    fold-free grid outside the bounds, not a folded one), and the report says it is outside
    them; where every grid met folds more, the Winslow grid itself."""
    plain = np.stack(np.meshgrid(np.linspace(0, 2, 9), np.linspace(0, 1, 5)), axis=-1)
    assert untangle.untangle(plain) is plain
    monkeypatch.setattr(untangle, "MEAN_TOL", -90.0)  # nothing is close enough
    outside = untangle.untangle(winslow)
    assert folded_cells(outside).sum() == 0
    assert untangle.untangled_report(winslow, outside)["within_bounds"] is False
    monkeypatch.setattr(untangle, "_move", lambda grid, free: grid[:, ::-1])  # all folded
    assert untangle.untangle(winslow) is winslow


def test_coarse_narrow_slots_are_untangled_within_the_bounds():
    """The hard set's staggered slots at 21 x 11: the boundary nodes cut across the slots,
    and the angle term finds a fold-free grid within the bounds (the Winslow functional's
    weighted edge lengths gave none)."""
    boundary = load_boundary(EXAMPLES / "hard" / "two_slots.vtp")
    slots = winslow_solve(tfi_grid(ArcLengthFit(boundary).sample, 21, 11))[0]
    assert folded_cells(slots).sum() > 0 and untangle.fold_forced(slots) is None
    grid = untangle.untangle(slots)
    assert folded_cells(grid).sum() == 0 and _close(grid, slots)


def test_a_fold_that_the_boundary_nodes_force_is_said():
    """A domain corner whose boundary edges make more than 180 degrees folds its one cell
    in every grid on those nodes: ``fold_forced`` says so, the report carries it and the
    folded-cells warning gives it in one line."""
    grid = np.stack(np.meshgrid(np.linspace(0, 2, 9), np.linspace(0, 1, 5)), axis=-1)
    grid[0, 0] = (0.5, 0.5)  # inside: the corner's edges open to 270 degrees
    reason = untangle.fold_forced(grid)
    assert reason and "(i, j) = (0, 0)" in reason
    report = untangle.untangled_report(grid, grid)
    assert report["forced"] == reason
    warning = folded_cells_warning(
        {"quality": {"folded_cells": 1}, "size": [9, 5], "training": {"untangled": report}},
        "cli",
    )
    assert "no grid on these boundary nodes is fold-free" in warning and "\n" not in warning
    assert untangle.fold_forced(np.stack(np.meshgrid(np.arange(4.0), np.arange(3.0)), -1)) is None


def test_a_folded_block_of_a_multiblock_grid_is_untangled(winslow):
    """A block of the multi-block pinn whose elliptic grid folds comes out fold-free, with
    its side nodes bit for bit, and the block's report says it was untangled."""
    block = winslow * 3.0 + 1.0  # in the user's units
    trained = train_block(block, make_settings("pinn", lbfgs_iterations=5))
    assert folded_cells(trained.grid).sum() == 0
    for side in (np.s_[0], np.s_[-1], np.s_[:, 0], np.s_[:, -1]):
        assert np.array_equal(trained.grid[side], block[side])
    assert trained.info["untangled"]["winslow_folded_cells"] > 0
    assert _close(trained.grid, block)


def test_an_untrained_block_is_untangled_too(winslow):
    """A block whose network cannot win (no auxiliary line in it) keeps its start untangled,
    its side nodes bit for bit, as the multi-block pinn's report says."""
    block = winslow * 3.0 + 1.0
    grid, report = start_block(block, WINSLOW)
    assert folded_cells(grid).sum() == 0 and report["untangled"]["folded_cells"] == 0
    for side in (np.s_[0], np.s_[-1], np.s_[:, 0], np.s_[:, -1]):
        assert np.array_equal(grid[side], block[side])
    assert _close(grid, block)
