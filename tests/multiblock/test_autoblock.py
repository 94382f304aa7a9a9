"""Automatic blocking (SPEC 13): ``--blocks auto`` and its routes, the saved edges' round
trip, the four-sided domain and the refusal. Small grids: each run well under a second."""

from __future__ import annotations

import sys

import numpy as np
import pytest
import pyvista as pv
from helpers import ROOT, bumped_l, refused, run_blocks, square_ring
from vtkmodules.vtkIOXML import vtkXMLMultiBlockDataReader, vtkXMLPolyDataReader

from pinn_engine.errors import InputError
from pinn_engine.io.export.edges import edges_of
from pinn_engine.multiblock import mesh
from pinn_engine.multiblock.autoblock import propose_edges
from pinn_engine.multiblock.autoblock.score import Rejected, score
from pinn_engine.multiblock.autoblock.search import best_meshed, ranked
from pinn_engine.multiblock.mesh import mesh_blocks
from pinn_engine.multiblock.walls import parse_walls
from pinn_engine.routes.cli import main
from pinn_engine.routes.multiblock_algorithm import PinnMultiBlockAlgorithm
from pinn_engine.settings import AUTO_BLOCKS, make_settings

DATA = ROOT / "example_data"
sys.path.insert(0, str(DATA))  # make_multiblock: the examples' rings and hand-drawn edges
CELL_SIZE = 0.25  # the L of arm width 1: 4 cells across an arm
ROUNDING = 1e-6  # degrees: the same blocking drawn in another order solves to within this
FAST = ("--method", "elliptic", "--cell-size", str(CELL_SIZE), "--quiet")


def _polydata(path):
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(path))
    reader.Update()
    return reader.GetOutput()


def _vtm_points(path) -> list[np.ndarray]:
    reader = vtkXMLMultiBlockDataReader()
    reader.SetFileName(str(path))
    reader.Update()
    out = reader.GetOutput()
    return [np.array(out.GetBlock(k).GetPoints().GetData()) for k in range(out.GetNumberOfBlocks())]


def test_cli_auto_saves_edges_that_mesh_to_the_same_grid(tmp_path):
    auto, again, edges = tmp_path / "auto.vtm", tmp_path / "again.vtm", tmp_path / "edges.vtp"
    boundary = str(DATA / "lshape.vtp")
    assert (
        main([boundary, "--blocks", "auto", "--save-blocks", str(edges), *FAST, "-o", str(auto)])
        == 0
    )
    assert main([boundary, "--blocks", str(edges), *FAST, "-o", str(again)]) == 0
    saved = edges_of(_polydata(edges))
    assert len(saved) == 1 and np.allclose(saved[0][:, :2], [[1, 1], [0, 1]])  # the L's cut
    first, second = _vtm_points(auto), _vtm_points(again)
    assert len(first) == 2 and all(np.array_equal(a, b) for a, b in zip(first, second))


def test_four_sided_domain_stays_one_block(tmp_path):
    assert propose_edges([square_ring(4)]) == []
    path = tmp_path / "square.csv"
    np.savetxt(path, square_ring(4), delimiter=",")
    out = run_blocks(make_settings("elliptic", cell_size=0.25), path, [AUTO_BLOCKS])
    assert out.edges == [] and out.report["blocks"] == 1
    assert out.report["blocking"]["mode"] == "automatic"
    assert out.report["blocking"]["edges"] == 0


def test_no_blocking_is_a_one_line_error(tmp_path, capsys):
    a = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    path = tmp_path / "disc.csv"
    np.savetxt(path, np.column_stack([np.cos(a), np.sin(a)]), delimiter=",")
    out = tmp_path / "disc.vtm"
    err = refused(capsys, [str(path), "--blocks", "auto", *FAST, "-o", str(out)], out)
    assert "automatic blocking found no four-cornered blocks (the face at (0, 0) has 0" in err
    assert err.endswith("draw the block edges and give them with --blocks EDGES")
    err = refused(
        capsys, [str(path), "--save-blocks", str(tmp_path / "e.vtp"), "-o", str(out)], out
    )
    assert "--save-blocks writes the block edges of --blocks" in err


def test_a_refusal_names_why_the_layouts_tried_fail_in_the_route_s_words():
    """A disc with a hole near its rim: the layouts tried leave a corner of the hole's box
    with no edge, and the refusal says so, not what the hole's ring alone would lack."""
    t = np.linspace(0, 2 * np.pi, 48, endpoint=False)
    rim, hole = [
        np.column_stack([c + r * np.cos(t), r * np.sin(t)]) for c, r in ((0, 2), (1.45, 0.4))
    ]
    with pytest.raises(InputError) as caught:
        propose_edges([rim, hole], cell_size=0.25)
    text = str(caught.value)
    assert "the reflex corner at (1.994, -0.1536) gets no edge, in 144 of the 256 layouts" in text
    assert "a hole or a loop" not in text
    assert str(caught.value.for_route("pyvista")).endswith(
        "draw the block edges and give them as blocks="
    )


def test_a_refusal_for_folds_names_the_nearest_layout_s_first_fold():
    """Every layout shortlisted folds: the refusal names the one with the fewest folds; one
    that folds only at the run's finer size gives way to the next best."""

    def fold(edges):
        raise Rejected(f"folds {len(edges)} cells at (1, 2)", len(edges))

    def fold_one(edges):
        return fold(edges) if len(edges) == 1 else 0.0

    layouts = [(1.0, [np.zeros((2, 2))] * n) for n in (3, 1, 2)]
    with pytest.raises(Rejected, match=r"^of the 3 layouts meshed, the nearest folds 1 cells"):
        best_meshed(layouts, fold)
    assert len(best_meshed(layouts, len, fold_one)) == 2


def test_mirror_layouts_that_tie_but_for_rounding_rank_in_the_order_found():
    """Two mirror layouts whose costs, and then scores, differ by rounding alone (which
    differs between machines) rank in the order the search found them, whichever costs or
    scores a hair less, and the first found wins the meshing."""
    left = [np.array([[0.0, 0.0], [0.0, 1.0]])]
    right = [np.array([[1.0, 0.0], [1.0, 1.0]])]
    for a, b in ((0.0, 1e-13), (1e-13, 0.0)):
        layouts = [(5 + a, left), (5 + b, right)]
        assert ranked(layouts)[0][1] is left and ranked(layouts[::-1])[0][1] is right
        scores = {id(left): 1 + a, id(right): 1 + b}
        assert best_meshed(ranked(layouts), lambda edges, s=scores: s[id(edges)]) is left


def test_a_layout_whose_first_edges_miss_the_spacing_is_out(monkeypatch):
    """A layout is judged as the run writes it: one whose first edges miss the wall
    spacing beyond SPEC 7's 10 % (the bumped L's, without the last slide of the lines
    leaving the wall) is out, as the run would refuse it."""
    monkeypatch.setattr(mesh, "fitted_first_edges", lambda points, *_: points)
    ring, edges = bumped_l()
    walls = parse_walls(["boundary=0.01"])
    with pytest.raises(Rejected, match=r"^misses the spacing asked: its first edges on"):
        score([ring], edges, 0.125, walls)


def _figures(rings, edges, h: float) -> dict:
    result = mesh_blocks(rings, edges, ["e"] * len(edges), make_settings("elliptic", cell_size=h))
    report = result.report
    return {
        "blocks": report["blocks"],
        "mean": report["quality"]["mean_max_angle"],
        "worst": report["quality"]["worst_max_angle"],
        "folds": report["quality"]["folded_cells"],
        "kink": report["interface_kink"]["mean"],
        "kink_max": report["interface_kink"]["max"],
    }


@pytest.mark.parametrize(
    ("example", "h"),
    [
        ("step", 0.2),
        ("tee", 0.2),
        ("ybranch", 0.1),
        pytest.param("cylinder_channel", 0.25, marks=pytest.mark.slow),
    ],
)
def test_proposals_hold_issue_35s_bounds_beside_the_hand_blocking(example, h):
    """No fold; mean and worst MaxIncludedAngle within 1.5 and 10 degrees of the hand-blocked
    elliptic grid (example_data's edges); interface kinks at most 3 mean and 20 max (or the
    hand blocking's, where a coarse Y's centre turns grid lines more); at most twice the
    hand blocking's blocks."""
    from make_multiblock import cylinder_channel, step, tee, ybranch

    rings, hand_edges = {
        "step": step, "tee": tee, "ybranch": ybranch, "cylinder_channel": cylinder_channel
    }[example]()  # fmt: skip
    auto = _figures(rings, propose_edges(rings), h)
    hand = _figures(rings, hand_edges, h)
    assert auto["folds"] == 0
    assert auto["mean"] <= hand["mean"] + 1.5 and auto["worst"] <= hand["worst"] + 10
    kink, kink_max = max(3.0, hand["kink"]), max(20.0, hand["kink_max"])
    assert auto["kink"] <= kink + ROUNDING and auto["kink_max"] <= kink_max + ROUNDING
    assert auto["blocks"] <= 2 * hand["blocks"]


def _rounded(ring: np.ndarray, radius: float, points: int = 6) -> np.ndarray:
    """``ring`` (counter-clockwise) with every concave vertex replaced by a quadratic arc
    from ``radius`` before it to ``radius`` after it (``points`` points)."""
    out = []
    for k, p in enumerate(ring):
        a, b = ring[k - 1], ring[(k + 1) % len(ring)]
        u, v = p - a, b - p
        if u[0] * v[1] - u[1] * v[0] >= 0:  # a left turn: convex
            out.append(p)
            continue
        s = p + radius * (a - p) / np.linalg.norm(a - p)
        e = p + radius * (b - p) / np.linalg.norm(b - p)
        out += [
            (1 - t) ** 2 * s + 2 * (1 - t) * t * p + t**2 * e for t in np.linspace(0, 1, points)
        ]
    return np.array(out)


def test_a_rounded_y_gets_its_three_block_centre():
    """A Y whose concave corners are drawn as arcs (each vertex turning under 9 degrees,
    none a reflex vertex alone): each arc emits as one corner, so the arms are cut at their
    mouths and the centre into three, no fold."""
    from make_multiblock import ybranch

    (ring,), _ = ybranch()  # counter-clockwise
    ring = _rounded(ring, 0.15)
    edges = propose_edges([ring])
    figures = _figures([ring], edges, 0.2)
    assert figures["blocks"] == 6 and figures["folds"] == 0


def test_algorithm_automatic_gives_blocks_and_the_edges_port():
    alg = PinnMultiBlockAlgorithm()
    alg.SetBlocking("automatic")
    alg.SetMethod("elliptic")
    alg.SetCellSize(CELL_SIZE)
    alg.SetInputDataObject(0, _polydata(DATA / "lshape.vtp"))
    alg.Update()
    assert alg.GetLastError() == ""
    assert alg.GetOutput().GetNumberOfBlocks() == 2
    assert alg.GetBlockEdges().GetNumberOfLines() == 1
    alg.AddInputDataObject(1, _polydata(DATA / "lshape_blocks.vtp"))
    alg.Update()
    assert "leave Block Edges empty" in alg.GetLastError()
    assert alg.GetBlockEdges().GetNumberOfLines() == 0


def test_pyvista_auto_matches_the_command_line(tmp_path):
    boundary = pv.read(DATA / "lshape.vtp")
    saved = tmp_path / "edges.vtp"
    blocks = boundary.pinn_mesh(
        blocks="auto", method="elliptic", cell_size=CELL_SIZE, save_blocks=saved
    )
    expected = run_blocks(
        make_settings("elliptic", cell_size=CELL_SIZE), DATA / "lshape.vtp", [AUTO_BLOCKS]
    )
    for grid, points in zip(blocks, expected.grids):
        assert np.array_equal(np.asarray(grid.points)[:, :2], points.reshape(-1, 2))
    again = boundary.pinn_mesh(blocks=pv.read(saved), method="elliptic", cell_size=CELL_SIZE)
    assert all(np.array_equal(a.points, b.points) for a, b in zip(blocks, again))
    with pytest.raises(InputError, match="draw the block edges and give them as blocks=$"):
        pv.Circle(radius=1.0, resolution=40).pinn_mesh(blocks="auto")


DIAMOND = 0.5 * np.sqrt(2.0) * np.array([[1, 0], [0, 1], [-1, 0], [0, -1]], dtype=float)
CHANNEL = np.array([[-3, -2], [6, -2], [6, 2], [-3, 2]], dtype=float)


def test_a_hole_s_sharp_corner_off_the_spokes_gets_a_spoke_along_its_bisector():
    """A square turned 45 degrees in a channel: the O-ring's spokes cross its sides, so each
    of its corners gets a spoke of its own, straight out along the bisector to the box
    (every ring block four-cornered); a round hole gets none."""
    from pinn_engine.multiblock.autoblock.orings import main_axes, o_ring

    ring = o_ring(DIAMOND[::-1], [CHANNEL], main_axes(CHANNEL))
    extra = ring.edges[8:]
    assert len(extra) == 4
    for edge in extra:
        corner, end = edge
        assert np.linalg.norm(DIAMOND - corner, axis=1).min() == 0.0
        direction = (end - corner) / np.linalg.norm(end - corner)
        assert np.allclose(direction, corner / np.linalg.norm(corner))
    a = np.linspace(0, 2 * np.pi, 48, endpoint=False)
    assert len(o_ring(np.c_[np.cos(a), -np.sin(a)], [CHANNEL], main_axes(CHANNEL)).edges) == 8


def _plate(degrees: float = 10.0) -> np.ndarray:
    """A plate 1 x 0.2 turned ``degrees`` (a thin body that its box does not fit)."""
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    plate = np.array([(-0.5, -0.1), (0.5, -0.1), (0.5, 0.1), (-0.5, 0.1)])
    return plate @ np.array([[c, s], [-s, c]])


def test_a_turned_plate_s_corner_spokes_take_the_box_corners_spokes_they_would_cross():
    """A plate at 10 degrees: the box corners' diagonal spokes meet its long sides short of
    two of its corners, whose bisector spokes would cross them (and were left out, so a
    ring block had a plate corner inside its side and the blocking was refused); the two
    are one spoke from the corner to the box corner, and every corner ends a spoke."""
    from pinn_engine.multiblock.autoblock.orings import main_axes, o_ring

    plate = _plate()
    ring = o_ring(plate, [CHANNEL], main_axes(CHANNEL))
    spokes = ring.edges[len(ring.edges) - 6 :]  # after the box's four sides
    starts = np.array([s[0] for s in spokes])
    for corner in plate:
        assert np.linalg.norm(starts - corner, axis=1).min() == 0.0
    assert sum(np.linalg.norm(ring.box - s[1], axis=1).min() == 0.0 for s in spokes) == 4


@pytest.mark.slow  # the search meshes the shortlisted layouts: about 5 s each
@pytest.mark.parametrize("body", ["plate", "diamond"])
def test_a_turned_body_in_a_channel_meshes_with_its_corners_as_nodes(tmp_path, body):
    """A plate at 10 degrees (it was refused: a block with a hole or a loop) and a square
    turned 45 degrees in a channel: every corner of the body is a node of the grid."""
    corners = _plate() if body == "plate" else DIAMOND
    path = tmp_path / f"{body}.vtp"
    lines = [np.r_[CHANNEL, CHANNEL[:1]], np.r_[corners, corners[:1]]]
    poly = pv.PolyData()
    poly.points = np.vstack([np.c_[r, np.zeros(len(r))] for r in lines])
    poly.lines = np.r_[5, 0, 1, 2, 3, 4, 5, 5, 6, 7, 8, 9]
    poly.save(path)
    out = tmp_path / "g.vtm"
    assert main([str(path), "--blocks", "auto", *FAST, "-o", str(out)]) == 0
    nodes = np.vstack(_vtm_points(out))[:, :2]
    for corner in corners:
        assert np.linalg.norm(nodes - corner, axis=1).min() < 1e-12


def _naca_0012(points: int = 41) -> np.ndarray:
    """A NACA 0012 of chord 1 with a sharp trailing edge, counter-clockwise from it."""
    x = 0.5 * (1 - np.cos(np.linspace(0, np.pi, points)))
    y = 0.6 * (0.2969 * np.sqrt(x) - 0.126 * x - 0.3516 * x**2 + 0.2843 * x**3 - 0.1036 * x**4)
    y[-1] = 0.0
    return np.vstack([np.column_stack([x, y])[::-1], np.column_stack([x, -y])[1:-1]])


@pytest.mark.slow  # the search meshes both rings' shortlisted layouts: about 10 s
def test_an_airfoil_in_a_channel_gets_c_shaped_ring_blocks_round_its_trailing_edge():
    """The trailing edge's spoke leaves 171.7 degrees on each side, no block corner: the two
    box corners' spokes beside it give way (the ring's C-shaped choice), the others end
    where they divide the airfoil's perimeter as their corners divide the box's, and the
    airfoil in a channel meshes (it was refused), its trailing edge a node."""
    from pinn_engine.multiblock.autoblock.orings import main_axes, o_ring

    airfoil = _naca_0012()
    ring = o_ring(airfoil, [CHANNEL], main_axes(CHANNEL))
    assert ring.c_shaped is not None and len(ring.c_shaped) == len(ring.edges) - 2
    trailing = [e for e in ring.c_shaped if np.allclose(e[0], (1.0, 0.0))]
    assert len(trailing) == 1 and trailing[0][1][1] == 0.0  # along the bisector, downstream
    assert o_ring(DIAMOND[::-1], [CHANNEL], main_axes(CHANNEL)).c_shaped is None
    edges = propose_edges([CHANNEL, airfoil])
    settings = make_settings("elliptic", kind="blocks")
    result = mesh_blocks([CHANNEL, airfoil], edges, [""] * len(edges), settings)
    assert result.report["quality"]["folded_cells"] == 0
    nodes = np.vstack([g.reshape(-1, 2) for g in result.grids])
    assert np.linalg.norm(nodes - (1.0, 0.0), axis=1).min() < 1e-12


def test_a_round_u_bend_is_cut_where_its_bends_begin():
    """A channel turning back through a half annulus is four-sided (its legs end square),
    so it was one block; its walls' straight runs meet the bend at x = 4, where the search
    now may cut it, and it keeps the cuts: three blocks (one block's mean was 118.5)."""
    from pinn_engine.multiblock.autoblock.bends import junctions

    t = np.linspace(-np.pi / 2, np.pi / 2, 33)
    outer = np.column_stack([4 + 1.5 * np.cos(t), 1.5 * np.sin(t)])
    inner = np.column_stack([4 + 0.5 * np.cos(t), 0.5 * np.sin(t)])[::-1]
    ring = np.vstack([[(0, -1.5)], outer, [(0, 1.5), (0, 0.5)], inner, [(0, -0.5)]])
    assert len(junctions(ring, 5.0)) == 4
    edges = propose_edges([ring])
    assert sorted(sorted(e[:, 1].tolist()) for e in edges) == [[-1.5, -0.5], [0.5, 1.5]]
    assert all(np.allclose(e[:, 0], 4.0) for e in edges)
    quarter = np.vstack([outer[16:], inner[:17]])  # a quarter annulus: no straight run
    assert propose_edges([quarter]) == []


def test_layouts_are_judged_at_the_run_s_cell_size_no_finer_than_a_quarter_of_the_default():
    from pinn_engine.multiblock.autoblock.score import FINEST, scoring_size
    from pinn_engine.multiblock.counts import default_cell_size

    default = default_cell_size(8.0)
    assert scoring_size(8.0) == default and scoring_size(8.0, 0.5) == 0.5
    assert scoring_size(8.0, 0.1) == 0.1 and scoring_size(8.0, 1e-3) == default / FINEST


@pytest.mark.slow  # the search meshes its shortlisted layouts: about 3 s
def test_a_wide_leaning_tee_is_blocked_for_the_cell_size_asked(tmp_path):
    """A tee [0, 8] x [0, 1] with a branch 2 wide leaning 30 degrees downstream, at 8 cells
    across the channel: judged at the default size (0.21) the search picked 5 blocks whose
    grid at 0.125 kinks 3.27 degrees on average (SPEC 13's bound 3); judged at the size
    asked, 3 blocks (kinks 0.20, worst 120.0) or 4 (kinks 1.10, worst 122.8): the two score
    within a few degrees and the same code has picked each on different machines; both keep
    the bound and stay well below the hand blocking's 132.5."""
    import json

    up = 2.0 * np.array([np.sin(np.pi / 6), np.cos(np.pi / 6)])
    left, right = np.array([2.5, 1.0]), np.array([4.5, 1.0])
    ring = np.array([(0, 0), (8, 0), (8, 1), right, right + up, left + up, left, (0, 1)])
    path, out, report = tmp_path / "tee.csv", tmp_path / "tee.vtm", tmp_path / "tee.json"
    np.savetxt(path, ring, delimiter=",", header="x,y", comments="")
    argv = [str(path), "--blocks", "auto", "--method", "elliptic", "--cell-size", "0.125"]
    assert main([*argv, "--quiet", "--report", str(report), "-o", str(out)]) == 0
    found = json.loads(report.read_text())
    assert found["quality"]["folded_cells"] == 0
    assert found["interface_kink"]["mean"] <= 3.0 and found["quality"]["worst_max_angle"] < 125.0


@pytest.mark.slow  # the search meshes its shortlisted layouts with the spacing: about 5 s
def test_a_layout_is_judged_with_the_wall_spacing_asked(tmp_path):
    """An open cavity [2, 3] x [-1, 0] under a channel [0, 6] x [0, 1]: its two mirror-image
    layouts (the lid and one upright edge, at x = 2 or at x = 3) are rectangular alike
    without a spacing; with --spacing boundary=0.01 the spacing carried through the block
    beside the cavity's other corner sheared one of them to 172.9 degrees. Judged with the
    spacing, the search keeps a rectangular grid."""
    import json

    ring = np.array([(0, 0), (2, 0), (2, -1), (3, -1), (3, 0), (6, 0), (6, 1), (0, 1)])
    path, out, report = tmp_path / "cavity.csv", tmp_path / "c.vtm", tmp_path / "c.json"
    np.savetxt(path, ring, delimiter=",", header="x,y", comments="")
    argv = [str(path), "--blocks", "auto", "--method", "elliptic", "--cell-size", "0.125"]
    argv += ["--spacing", "boundary=0.01", "--quiet", "--report", str(report), "-o", str(out)]
    assert main(argv) == 0
    found = json.loads(report.read_text())
    assert found["quality"]["worst_max_angle"] < 90.5


def test_a_reflex_vertex_emits_the_cross_field_s_separatrices():
    """A 245-degree corner (a tee's branch leaning 25 degrees) splits into three corners of
    81.7 degrees; a 270-degree corner's separatrices are its two sides carried on."""
    from pinn_engine.multiblock.autoblock.corners import Reflex
    from pinn_engine.multiblock.autoblock.rays import separatrices

    d_in = np.array([np.sin(np.radians(205.0)), np.cos(np.radians(205.0))])
    vertex = Reflex(np.zeros(2), d_in, np.array([-1.0, 0.0]), 245.0, True)
    turns = [np.degrees(np.arctan2(d[1], d[0])) % 360 for d in separatrices(vertex)]
    assert np.allclose(turns, [180 + 245 / 3, (180 + 2 * 245 / 3) % 360])
    corner = Reflex(np.zeros(2), np.array([1.0, 0.0]), np.array([0.0, -1.0]), 270.0, True)
    assert np.allclose(separatrices(corner), [[1.0, 0.0], [0.0, 1.0]], atol=1e-12)


def test_a_steep_tee_carries_its_branch_walls_on():
    """A tee [0, 8] x [0, 1] whose branch (1 along the channel) leans 60 degrees upstream:
    the branch's wall carried on leaves 30 degrees beside the channel's wall, as a careful
    hand blocking draws it (worst 150.0); without that direction the search found no layout
    that meshes without folds (and 173.6 degrees leaning downstream)."""
    up = 2.0 * np.array([-np.sin(np.pi / 3), np.cos(np.pi / 3)])
    left, right = np.array([3.0, 1.0]), np.array([4.0, 1.0])
    ring = np.array([(0, 0), (8, 0), (8, 1), right, right + up, left + up, left, (0, 1)])
    figures = _figures([ring], propose_edges([ring], cell_size=0.125), 0.125)
    assert figures["folds"] == 0 and figures["worst"] < 150.5


def test_a_narrow_y_with_no_layout_that_meshes_widens_the_search_to_its_mouth_s_kinks():
    """A Y whose arms (0.6 wide) leave at +-35 degrees: every layout of the edges from its
    crotch's corners folds 1 cell there (refused); the search then widens to cuts between
    the walls' kinks, the inlet's mouth among them (worst 129.5; the hand-drawn centre's
    178.9)."""
    ring = []
    for angle, width in ((-35.0, 0.6), (35.0, 0.6), (180.0, 1.0)):
        a = np.array([np.cos(np.radians(angle)), np.sin(np.radians(angle))])
        n = np.array([-a[1], a[0]])
        right, left = a - 0.5 * width * n, a + 0.5 * width * n
        ring += [right, right + 3 * a, left + 3 * a, left]
    edges = propose_edges([np.array(ring)], cell_size=0.125)
    mouth = [[-1.0, 0.5], [-1.0, -0.5]]
    assert any(np.allclose(e, mouth) or np.allclose(e[::-1], mouth) for e in edges)
    figures = _figures([np.array(ring)], edges, 0.125)
    assert figures["folds"] == 0 and figures["worst"] < 130 and figures["kink"] < 3.0


# the search meshes its shortlisted layouts: about 2 s at 0.1
@pytest.mark.parametrize("h", [pytest.param(0.1, marks=pytest.mark.slow), 0.125])
def test_a_y_s_hexagonal_centre_may_be_cut_along_a_diagonal(h):
    """The example Y at cell sizes of 0.1 and 0.125: its three-block centre turns grid lines
    by 4.49 and 5.29 degrees at the interfaces on average (SPEC 13's bound 3); cut along a
    diagonal, the centre has no vertex where three blocks meet and the kinks fall under 3,
    the mean and worst cell within SPEC 13's bounds of the three-block centre (at 0.125 a
    layout 0.8 degrees better on the mean, kinks 3.49, ranked first before a kink beyond
    the bound was weighed more)."""
    from make_multiblock import ybranch

    rings, hand_edges = ybranch()
    auto = _figures(rings, propose_edges(rings, cell_size=h), h)
    hand = _figures(rings, hand_edges, h)
    assert auto["folds"] == 0 and auto["kink"] <= 3.0 < hand["kink"]
    assert auto["mean"] <= hand["mean"] + 1.5 and auto["worst"] <= hand["worst"] + 10


@pytest.mark.slow  # the search meshes both rings' shortlisted layouts: about 2.5 s
def test_a_square_near_a_floor_gets_a_ring_reaching_the_floor():
    """A square of side 0.5 whose bottom is 0.25 above the floor of [-2, 5] x [0, 2]: its
    O-ring took 45 % of that gap beneath it and of the gap beside its lower corners, and
    every layout folded (the proposal was refused); the ring reaching the floor meshes with
    no fold (worst 139.6, the hand-drawn O-ring's 148.2)."""
    channel = np.array([(-2, 0), (5, 0), (5, 2), (-2, 2)], dtype=float)
    body = np.array([(1, 0.25), (1.5, 0.25), (1.5, 0.75), (1, 0.75)])
    figures = _figures([channel, body], propose_edges([channel, body], cell_size=0.125), 0.125)
    assert figures["folds"] == 0 and figures["worst"] < 148.2


SQUARE = np.array([(0, 0.05), (0.5, 0.05), (0.5, 0.55), (0, 0.55)])  # 0.1 above its mirror


def test_holes_too_close_for_rings_of_their_own_share_a_box_cut_across_their_gap():
    """Two squares 0.5 wide, 0.1 apart: each one's ring would leave a tenth of the gap
    between their boxes, so the search also tries one box round both, cut midway across
    the gap, whose block across the gap runs between the squares' facing corners; where
    the boxes overlap (a slat against its main element) only the shared box is tried."""
    from pinn_engine.multiblock.autoblock.orings import main_axes, ring_forms

    holes = [SQUARE[::-1], (SQUARE * (1, -1))]  # clockwise, as the domain's holes
    forms = ring_forms([CHANNEL, *holes], main_axes(CHANNEL))
    shared = [f[0] for f in forms if len(f) == 1]
    assert len(forms) > len(shared) >= 1  # separate rings are tried too
    for ring in shared:
        assert np.allclose(ring.box.min(axis=0), (-0.55, -1.1))
        edges = {tuple(np.round(e, 9).ravel()) for e in ring.edges}
        assert (-0.55, 0.0, 1.05, 0.0) in edges  # the cut
        for x in (0.0, 0.5):  # the gap's block: its sides from the facing corners to the cut
            assert (x, 0.05, x, 0.0) in edges and (x, -0.05, x, 0.0) in edges
    slat = np.array([(-0.2, -0.05), (-0.02, -0.1), (-0.05, -0.02)])
    main_element = np.array([(0.0, 0.0), (0.3, -0.05), (1.0, 0.0), (0.3, 0.05)])[::-1]
    forms = ring_forms([CHANNEL, slat[::-1], main_element], main_axes(CHANNEL))
    assert [len(f) for f in forms] == [1] * len(forms)


@pytest.mark.slow  # the search meshes the shortlisted layouts: about 8 s of CPU
def test_two_squares_side_by_side_mesh_with_their_corners_as_nodes(tmp_path):
    """The two squares 0.1 apart in a channel, at 8 cells a unit: every ring of each alone
    folds (they were refused); the shared box meshes, every corner a node."""
    lower = (SQUARE * (1, -1))[::-1]
    lines = [np.r_[r, r[:1]] for r in (CHANNEL, SQUARE, lower)]
    poly = pv.PolyData()
    poly.points = np.vstack([np.c_[r, np.zeros(len(r))] for r in lines])
    poly.lines = np.r_[5, 0, 1, 2, 3, 4, 5, 5, 6, 7, 8, 9, 5, 10, 11, 12, 13, 14]
    path, out = tmp_path / "squares.vtp", tmp_path / "g.vtm"
    poly.save(path)
    argv = ["--blocks", "auto", "--method", "elliptic", "--cell-size", "0.125", "--quiet"]
    assert main([str(path), *argv, "-o", str(out)]) == 0
    nodes = np.vstack(_vtm_points(out))[:, :2]
    for corner in np.vstack([SQUARE, lower]):
        assert np.linalg.norm(nodes - corner, axis=1).min() < 1e-12
