"""The multi-block pinn: each block's PINN on the elliptic grid, its sides
held, kept only where no worse; never worse than the elliptic grid."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import ROOT, run_blocks

from pinn_engine.classical.tfi import tfi_of_sides
from pinn_engine.errors import STOP
from pinn_engine.kinds.blocks.problem import train_block, train_blocks
from pinn_engine.multiblock.mesh import mesh_blocks
from pinn_engine.quality import guard_figures
from pinn_engine.settings import make_settings

DATA = ROOT / "example_data"
MEAN_OVER, WORST_OVER = 0.5, 2.0  # degrees above the elliptic grid allowed
ROUNDING = 1e-9  # degrees: the guard checks the working frame's grid, the output is in yours
QUICK = {"lbfgs_iterations": 20}  # a short training: the guard's rule, not its reach, is tested


def _sides(grid: np.ndarray) -> list[np.ndarray]:
    return [grid[0], grid[-1], grid[:, 0], grid[:, -1]]


@pytest.fixture(scope="module", params=["step", "cylinder_channel"])
def runs(request):
    """The example's elliptic and default pinn grids at a cell size of 0.1."""
    files = DATA / f"{request.param}.vtp", [DATA / f"{request.param}_blocks.vtp"]
    return {m: run_blocks(make_settings(m, cell_size=0.1), *files) for m in ("elliptic", "pinn")}


def test_pinn_is_never_worse_than_elliptic(runs):
    """No fold; mean and worst MaxIncludedAngle no more than 0.5 / 2 degrees
    above the elliptic grid's, and by the guard's rule no more than rounding above them."""
    ell, pinn = runs["elliptic"].report["quality"], runs["pinn"].report["quality"]
    assert pinn["folded_cells"] == 0
    assert pinn["mean_max_angle"] <= ell["mean_max_angle"] + min(MEAN_OVER, ROUNDING)
    assert pinn["worst_max_angle"] <= ell["worst_max_angle"] + min(WORST_OVER, ROUNDING)
    kink = runs["pinn"].report["interface_kink"]
    assert kink["mean"] <= 2.0 and kink["max"] <= 15.0  # the interface bounds
    ell_kink = runs["elliptic"].report["interface_kink"]
    assert kink["mean"] <= ell_kink["mean"] + ROUNDING and kink["max"] <= ell_kink["max"] + ROUNDING


def test_the_guard_keeps_interfaces_as_smooth_as_elliptic(monkeypatch):
    """A Y-branch with a narrow arm (not one of the examples; found in a sweep of variants):
    judged by its own cells alone, a block's network had raised the grid's interface kink
    max from 15.1 to 20.7 degrees at the default cell size; the guard judges the whole
    grid's kinks too, so the pinn's are no larger than the elliptic grid's."""
    monkeypatch.syspath_prepend(str(DATA))
    import make_multiblock

    monkeypatch.setattr(make_multiblock, "Y_ARMS", (-38.0, 38.0, 180.0))
    monkeypatch.setattr(make_multiblock, "Y_WIDTHS", (0.95, 0.67, 1.0))
    monkeypatch.setattr(make_multiblock, "Y_MOUTH", 1.23)
    rings, edges = make_multiblock.ybranch()
    names = [f"edge {k}" for k in range(len(edges))]
    kinks = {
        m: mesh_blocks(
            rings, edges, names, make_settings(m, kind="blocks"), train=train_blocks
        ).report["interface_kink"]
        for m in ("elliptic", "pinn")
    }
    assert kinks["pinn"]["max"] <= kinks["elliptic"]["max"] + ROUNDING
    assert kinks["pinn"]["mean"] <= kinks["elliptic"]["mean"] + ROUNDING


def test_sides_are_the_elliptic_grids_and_blocks_report_what_was_kept(runs):
    """Every block's side nodes are the elliptic grid's bit for bit (so a node on a shared
    side is one point in both blocks); a block where the network was kept differs inside,
    one where the start was kept is the elliptic block."""
    training = runs["pinn"].report["training"]
    assert len(training["blocks"]) == runs["pinn"].report["blocks"]
    assert training["seconds"] >= sum(b["seconds"] for b in training["blocks"]) > 0
    for grid, start, block in zip(runs["pinn"].grids, runs["elliptic"].grids, training["blocks"]):
        assert all(np.array_equal(a, b) for a, b in zip(_sides(grid), _sides(start)))
        assert np.array_equal(grid, start) == (block["result"] == "start")
    assert training["network_blocks"] == sum(b["result"] == "network" for b in training["blocks"])


def test_a_block_the_network_improves_is_kept():
    """Started from a TFI block (not the converged Winslow grid), the network finds a better
    grid on the same sides: the network's state is kept, no worse than the start."""
    t = np.linspace(0.0, 1.0, 17)
    bottom = np.column_stack([t, 0.3 * np.sin(np.pi * t)])
    top = np.column_stack([t, 1.0 + 0.0 * t])
    s = np.linspace(0.0, 1.0, 11)
    left = np.column_stack([0.0 * s, 1.0 * s])
    right = np.column_stack([1.0 + 0.4 * s * (1 - s), s])
    start = tfi_of_sides(bottom, right, top, left) * 2.0 + 5.0  # off the unit box
    trained = train_block(start, make_settings("pinn", **QUICK))
    assert trained.result == "network" and trained.info["lbfgs_iterations"] > 0
    assert all(np.array_equal(a, b) for a, b in zip(_sides(trained.grid), _sides(start)))
    kept, before = guard_figures(trained.grid), guard_figures(start)
    assert kept["mean_max_angle"] < before["mean_max_angle"]
    assert kept["worst_max_angle"] <= before["worst_max_angle"] + ROUNDING


def test_progress_per_block_and_stop():
    """The progress callback hears each block start and its training steps with the block;
    a STOP at the second block's start leaves it and the rest at their start grids."""
    t = np.linspace(0.0, 1.0, 9)
    square = np.stack(np.meshgrid(t, t), axis=-1)
    skewed = (
        square + 0.1 * np.sin(np.pi * square[..., ::-1]) * square[..., :1] * (1 - t)[:, None, None]
    )
    heard: list[dict] = []

    def progress(info: dict):
        heard.append(info)
        return STOP if info["phase"] == "prepare" and info["step"] == 1 else None

    grids, report = train_blocks([skewed, skewed, square], make_settings("pinn", **QUICK), progress)
    stages = [i for i in heard if i["phase"] == "prepare"]
    assert [i["stage"] for i in stages] == ["training block 1 of 3", "training block 2 of 3"]
    assert {i["block"] for i in heard if i["phase"] == "lbfgs"} == {0}
    assert [b.get("stopped", False) for b in report["blocks"]] == [False, True, True]
    assert np.array_equal(grids[1], skewed) and np.array_equal(grids[2], square)
