"""Multi-block set-up as CFD users do it (SPEC 10): a whole ring named in one --patch item,
negative patch points, --cells X,Y=N on a chain, --spacing X,Y=H at any block side (an
interior one too) growing along the chain, in the command line and in pyvista."""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv
from helpers import EXAMPLES

from pinn_engine.routes.cli import main

DFG = [str(EXAMPLES / "dfg.vtp"), "--blocks", str(EXAMPLES / "dfg_blocks.vtp")]
CYLINDER = [str(EXAMPLES / "cylinder_channel.vtp"), "--blocks"]
CYLINDER += [str(EXAMPLES / "cylinder_channel_blocks.vtp"), "--cell-size", "0.25"]
COARSE = ["--cell-size", "0.02", "--method", "elliptic", "--quiet"]
GRADE = 0.005  # a first edge at the DFG cylinder's box, half the cell size of COARSE


def _run(tmp_path, args, name="grid.vtm"):
    out = tmp_path / name
    assert main([*args, "-o", str(out)]) == 0
    return out


def _markers(path) -> list[str]:
    return [
        line.split("=")[1].strip() for line in path.read_text().splitlines() if "MARKER_TAG" in line
    ]


def test_a_ring_is_named_in_one_item_and_is_one_patch(tmp_path):
    """hole1= and boundary= name every piece of their ring; a point item still names one
    piece over its ring's name; the SU2 export has one marker a name."""
    su2 = _run(
        tmp_path,
        [*DFG, *COARSE, "--patch", "hole1=cylinder:wall", "--patch", "boundary=walls:wall",
         "--patch", "0,0.2=inlet:inflow"],
        "dfg.su2",
    )  # fmt: skip
    assert sorted(_markers(su2)) == ["cylinder", "inlet", "walls"]


def test_a_negative_patch_point_and_a_ring_that_does_not_exist(tmp_path, capsys):
    """--patch -0.5,0=NAME is a value, not an option; hole2 of a domain with one hole is
    refused in one line naming its rings."""
    su2 = _run(
        tmp_path, [*CYLINDER, "--method", "tfi", "--patch", "-0.5,0=back", "--quiet"], "c.su2"
    )
    assert sorted(_markers(su2)) == ["back", "boundary", "hole1"]
    assert main([*CYLINDER, "--patch", "hole2=x", "-o", str(tmp_path / "x.vtm")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no ring hole2 (its rings: boundary, hole1)" in err


def _block_at(grid: pv.MultiBlock, x: float, y: float) -> np.ndarray:
    """The nodes (nj, ni, 2) of the block whose nodes' mean is nearest (x, y)."""
    block = min(grid, key=lambda b: np.linalg.norm(b.points[:, :2].mean(axis=0) - (x, y)))
    ni, nj, _ = block.dimensions
    return block.points[:, :2].reshape(nj, ni, 2)


def test_cells_set_a_chain_and_a_negative_point_works(tmp_path):
    """--cells X,Y=N gives the chain through the side nearest (X, Y) N cells: the three
    blocks downstream of the DFG box and, through the cylinder channel's inlet (a negative
    x), the block at the inlet; that chain ends at the cylinder (the O-ring's blocks join
    the arc to the box's side), so the block downstream keeps its count from the cell size
    (2 / 0.25)."""
    grid = pv.read(_run(tmp_path, [*DFG, *COARSE, "--cells", "1.2,0.41=17"]))
    for y in (0.05, 0.2, 0.355):
        assert _block_at(grid, 1.2, y).shape[1] == 18
    grid = pv.read(_run(tmp_path, [*CYLINDER, "--method", "tfi", "--cells", "-3,0=9", "--quiet"]))
    assert _block_at(grid, -2, 0).shape[0] == 10
    assert _block_at(grid, 3, 0).shape[0] == 9


def _middle(first: np.ndarray) -> np.ndarray:
    """The first edges of a side's lines but the two at its corners (SPEC 7 excepts
    corners)."""
    return first[1:-1]


def _growth(cells: np.ndarray) -> float:
    ratio = cells[1:] / cells[:-1]
    return float(max(ratio.max(), (1 / ratio).max()))


@pytest.mark.slow  # graded multi-block runs on both sides of a side
def test_spacing_at_an_interior_side_grades_both_sides(tmp_path):
    """--spacing X,Y=H at the DFG box's right side (an interface): the first cells on both
    sides are H across it (within 10 %; the lines at the side's corners aside), the column
    downstream grows by at most 1.25 a cell along every row (the walls' rows too), and no
    cell folds."""
    out = _run(
        tmp_path,
        [*DFG, *COARSE, "--spacing", f"0.3,0.2={GRADE}", "--report", str(tmp_path / "r.json")],
    )
    grid = pv.read(out)
    assert sum(int(b.cell_data["Folded"].sum()) for b in grid) == 0
    for y in (0.05, 0.2, 0.355):
        rows = _block_at(grid, 1.2, y)
        cells = np.linalg.norm(np.diff(rows, axis=1), axis=2)
        assert np.all(np.abs(_middle(cells[:, 0]) / GRADE - 1) < 0.1)
        assert max(_growth(row) for row in cells) <= 1.25
    ring = _block_at(grid, 0.27, 0.2)  # the O-ring's block right of the cylinder
    lines = ring.transpose(1, 0, 2)  # its radial lines, from the box's side inward
    first = np.linalg.norm(lines[:, 1] - lines[:, 0], axis=1)
    assert np.all(np.abs(_middle(first) / GRADE - 1) < 0.1)


@pytest.mark.slow  # the DFG channel twice, refused then graded (about 5 s CPU)
def test_cells_and_spacing_together_and_the_count_a_grading_needs(tmp_path, capsys):
    """A graded chain given too few cells is refused in one line saying how many it needs;
    with enough, the downstream rows start at H and grow by at most 1.25."""
    bad = [*DFG, *COARSE, "--cells", "1.2,0.41=12", "--spacing", f"0.3,0.2={GRADE / 5}"]
    assert main([*bad, "-o", str(tmp_path / "x.vtm")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "needs at least" in err and "cells 1.2,0.41=12" in err
    args = [*DFG, *COARSE, "--cells", "1.2,0.41=40", "--spacing", f"0.3,0.2={GRADE}"]
    rows = _block_at(pv.read(_run(tmp_path, args)), 1.2, 0.2)
    cells = np.linalg.norm(np.diff(rows, axis=1), axis=2)
    assert rows.shape[1] == 41 and max(_growth(row) for row in cells) <= 1.25
    assert np.all(np.abs(_middle(cells[:, 0]) / GRADE - 1) < 0.1)


@pytest.mark.slow  # the DFG channel on two routes (about 5 s CPU)
def test_pyvista_takes_the_same_settings(tmp_path):
    """pyvista's patches={"hole1": ...}, cells={(x, y): n} and spacing={(x, y): h} give the
    command line's grid."""
    out = _run(
        tmp_path,
        [*DFG, *COARSE, "--patch", "hole1=cylinder:wall", "--cells", "1.2,0.41=40",
         "--spacing", f"0.3,0.2={GRADE}", "--spacing", "cylinder=0.002"],
    )  # fmt: skip
    cli = pv.read(out)
    boundary = pv.read(EXAMPLES / "dfg.vtp")
    grid = boundary.pinn_mesh(
        blocks=pv.read(EXAMPLES / "dfg_blocks.vtp"),
        cell_size=0.02,
        method="elliptic",
        patches={"hole1": "cylinder:wall"},
        cells={(1.2, 0.41): 40},
        spacing={(0.3, 0.2): GRADE, "cylinder": 0.002},
    )
    assert len(grid) == len(cli)
    for a, b in zip(grid, cli):
        assert np.allclose(a.points, b.points, atol=1e-12)


def _ratios(path) -> list[tuple[float, float]]:
    """Each block's ratio of its last cell to its first along i, on its first and last rows."""
    out = []
    for grid in pv.read(path):
        ni, nj, _ = grid.dimensions
        nodes = grid.points[:, :2].reshape(nj, ni, 2)
        d = [np.linalg.norm(np.diff(nodes[j], axis=0), axis=1) for j in (0, -1)]
        out.append((d[0][-1] / d[0][0], d[1][-1] / d[1][0]))
    return out


def test_an_expansion_ratio_grades_every_block_along_its_chain(tmp_path, capsys):
    """``--grading X,Y=R`` as blockMesh's expansion ratio: the wake column behind the
    cylinder (three blocks) grows 4 times from the box to the outlet, every row of it."""
    out = _run(tmp_path, [*CYLINDER, "--method", "elliptic", "-q", "--grading", "1.5,-2=4"])
    graded = [b for b, rows in enumerate(_ratios(out)) if np.allclose(rows, 4.0, rtol=1e-3)]
    assert len(graded) == 3  # the wake column, each of its rows
    argv = [str(EXAMPLES / "lshape.vtp"), "--blocks", str(EXAMPLES / "lshape_blocks.vtp")]
    assert main([*argv, "--grading", "1.9,0=5", "-o", str(tmp_path / "l.vtm"), "-q"]) == 2
    err = capsys.readouterr().err
    assert "side of several pieces" in err and err.count("\n") == 1
    assert main([*argv, "--grading", "1.9,0=-1", "-o", str(tmp_path / "l.vtm"), "-q"]) == 2
    assert "expected X,Y=R, R > 0" in capsys.readouterr().err
    boundary, edges = (pv.read(EXAMPLES / f) for f in CYLINDER[0:3:2])
    grid = boundary.pinn_mesh(
        blocks=edges, cell_size=0.25, method="elliptic", grading={(1.5, -2): 4}
    )
    assert len(grid) == 12  # pyvista's grading= gives the command line's grid
    assert all(np.allclose(a.points, b.points, atol=1e-12) for a, b in zip(grid, pv.read(out)))


def _polylines(path, lines, closed=False):
    """``lines`` (lists of (x, y)) written as one polydata of polylines."""
    points, cells = [], []
    for line in lines:
        ids = list(range(len(points), len(points) + len(line)))
        points += [(x, y, 0.0) for x, y in line]
        cells += [len(ids) + closed, *ids, *ids[:1]] if closed else [len(ids), *ids]
    pv.PolyData(np.array(points), lines=np.array(cells)).save(path)
    return str(path)


def test_the_default_keeps_a_step_s_orthogonal_tfi_grid_over_a_sheared_solve(tmp_path, capsys):
    """A backward-facing step of three rectangles with --cells: TFI is orthogonal, while the
    solve with free interfaces shears the cells round the lip (worst 165 degrees at this
    size); the default starts from the better grid and says so."""
    ring = [(-1, 0), (0, 0), (0, -1), (8, -1), (8, 1), (-1, 1)]
    boundary = _polylines(tmp_path / "step.vtp", [ring], closed=True)
    blocks = _polylines(tmp_path / "blocks.vtp", [[(0, 0), (0, 1)], [(0, 0), (8, 0)]])
    cells = ["--cells=-0.5,1=10", "--cells", "0,-0.5=15", "--cells=-1,0.5=15", "--cells", "4,1=30"]
    out = tmp_path / "step.vtm"
    assert main([boundary, "--blocks", blocks, *cells, "-o", str(out)]) == 0
    summary = "".join(capsys.readouterr())
    assert "worst 90.00 deg" in summary and "chose the tfi grid in every block" in summary
    assert "ranks above the Winslow grid" in summary
    elliptic = tmp_path / "elliptic.vtm"
    assert (
        main([boundary, "--blocks", blocks, *cells, "--method", "elliptic", "-o", str(elliptic)])
        == 0
    )
    worst = "".join(capsys.readouterr()).split("worst ")[1].split(" deg")[0]
    assert float(worst) > 120.0  # the check can fail: the solve shears this step
