"""The rule every written 2D grid keeps (``job.cover``): it covers exactly the domain drawn,
every sharp corner a node; otherwise one line that names the fix, and no file."""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv
from helpers import EXAMPLES, bumped_l

from pinn_engine import job
from pinn_engine.errors import InputError
from pinn_engine.geometry.boundary import segment_distance
from pinn_engine.io.pipeline import load_boundary
from pinn_engine.job.cover import (
    SKEW_LIMIT,
    check_blocks_cover,
    check_blocks_skewness,
    check_body_cover,
)
from pinn_engine.multiblock import mesh
from pinn_engine.multiblock.walls import parse_walls
from pinn_engine.routes.cli import main
from pinn_engine.settings import make_settings

L_RING = np.array([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]], dtype=float)
FIX = "draw the block edges"


def _block(x0: float, x1: float, y0: float, y1: float, n: int = 5) -> np.ndarray:
    x, y = np.meshgrid(np.linspace(x0, x1, n), np.linspace(y0, y1, n))
    return np.stack([x, y], axis=-1)


def _l_blocks() -> list[np.ndarray]:
    """The L of ``L_RING`` as three blocks."""
    return [_block(0, 1, 0, 1), _block(1, 2, 0, 1), _block(0, 1, 1, 2)]


def test_three_blocks_that_tile_the_l_cover_it():
    figures = check_blocks_cover(_l_blocks(), [L_RING], "l", FIX)
    assert figures["area"] == pytest.approx(3.0)
    assert figures["cells_area"] == pytest.approx(3.0)
    assert figures["sharp_corners"] == 6


def test_a_reflex_corner_moved_off_the_grid_is_refused_with_the_fix():
    blocks = _l_blocks()
    for b, (j, i) in ((0, (-1, -1)), (1, (-1, 0)), (2, (0, -1))):
        blocks[b][j, i] = (0.98, 1.0)  # the reflex corner (1, 1), moved as one node
    with pytest.raises(InputError, match=r"^l: .*sharp corner at \(1, 1\) is no grid node; draw"):
        check_blocks_cover(blocks, [L_RING], "l", FIX)


def test_blocks_that_overlap_are_refused_though_no_cell_folds():
    blocks = _l_blocks()
    blocks[2] = _block(0, 1, 0.5, 2)  # the upper arm reaches down into the corner block
    with pytest.raises(InputError, match="cover 0.17 of its area more than the boundary"):
        check_blocks_cover(blocks, [L_RING], "l", FIX)


def test_a_hole_must_be_a_grid_side():
    outer = np.array([[-2, -2], [2, -2], [2, 2], [-2, 2]], dtype=float)
    hole = np.array([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])
    with pytest.raises(InputError, match="sharp corner at \\(-0.5, -0.5\\)"):
        check_blocks_cover([_block(-2, 2, -2, 2)], [outer, hole], "box", FIX)


def test_a_body_wall_off_the_file_or_a_trailing_edge_missed_is_refused():
    t = np.linspace(0, 2 * np.pi, 65)
    surface = np.c_[np.cos(t), np.sin(t)]
    edge = surface[:1]
    r = np.linspace(1, 3, 4)[:, None, None]
    grid = r * np.stack([np.cos(t), np.sin(t)], axis=-1)[None]
    figures = check_body_cover(grid, surface, edge, 2.0, slice(None), "c", "fix")
    assert figures["wall_deviation"] < 1e-12 and figures["sharp_corners"] == 1
    moved = grid.copy()
    moved[0, 10] *= 1.01  # 1 % of the radius: 0.5 % of the chord
    with pytest.raises(InputError, match="wall leaves the body drawn by 0.005 chord"):
        check_body_cover(moved, surface, edge, 2.0, slice(None), "c", "fix")
    with pytest.raises(InputError, match="trailing-edge corner at \\(1.1, 0\\) is no wall"):
        check_body_cover(grid, surface, np.array([[1.1, 0.0]]), 2.0, slice(None), "c", "fix")


def test_the_step_with_automatic_blocking_and_wall_spacing_keeps_its_lip():
    """The lip (0, 1) of example_data/step.vtp is a reflex corner: it stays a node when the
    wall spacing stretches the lines that run through it."""
    geometry = job.blocks_from_files(
        "example_data/step.vtp", ["auto"], patches=["-2,1.5=inlet", "6,1.5=outlet"],
        spacing=["boundary=0.01"],
    )  # fmt: skip
    outcome = job.run(make_settings("elliptic"), geometry)
    nodes = np.vstack([g.reshape(-1, 2) for g in outcome.grids])
    assert np.linalg.norm(nodes - (0.0, 1.0), axis=1).min() == 0.0
    assert outcome.report["domain"]["cells_area"] == pytest.approx(14.0, rel=1e-12)
    assert outcome.report["quality"]["folded_cells"] == 0


def _thin_row_blocks(crowd: bool) -> list[np.ndarray]:
    """Two unit squares side by side, 9 x 9 nodes each, a first row 0.01 off the floor;
    with ``crowd`` the floor's nodes of the right block crowd against the shared side
    (a wall row stretched alone) while its first row keeps equal steps."""
    y = np.r_[0.0, 0.01, np.linspace(0.01, 1.0, 8)[1:]]
    blocks = []
    for x0 in (0.0, 1.0):
        x, yy = np.meshgrid(np.linspace(x0, x0 + 1.0, 9), y)
        blocks.append(np.stack([x, yy], axis=-1))
    if crowd:
        blocks[1][0, 1:-1, 0] = 1.0 + np.linspace(0, 1, 9)[1:-1] ** 3
    return blocks


def test_a_multi_block_grid_that_checkmesh_finds_skewed_is_refused_with_the_fix():
    """A thin row beside a crowded wall row squeezes cells to near 180 degrees: checkMesh's
    skewness exceeds its limit there (the same figure checkMesh prints, 89.08 on the
    upright tee this rule was written for), so the grid is refused, not written."""
    figures = check_blocks_skewness(_thin_row_blocks(False), "two", FIX)
    assert figures["max_skewness"] < 1e-9
    with pytest.raises(InputError, match=f"skewed .* \\(checkMesh's limit {SKEW_LIMIT:g}\\)"):
        check_blocks_skewness(_thin_row_blocks(True), "two", FIX)


def test_a_wall_spacing_beyond_a_reflex_corner_runs_through_the_block(tmp_path):
    """The upright tee's automatic blocking leaves its branch's corner (3.5, 1) inside the
    side of the block beneath; with a wall spacing every row of that block is cut there and
    stretched alike, so the grid stays rectangular (it had cells of 179.5 degrees)."""
    ring = [(0, 0), (6, 0), (6, 1), (3.5, 1), (3.5, 3), (2.5, 3), (2.5, 1), (0, 1)]
    path = tmp_path / "tee.csv"
    path.write_text("x,y\n" + "".join(f"{x},{y}\n" for x, y in ring))
    geometry = job.blocks_from_files(path, ["auto"], spacing=["boundary=0.01"])
    outcome = job.run(make_settings("elliptic", cell_size=0.125), geometry)
    assert outcome.report["quality"]["worst_max_angle"] < 90.01
    assert outcome.report["checkmesh"]["max_skewness"] < 0.01
    firsts = [g[1, :, 1] - g[0, :, 1] for g in outcome.grids if g[0, 0, 1] == 0.0]
    assert np.allclose(np.concatenate(firsts), 0.01, rtol=0.1)


def test_a_round_trailing_edge_gets_a_fold_free_c_grid(tmp_path, capsys):
    """A circular root section has no trailing-edge corner: its C-grid's cut leaves the
    point of largest x, the grid smoothed round the cut as round a base of the height that
    faces downstream; written with no fold, the cut's node on the wall."""
    t = np.linspace(0, 2 * np.pi, 81)
    path = tmp_path / "root.dat"
    path.write_text("root\n" + "".join(f"{x:.8f} {y:.8f}\n" for x, y in zip(np.cos(t), np.sin(t))))
    base = [str(path), "--size", "300", "80", "--spacing", "bottom=1e-5", "--method", "elliptic"]
    base += ["-q"]
    for topology in "co":
        out = tmp_path / f"{topology}.vts"
        assert main([*base, "--topology", topology, "-o", str(out), "--fail-on-folded"]) == 0
        grid = pv.read(out)
        assert grid["Folded"].sum() == 0 and grid["MaxIncludedAngle"].max() < 180
    assert capsys.readouterr().err == ""


def _bump_file(tmp_path) -> str:
    """A four-sided domain whose bottom side climbs a trapezoidal bump: four vertices inside
    the side turning 45 degrees, none at a uniform node."""
    ring = [(0, 0), (1.03, 0), (1.33, 0.3), (1.73, 0.3), (2.03, 0), (3, 0), (3, 1.5), (0, 1.5)]
    path = tmp_path / "bump.csv"
    path.write_text("x,y\n" + "".join(f"{x},{y}\n" for x, y in ring))
    return str(path)


@pytest.mark.parametrize(
    "options",
    [
        ["--method", "tfi"],
        ["--method", "elliptic"],
        [],  # the default
        ["--method", "elliptic", "--spacing", "left=0.01"],
        ["--spacing", "top=0.02"],
    ],
)
def test_a_sharp_vertex_inside_a_side_is_a_node_of_the_four_sided_grid(tmp_path, options):
    out = tmp_path / "g.vts"
    args = [_bump_file(tmp_path), "--size", "33", "17", "-o", str(out), "-q", *options]
    assert main(args) == 0
    nodes = np.asarray(pv.read(out).points)[:, :2]
    for vertex in [(1.03, 0), (1.33, 0.3), (1.73, 0.3), (2.03, 0)]:
        assert np.linalg.norm(nodes - vertex, axis=1).min() < 1e-12


def test_more_sharp_vertices_than_nodes_along_a_side_is_refused_with_the_size(tmp_path, capsys):
    out = tmp_path / "g.vts"
    assert main([_bump_file(tmp_path), "--size", "5", "5", "--method", "tfi", "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and not out.exists()
    assert "sharp corner at (1.03, 0) is no grid node; a larger --size" in err


def _bumped_l(tmp_path) -> job.BlocksGeometry:
    """``helpers.bumped_l`` in three blocks with a wall spacing of 0.01."""
    ring, edges = bumped_l()
    walls = parse_walls(["boundary=0.01"])
    return job.BlocksGeometry([ring], edges, ["a", "b"], str(tmp_path / "l.csv"), walls=walls)


def test_first_edges_off_the_spacing_asked_are_refused_with_the_fix(tmp_path, monkeypatch):
    """Without the last slide of the lines leaving the wall, the bumped L's first edges
    beside its bump are 0.0088 to 0.011 for 0.01 asked (lines of 0.125 cells cut across
    the bump): beyond SPEC 7's 10 %, so the grid is refused in one line."""
    monkeypatch.setattr(mesh, "fitted_first_edges", lambda points, *_: points)
    with pytest.raises(InputError, match=r"first edges on boundary are .*, 0.01 asked .*cell"):
        job.run(make_settings("elliptic", cell_size=0.125), _bumped_l(tmp_path))


def test_lines_leaving_a_wall_keep_its_first_edge_beside_a_bump(tmp_path):
    """The same L is written, its first edges 0.01 within 0.2 % (the stretching fits them
    to 0.1 %), its worst cell no worse than before the slide (106.97 degrees)."""
    outcome = job.run(make_settings("elliptic", cell_size=0.125), _bumped_l(tmp_path))
    edge = outcome.report["walls"]["boundary"]["first_edge"]
    assert 0.998 * 0.01 < edge["min"] <= edge["max"] < 1.002 * 0.01
    assert outcome.report["quality"]["worst_max_angle"] < 107.0


def test_a_curved_wall_with_a_spacing_keeps_its_nodes_on_the_drawn_polyline(tmp_path):
    """A quarter annulus drawn by 33 points a wall, meshed as blocks with a wall spacing:
    the lines along the curved walls are stretched as splines of their nodes, which cut the
    drawn chords; the nodes go back onto the polyline, and the cells cover the domain."""
    t = np.linspace(0, np.pi / 2, 33)
    ring = np.vstack([np.c_[2 * np.cos(t), 2 * np.sin(t)], np.c_[np.cos(t), np.sin(t)][::-1]])
    path = tmp_path / "bend.csv"
    np.savetxt(path, ring, delimiter=",")
    geometry = job.blocks_from_files(str(path), ["auto"], spacing=["boundary=0.01"])
    outcome = job.run(make_settings("elliptic", cell_size=0.125), geometry)  # not refused
    grid = outcome.grids[0]
    walls = np.vstack([grid[0], grid[-1]]) if grid.shape[0] < grid.shape[1] else grid[:, [0, -1]]
    assert segment_distance(walls.reshape(-1, 2), ring).max() < 1e-12
    assert outcome.report["quality"]["folded_cells"] == 0


def test_a_drawn_line_the_default_cannot_follow_is_refused_in_one_line(tmp_path, capsys):
    """A line grazing the bump's flank at 81 x 41, which the default's grid lines cannot
    reach within 2e-3 of the diagonal without folding (5e-3): no grid is written, and the
    one line names the line, how far it was missed and the fixes."""
    shape = EXAMPLES / "hard" / "bump.vtp"
    boundary = load_boundary(shape)  # from 0.35 of the bottom side to 0.65 of the top
    ends = [boundary.side(s).at(np.array([t]))[0] for s, t in (("bottom", 0.35), ("top", 0.65))]
    unit = ends[0] + np.linspace(0.0, 1.0, 21)[:, None] * (ends[1] - ends[0])
    line = boundary.plane.lift(boundary.frame.to_user(unit))
    aux = tmp_path / "line.vtp"
    pv.lines_from_points(line).save(aux)
    out = tmp_path / "g.vts"
    assert main([str(shape), "--aux", str(aux), "--size", "81", "41", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "only to" in err and "--method elliptic" in err
    assert not out.exists()
