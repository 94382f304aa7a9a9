"""Multi-block domains (SPEC 10): topology errors, shared nodes, folds, the .vtm output and
how smoothly grid lines cross the interfaces."""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv
from helpers import EXAMPLES, run_blocks
from multiblock_checks import block_sides, interface_kinks, write_polylines
from vtkmodules.vtkFiltersVerdict import vtkMeshQuality

from pinn_engine.multiblock.graph import snap_edges
from pinn_engine.routes.cli import main
from pinn_engine.settings import make_settings

CYLINDER = ["cylinder_channel.vtp", "--blocks", "cylinder_channel_blocks.vtp", "--cell-size", "0.1"]
EXAMPLE_RUNS = {
    "lshape": ["lshape.vtp", "--blocks", "lshape_blocks.vtp"],
    "step": ["step.vtp", "--blocks", "step_blocks.vtp", "--cell-size", "0.1"],
    "cylinder": CYLINDER,
}


def _run(tmp_path, args: list[str], *more: str) -> tuple[int, pv.MultiBlock | None]:
    """Run the command on example files; the exit status and the grid read back."""
    out = tmp_path / "grid.vtm"
    files = [str(EXAMPLES / a) if a.endswith(".vtp") else a for a in args]
    code = main([*files, *more, "-o", str(out), "--quiet"])
    return code, pv.read(out) if out.exists() else None


RECTANGLE = [(0, 0), (2, 0), (2, 2), (0, 2)]


@pytest.mark.parametrize(
    "ring, edges, expected",
    [
        # a diagonal cut: two triangles
        (RECTANGLE, [[(0, 0), (2, 2)]], "has 3 corners"),
        # the right block has a chamfered corner: five corners
        ([(0, 0), (3, 0), (3, 1), (2, 2), (0, 2)], [[(1, 0), (1, 2)]], "has 5 corners"),
        (RECTANGLE, [[(1, 0), (1, 1.5)]], "ends nowhere at (1, 1.5)"),
        (RECTANGLE, [[(1, 0), (1, 2)], [(0, 1), (2, 1)]], "edges.vtp line 1 at (1, 1)"),
        # out through the top and back onto it
        (RECTANGLE, [[(1, 0), (1, 3), (1.5, 3), (1.5, 2)]], "crosses the boundary at (1, 2)"),
        # a boundary drawn as a bow tie: its faces were not found (an internal error)
        ([(0, 0), (2, 0), (0, 2), (2, 2)], [[(1, 0), (1, 1)]], "crosses itself at (1, 1)"),
    ],
)
def test_topology_errors(tmp_path, capsys, ring, edges, expected):
    """A block with other than four corners, an edge ending nowhere, crossing edges, a
    boundary crossing itself: one line naming the place, exit status 2, no file."""
    boundary = write_polylines(tmp_path / "ring.vtp", [ring], closed=True)
    blocks = write_polylines(tmp_path / "edges.vtp", edges)
    out = tmp_path / "grid.vtm"
    assert main([boundary, "--blocks", blocks, "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and expected in err, err
    assert not out.exists() and not (tmp_path / "grid").exists()


def test_mgnet_is_refused_and_pinn_is_the_default(tmp_path, capsys):
    """MGNet has no multi-block kind: --method mgnet says which methods work; without
    --method the grid is the pinn's."""
    assert _run(tmp_path, EXAMPLE_RUNS["lshape"], "--method", "mgnet")[0] == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "tfi, elliptic or pinn" in err
    code, grid = _run(tmp_path, EXAMPLE_RUNS["lshape"])
    assert code == 0 and str(grid[0].field_data["Method"][0]) == "pinn"


@pytest.mark.parametrize("name", sorted(EXAMPLE_RUNS))
@pytest.mark.parametrize("method", ["tfi", "elliptic", "pinn"])
def test_examples_have_no_folds_and_shared_nodes(tmp_path, name, method):
    """No folded cell; a node on a side shared by two blocks is the same point in both:
    side nodes closer than 1e-9 are equal, and every side node off the boundary is in at
    least two blocks."""
    code, grid = _run(tmp_path, EXAMPLE_RUNS[name], "--method", method, "--fail-on-folded")
    assert code == 0
    assert sum(int(b.cell_data["Folded"].sum()) for b in grid) == 0
    nodes = np.vstack([s for b in grid for s, _ in block_sides(b)])
    exact = np.unique(nodes, axis=0)
    close = np.unique(np.round(exact / 1e-9), axis=0)
    assert len(close) == len(exact)  # no two distinct nodes within 1e-9: shared means equal
    boundary = pv.read(EXAMPLES / EXAMPLE_RUNS[name][0])
    lines = boundary.extract_all_edges()
    _, closest = lines.find_closest_cell(
        np.column_stack([exact, np.zeros(len(exact))]), return_closest_point=True
    )
    off = np.linalg.norm(closest[:, :2] - exact, axis=1) > 1e-6  # the locator is that exact
    count = {tuple(p): 0 for p in exact}
    for block in grid:
        for p in {tuple(q) for s, _ in block_sides(block) for q in s}:
            count[p] += 1
    assert min(count[tuple(p)] for p in exact[off]) >= 2


def test_vtm_round_trip(tmp_path):
    """The .vtm holds one structured grid a block, named block0, block1, ..., with the
    quality arrays of SPEC 3 and the run's report."""
    code, grid = _run(tmp_path, CYLINDER)
    assert code == 0 and isinstance(grid, pv.MultiBlock)
    assert grid.keys() == [f"block{k}" for k in range(12)]
    cells = 0
    for block in grid:
        assert isinstance(block, pv.StructuredGrid)
        for name in ("MaxIncludedAngle", "MinIncludedAngle", "ScaledJacobian", "Folded"):
            assert len(block.cell_data[name]) == block.n_cells
        verdict = vtkMeshQuality()
        verdict.SetInputData(block)
        verdict.SetQuadQualityMeasureToMaxAngle()
        verdict.Update()
        expected = pv.wrap(verdict.GetOutput()).cell_data["Quality"]
        np.testing.assert_allclose(block.cell_data["MaxIncludedAngle"], expected, atol=1e-9)
        cells += block.n_cells
    assert cells == 4000  # SPEC 10's counts: 4 x 20 x 10 + 2 x (20 + 50) x 10 + ...
    assert "cell_size" in str(grid[0].field_data["Report"][0])


def test_elliptic_interfaces_are_smooth(tmp_path):
    """Around the cylinder, grid lines cross the interfaces of the elliptic grid with kinks
    of at most 2 degrees on average (15 at most); the drawn interfaces (tfi, or --interfaces
    fixed) kink by far more."""
    kinks = interface_kinks(_run(tmp_path, CYLINDER)[1])
    assert len(kinks) > 100 and kinks.mean() <= 2.0 and kinks.max() <= 15.0
    for more in (["--method", "tfi"], ["--interfaces", "fixed"]):
        drawn = interface_kinks(_run(tmp_path, CYLINDER, *more)[1])
        assert drawn.mean() > 5.0


def test_fixed_interfaces_keep_the_drawn_edge(tmp_path):
    """--interfaces fixed keeps the L-shape's askew edge where it is drawn; free, its end
    slides along the straight left wall and its nodes leave the drawn line."""

    def edge_nodes(grid):
        top = grid[1] if grid[1].bounds[3] > 1.9 else grid[0]
        ni, nj, _ = top.dimensions
        return top.points[:, :2].reshape(nj, ni, 2)[0]

    def off_line(p):  # distance from the drawn edge, (1, 1) to (0, 1.25)
        return np.abs(0.25 * (p[:, 0] - 1.0) + (p[:, 1] - 1.0)) / np.hypot(0.25, 1.0)

    fixed = edge_nodes(_run(tmp_path, EXAMPLE_RUNS["lshape"], "--interfaces", "fixed")[1])
    assert off_line(fixed).max() < 1e-12 and fixed[0, 0] == 0.0 and fixed[0, 1] == 1.25
    free = edge_nodes(_run(tmp_path, EXAMPLE_RUNS["lshape"])[1])
    assert off_line(free).max() > 1e-2 and free[0, 0] == 0.0 and free[0, 1] != 1.25


@pytest.mark.parametrize("method", ["tfi", "elliptic"])
def test_kinks_against_the_lines_own_turn(method):
    """The report's ``inside_mean``: the turn of the interface-crossing grid lines one node
    inside the blocks. On the Y-branch's elliptic grid the kink is about that (the lines are
    smooth; they turn in the 3-block centre), on TFI's the lines are straight inside the
    blocks and bent at the interfaces."""
    settings = make_settings(method, cell_size=0.1)
    files = EXAMPLES / "ybranch.vtp", [EXAMPLES / "ybranch_blocks.vtp"]
    kink = run_blocks(settings, *files).report["interface_kink"]
    if method == "elliptic":
        assert 0.8 * kink["mean"] <= kink["inside_mean"] <= kink["mean"]
    else:
        assert kink["inside_mean"] < 0.1 < 10.0 < kink["mean"]


def test_ybranch_kinks_fall_within_the_bound_as_cells_shrink():
    """The Y-branch's 3-block centre turns its grid lines by about 60 degrees: at a cell size
    of 0.1 that is over the bound of a 2-degree mean kink a node; at 0.025 (16 times the
    cells, the benchmark's row) the same turn spread over more nodes is within it."""
    files = EXAMPLES / "ybranch.vtp", [EXAMPLES / "ybranch_blocks.vtp"]
    kinks = {
        h: run_blocks(make_settings("elliptic", cell_size=h), *files).report for h in (0.1, 0.025)
    }
    coarse, fine = (kinks[h]["interface_kink"] for h in (0.1, 0.025))
    assert coarse["mean"] > 2.0 >= fine["mean"] and fine["max"] <= 15.0
    assert kinks[0.025]["quality"]["folded_cells"] == 0


def test_ends_snapped_onto_one_side_are_inserted_in_order():
    """Two edges across a square end on its bottom side: the second end's foot goes in
    after the first's (the side's points are re-read after each insertion)."""
    ring = np.array(RECTANGLE, dtype=float)
    edges = [np.array([(0.5, 2.0), (0.5, 0.0)]), np.array([(1.5, 2.0), (1.5, 0.0)])]
    curves, loose = snap_edges([ring], edges, 1e-6)
    assert not loose
    assert curves[0][:4] == [(0.0, 0.0), (0.5, 0.0), (1.5, 0.0), (2.0, 0.0)]
