"""Spacing and orthogonality on multi-block patches (SPEC 10 with SPEC 7):
the cylinder of diameter 1 in its channel with a first cell of 0.005 at its wall, within
10 %, grid lines within 2 degrees of its normal, no folds, shared nodes identical."""

from __future__ import annotations

import json

import numpy as np
import pytest
import pyvista as pv
from helpers import EXAMPLES, refused
from multiblock_checks import (
    block_sides,
    first_edges,
    interface_kinks,
    patch_walls,
    wall_angles,
    write_polylines,
)

from pinn_engine import job
from pinn_engine.kinds.blocks.run import run_blocks
from pinn_engine.multiblock.walls import first_edges_refusal
from pinn_engine.routes.cli import main
from pinn_engine.settings import make_settings

BOUNDARY = str(EXAMPLES / "cylinder_channel.vtp")
EDGES = str(EXAMPLES / "cylinder_channel_blocks.vtp")
CYLINDER = ["--patch=0.5,0=cylinder:wall", "--patch=0,0.5=cylinder"]
CYLINDER += ["--patch=-0.5,0=cylinder", "--patch=0,-0.5=cylinder"]
H = 0.005  # the first cell at the cylinder's wall
WALL = ["--spacing", f"cylinder={H}", "--orthogonal", "cylinder"]


def _mesh(tmp_path, *more: str) -> tuple[pv.MultiBlock, dict]:
    """The cylinder at cell size 0.1 with the four cylinder pieces named, and its report."""
    out, report = tmp_path / "grid.vtm", tmp_path / "report.json"
    args = [BOUNDARY, "--blocks", EDGES, "--cell-size", "0.1", *CYLINDER, *more]
    assert main([*args, "-o", str(out), "--report", str(report), "--quiet"]) == 0
    return pv.read(out), json.loads(report.read_text())


@pytest.fixture(scope="module")
def cylinder(tmp_path_factory):
    return _mesh(tmp_path_factory.mktemp("spacing"), *WALL)


def test_cylinder_first_cell_and_normal_lines(cylinder):
    """A first cell of 0.005 within 10 % and grid lines within 2 degrees of the
    normal at the cylinder; no folds; shared nodes are the same point in every block; lines
    still cross interfaces smoothly; the report says the same."""
    grid, report = cylinder
    walls = patch_walls(grid, "cylinder")
    assert len(walls) == 4
    edges, angles = first_edges(walls), wall_angles(walls)
    assert np.abs(edges / H - 1).max() <= 0.1
    assert angles.max() <= 2.0
    assert sum(int(b.cell_data["Folded"].sum()) for b in grid) == 0
    nodes = np.unique(np.vstack([s for b in grid for s, _ in block_sides(b)]), axis=0)
    assert len(np.unique(np.round(nodes / 1e-9), axis=0)) == len(nodes)
    kinks = interface_kinks(grid)
    assert kinks.mean() <= 2.0 and kinks.max() <= 15.0
    wall = report["walls"]["cylinder"]
    assert wall["first_edge"]["min"] == pytest.approx(edges.min())
    assert wall["first_edge"]["max"] == pytest.approx(edges.max())
    assert wall["max_angle_deviation"] == pytest.approx(angles.max(), abs=1e-9)


def test_spacing_moves_only_the_lines_leaving_the_patch(tmp_path, cylinder):
    """The eight blocks away from the cylinder are node for node the grid without spacing;
    without it the first cell at the wall is the Winslow grid's, about 0.04 (8 times H)."""
    plain, _ = _mesh(tmp_path)
    spaced, _ = cylinder
    for k in range(8):
        assert np.array_equal(plain[k].points, spaced[k].points)
    assert first_edges(patch_walls(plain, "cylinder")).min() > 5 * H


def test_orthogonal_turns_tfi_lines_onto_the_normal(tmp_path):
    """TFI's straight lines leave the cylinder up to 7 degrees off its normal; with
    --orthogonal they are within 2, the first cell still H."""
    leaning, _ = _mesh(tmp_path, "--method", "tfi", "--spacing", f"cylinder={H}")
    assert wall_angles(patch_walls(leaning, "cylinder")).max() > 5.0
    normal, _ = _mesh(tmp_path, "--method", "tfi", *WALL)
    walls = patch_walls(normal, "cylinder")
    assert wall_angles(walls).max() <= 2.0
    assert np.abs(first_edges(walls) / H - 1).max() <= 0.1
    assert sum(int(b.cell_data["Folded"].sum()) for b in normal) == 0


@pytest.mark.parametrize(
    "flags, message",
    [
        (["--spacing", "cylindr=0.005"], "spacing cylindr=: no patch named 'cylindr'"),
        (["--orthogonal", "cylinder,wall"], "orthogonal wall: no patch named 'wall'"),
        (["--spacing", "cylinder"], "expected NAME=H"),
        (["--spacing", "cylinder=-1"], "expected NAME=H"),
        (["--spacing", "cylinder=0.3"], "shorter than half of every grid line"),
    ],
)
def test_bad_walls_are_one_line(tmp_path, capsys, flags, message):
    """An unknown patch name, a bad item, a first edge too long: one line, exit 2, no file."""
    out = tmp_path / "grid.vtm"
    args = [BOUNDARY, "--blocks", EDGES, "--cell-size", "0.1", *CYLINDER, *flags]
    assert main([*args, "-o", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err
    assert not out.exists()


def test_square_hole_corner_blocks_are_stretched_too(tmp_path):
    """A square hole whose sides run on to the channel's walls (8 blocks, a blockMesh
    user's blocking): the corner blocks share a stretched line with the wall blocks beside
    them and are stretched along it, so no cell shears next to the hole's corners (without
    that, cells of 176 degrees: checkMesh's non-orthogonality 86)."""
    ring = [(0, 0), (3, 0), (3, 1), (0, 1)]
    hole = [(0.9, 0.55), (0.9, 0.2), (0.5, 0.2), (0.5, 0.55)]
    edges = [[(x, 0.0), (x, 0.2)] for x in (0.5, 0.9)] + [[(x, 0.55), (x, 1.0)] for x in (0.5, 0.9)]
    edges += [[(0.0, y), (0.5, y)] for y in (0.2, 0.55)] + [
        [(0.9, y), (3.0, y)] for y in (0.2, 0.55)
    ]
    boundary = write_polylines(tmp_path / "square.vtp", [ring, hole], closed=True)
    blocks = write_polylines(tmp_path / "square_blocks.vtp", edges)
    out, h = tmp_path / "grid.vtm", 0.004
    args = [boundary, "--blocks", blocks, "--cell-size", "0.04", "--method", "elliptic"]
    args += ["--patch", "hole1=block:wall", "--spacing", f"block={h}", "--orthogonal", "block"]
    assert main([*args, "-o", str(out), "--quiet"]) == 0
    grid = pv.read(out)
    walls = patch_walls(grid, "block")
    assert len(walls) == 4
    assert np.abs(first_edges(walls) / h - 1).max() <= 0.1
    assert wall_angles(walls).max() <= 2.0
    assert max(float(b.cell_data["MaxIncludedAngle"].max()) for b in grid) < 100.0
    assert sum(int(b.cell_data["Folded"].sum()) for b in grid) == 0


def test_orthogonal_folds_no_cell_beside_leaning_corner_lines(tmp_path, capsys):
    """An ellipse off-centre in a channel, its O-ring's corners joined to the channel's (8
    blocks): the O-ring's radial lines leave the wall about 50 degrees off its normal,
    beside wall nodes five times closer together than the first edge. Turning them fully
    folded 9 cells; the turn is eased beside them until none folds, and the lines away
    from the corners still leave along the normal."""
    a, b, centre = 0.3, 0.15, np.array([0.3, 0.05])
    t = 2 * np.pi * np.arange(80) / 80
    ring = [(-1.0, -0.7), (2.5, -0.7), (2.5, 0.6), (-1.0, 0.6)]
    hole = centre + np.column_stack([a * np.cos(t), b * np.sin(t)])
    box = [(0.8, -0.35), (0.8, 0.45), (-0.2, 0.45), (-0.2, -0.35)]
    edges = [[box[k - 1], box[k]] for k in range(4)] + [
        [p, q] for p, q in zip(box, ring[1:] + ring[:1])
    ]
    for corner in box:
        d = np.arctan2((corner[1] - centre[1]) / b, (corner[0] - centre[0]) / a)
        edges.append([centre + (a * np.cos(d), b * np.sin(d)), corner])
    boundary = write_polylines(tmp_path / "ellipse.vtp", [ring, hole], closed=True)
    blocks = write_polylines(tmp_path / "ellipse_blocks.vtp", edges)
    geometry = job.blocks_from_files(
        boundary, [blocks], patches=["hole1=body:wall"], orthogonal=["body"]
    )
    # the kind's own grid: the blocking's lines leaning 50 degrees leave cells that
    # checkMesh finds skewed (6.87, the same with or without --orthogonal), so no route
    # writes it (below)
    grid = run_blocks(make_settings("elliptic", cell_size=0.1), geometry).data
    grid = pv.wrap(grid)
    assert sum(int(b.cell_data["Folded"].sum()) for b in grid) == 0
    args = [boundary, "--blocks", blocks, "--cell-size", "0.1", "--method", "elliptic"]
    args += ["--patch", "hole1=body:wall", "--orthogonal", "body"]
    out = tmp_path / "grid.vtm"
    assert "skewed 6.87" in refused(capsys, [*args, "-o", str(out)], out)
    for side, inside in patch_walls(grid, "body"):
        angles = wall_angles([(side, inside)])
        assert angles[len(angles) // 4 : -len(angles) // 4].max() <= 2.0


def test_a_block_with_two_wall_sides_keeps_both_stretchings(tmp_path):
    """An L-shaped duct of three blocks, every boundary piece one spaced wall: the corner
    block's rows leave one wall and its columns the other; both are stretched (the second
    once stretched from the nodes the first left: before, one undid the other, first
    edges up to 44 H)."""
    ring = [(-2, -2), (1, -2), (1, -1), (-1, -1), (-1, 1), (-2, 1)]
    edges = [[(-1.0, -1.0), (-2.0, -1.0)], [(-1.0, -1.0), (-1.0, -2.0)]]
    boundary = write_polylines(tmp_path / "duct.vtp", [ring], closed=True)
    blocks = write_polylines(tmp_path / "duct_blocks.vtp", edges)
    out, h = tmp_path / "grid.vtm", 0.01
    args = [boundary, "--blocks", blocks, "--cell-size", "0.1", "--method", "elliptic"]
    args += ["--patch", "boundary=duct:wall", "--spacing", f"duct={h}", "--orthogonal", "duct"]
    assert main([*args, "-o", str(out), "--quiet"]) == 0
    grid = pv.read(out)
    walls = patch_walls(grid, "duct")
    assert len(walls) == 8
    assert np.abs(first_edges(walls) / h - 1).max() <= 0.1
    assert wall_angles(walls).max() <= 2.0
    assert max(float(b.cell_data["MaxIncludedAngle"].max()) for b in grid) < 100.0


def test_walls_means_the_wall_patches_else_the_unnamed_boundary():
    """``walls`` (no patch so named): the patches of type wall, else the boundary left with
    its default names; a name given on its own keeps its spacing; nothing to mean is one
    line naming the fix."""
    from pinn_engine.errors import InputError
    from pinn_engine.multiblock.walls import parse_walls, with_walls

    asked = parse_walls(["walls=0.01", "hole1=0.002"], ["walls"])
    typed = [("inlet", "inflow"), ("top", "wall"), ("floor", "wall"), None, ("hole1", "patch")]
    meant = with_walls(asked, typed)
    assert meant.spacing == {"hole1": 0.002, "floor": 0.01, "top": 0.01}
    assert meant.orthogonal == ("floor", "top")
    untyped = [("inlet", "inflow"), ("boundary", "patch"), ("hole1", "patch"), None]
    meant = with_walls(asked, untyped)
    assert meant.spacing == {"hole1": 0.002, "boundary": 0.01}
    assert meant.orthogonal == ("boundary", "hole1")
    named = [("walls", "patch"), ("inlet", "inflow")]  # a patch named walls is itself
    assert with_walls(asked, named) == asked
    with pytest.raises(InputError, match=r"walls: no patch of type wall .* inlet, outlet \("):
        with_walls(asked, [("inlet", "inflow"), ("outlet", "outflow")])


def test_walls_on_a_step_drawn_without_patches_is_its_whole_boundary(tmp_path):
    """``example_data/step.vtp --blocks auto --spacing walls=0.01``: the grid of
    ``--spacing boundary=0.01``, every corner of the step a node."""
    grids = []
    for name in ("walls", "boundary"):
        out = tmp_path / f"{name}.vtm"
        argv = [str(EXAMPLES / "step.vtp"), "--blocks", "auto", "--spacing", f"{name}=0.01"]
        assert main([*argv, "-o", str(out), "--quiet"]) == 0
        grids.append(np.vstack([b.points for b in pv.read(out)]))
    np.testing.assert_array_equal(*grids)
    corners = pv.read(EXAMPLES / "step.vtp").points
    assert max(np.linalg.norm(grids[0] - c, axis=1).min() for c in corners) == 0.0


def test_lines_asked_at_both_ends_get_the_same_nodes_whichever_way_they_run():
    """Three parallel rows of a block, asked 0.01 at their left ends and 0.05 at their right
    ends, the middle one listed from its right end (a line's ids may run either way): all
    three get the same nodes (before, the stretching they shared was steeper at one end
    and the middle row got it mirrored: a wall row of the Y-branch at +-35 degrees sheared
    its cells to 179 degrees)."""
    from pinn_engine.multiblock.spacing import respace

    n = 11
    x = np.linspace(0.0, 1.0, n)
    points = np.vstack([np.column_stack([x, np.full(n, y)]) for y in (0.0, 1.0, 2.0)])
    rows = [tuple(range(k * n, (k + 1) * n)) for k in range(3)]
    asked = {rows[0]: [0.01, 0.05, "spacing"], rows[1][::-1]: [0.05, 0.01, "spacing"]}
    asked[rows[2]] = [0.01, 0.05, "spacing"]
    out = respace(points, asked)
    along = [out[list(row), 0] for row in rows]
    np.testing.assert_allclose(along[1], along[0], atol=1e-12)
    np.testing.assert_allclose(along[2], along[0], atol=1e-12)
    assert abs(along[0][1] - 0.01) < 1e-3 and abs(along[0][-1] - along[0][-2] - 0.05) < 5e-3


def test_a_block_corner_inside_a_spaced_line_stays_where_the_solve_put_it():
    """A channel cut in two, its right half cut again at 0.3 (a T-junction on the left
    block's side), every wall spaced 0.002: the left block's side is cut at the junction
    and each part stretched on its own, so the junction, a corner of the blocks across,
    stays where the solve put it and no cell folds (before, the whole side was stretched
    past it, moving the junction from 0.3 to 0.05, and the right blocks' sides stretched
    again from there; the Y-branch at +-35 degrees folded a cell so)."""
    from pinn_engine.multiblock.mesh import mesh_blocks
    from pinn_engine.multiblock.walls import parse_walls

    ring = np.array([(0, 0), (2, 0), (2, 1), (0, 1)], dtype=float)
    edges = [np.array([(1.0, 0.0), (1.0, 1.0)]), np.array([(1.0, 0.3), (2.0, 0.3)])]
    names = ["cut", "tee"]
    settings = make_settings("elliptic", cell_size=0.1)
    plain = mesh_blocks([ring], edges, names, settings)
    walls = parse_walls(["boundary=0.002"], [])
    spaced = mesh_blocks([ring], edges, names, settings, walls=walls)
    left = next(k for k, g in enumerate(plain.grids) if g[:, 0, 0].max() < 1e-9)
    side = [g[:, -1] for g in (plain.grids[left], spaced.grids[left])]
    junction = int(np.argmin(np.abs(side[0][:, 1] - 0.3)))
    np.testing.assert_allclose(side[1][junction], side[0][junction], atol=1e-12)
    assert spaced.report["quality"]["folded_cells"] == 0


def test_a_gradings_first_edges_off_h_are_refused_as_a_patchs():
    """A grading along a chain (``--spacing X,Y=H``) is held to SPEC 7 as a spaced patch is:
    its first edges off H by more than 10 % name it in the refusal."""
    figures = {"first_edge": {"min": 1e-3, "median": 1.5e-3, "max": 2e-3}, "spacing": 1e-3}
    far = figures | {"first_edge_off": {"share": 1.0, "at": [5.0, 1.0]}}
    near = figures | {"first_edge_off": {"share": 0.05, "at": [5.0, 1.0]}}
    label = "the side of spacing 3,1=0.001"
    assert first_edges_refusal({"walls": {}, "gradings": {label: near}}) is None
    refusal = first_edges_refusal({"walls": {}, "gradings": {label: far}})
    assert refusal.startswith(f"its first edges on {label} are 0.001 to 0.002")
