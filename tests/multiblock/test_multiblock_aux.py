"""Auxiliary lines inside blocks: each line goes to the block holding its
middle point and is fitted by that block's PINN (SPEC 2 on the block's sides); a line in no
block, or one that leaves its block, is one line, exit 2, no file."""

from __future__ import annotations

import json

import numpy as np
import pytest
import pyvista as pv
from helpers import ROOT, run_blocks
from multiblock_checks import write_polylines

from pinn_engine.routes.cli import main
from pinn_engine.settings import make_settings

DATA = ROOT / "example_data"
FILES = DATA / "lshape.vtp", [DATA / "lshape_blocks.vtp"]
AUX = DATA / "lshape_aux.vtp"  # a bent line inside the L's bottom block
LINE = f"{AUX} line 0"
MEAN_OVER, WORST_OVER = 0.5, 2.0  # degrees above the elliptic grid allowed


def block_sides(grid: np.ndarray) -> list[np.ndarray]:
    return [grid[0], grid[-1], grid[:, 0], grid[:, -1]]


@pytest.fixture(scope="module")
def runs():
    """The L-shape with its line, elliptic and pinn, at a cell size of 0.1."""
    return {
        m: run_blocks(make_settings(m, cell_size=0.1), *FILES, aux=[AUX])
        for m in ("elliptic", "pinn")
    }


def test_the_block_holding_the_line_follows_it(runs):
    """The bottom block's network moves its grid nearer the drawn line than the elliptic
    grid is (the other block, without lines, keeps its elliptic grid); no fold, quality
    within 0.5 / 2 degrees of the elliptic grid's, side nodes the elliptic grid's."""
    ell, pinn = runs["elliptic"], runs["pinn"]
    assert ell.report["aux_lines"] == pinn.report["aux_lines"] == [LINE]
    before = ell.report["aux_line_distance"][LINE]
    after = pinn.report["aux_line_distance"][LINE]
    assert after < 0.8 * before
    assert [b["result"] for b in pinn.report["training"]["blocks"]] == ["network", "start"]
    q, e = pinn.report["quality"], ell.report["quality"]
    assert q["folded_cells"] == 0
    assert q["mean_max_angle"] <= e["mean_max_angle"] + MEAN_OVER
    assert q["worst_max_angle"] <= e["worst_max_angle"] + WORST_OVER
    for grid, start in zip(pinn.grids, ell.grids):
        assert all(np.array_equal(a, b) for a, b in zip(block_sides(grid), block_sides(start)))


@pytest.mark.parametrize(
    ("points", "message"),
    [
        ([(1.5, 1.5), (1.8, 1.8)], "line 0: its middle point (1.65, 1.65) lies in no block"),
        (
            [(0.5, 0.0), (0.5, 1.8)],
            "line 0: does not end on two opposite sides (start near bottom, end near no side; "
            "tolerance 0.01 of the diagonal) (in the block at (1, 0.5); an auxiliary line "
            "runs inside one block",
        ),
    ],
)
def test_a_line_outside_its_block_is_one_line(tmp_path, capsys, points, message):
    aux, out = write_polylines(tmp_path / "aux.vtp", [points]), tmp_path / "grid.vtm"
    args = [str(FILES[0]), "--blocks", str(FILES[1][0]), "--aux", aux, "--method", "tfi"]
    assert main([*args, "-o", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err
    assert not out.exists()


def test_pyvista_takes_the_lines_as_aux(runs):
    """pyvista's ``blocks=`` with ``aux=``: the command line's pinn grid node for node."""
    boundary = pv.read(FILES[0])
    blocks = boundary.pinn_mesh(
        blocks=pv.read(FILES[1][0]), aux=pv.read(AUX), cell_size=0.1, method="pinn"
    )
    for block, expected in zip(blocks, runs["pinn"].grids):
        nj, ni = expected.shape[:2]
        assert np.array_equal(block.points[:, :2].reshape(nj, ni, 2), expected)
    report = json.loads(blocks[0].field_data["Report"][0])["multiblock"]
    assert list(report["aux_line_distance"]) == ["auxiliary lines input line 0"]
