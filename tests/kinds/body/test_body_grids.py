"""The body kind's O- and C-grids (SPEC 9), called as the kind (``kinds.body.mesh.mesh_body``):
indices, seam, wake cut, far field, wall, blunt bases, every method unfolded, the pinn."""

from __future__ import annotations

import re

import numpy as np
import pytest
from helpers import write_selig

from pinn_engine.bodies.airfoil import body_from_points, circle, load_body, naca4
from pinn_engine.bodies.bodygrid import C_BASE_INTERVALS
from pinn_engine.errors import InputError
from pinn_engine.geometry.boundary import segment_distance
from pinn_engine.io.pipeline import read_body_and_farfield
from pinn_engine.kinds.body.mesh import mesh_body
from pinn_engine.quality import non_orthogonality, worst_non_orthogonality
from pinn_engine.settings import make_settings

FAST_PINN = {"lbfgs_iterations": 10, "lbfgs_points": 200}


@pytest.fixture(scope="module")
def o_grid():
    body = load_body(naca="0012", te="blunt")
    far = circle(body, 15)
    return body, far, mesh_body(body, far, "o", "elliptic", 81, 33, wall_spacing=1e-4)


@pytest.fixture(scope="module")
def c_grid():
    body = load_body(naca="2412")
    far = circle(body, 10)
    return body, far, mesh_body(body, far, "c", "elliptic", 121, 33, wall_spacing=1e-4)


def test_o_grid_indices_seam_far_field_and_wall(o_grid):
    body, far, result = o_grid
    g = result.points
    t = result.report["topology"]
    assert t["seam_gap"] == 0.0 and np.array_equal(g[:, 0], g[:, -1])
    assert t["far_field_radius_error"] < 1e-9
    assert np.argmax(g[0, :-1, 0]) == 0  # starts at the trailing edge (largest x)
    assert g[0, 1, 1] > g[0, 0, 1]  # counter-clockwise: up the trailing edge first
    assert result.quality["folded_cells"] == 0
    assert result.quality["boundary_deviation"] < 1e-4
    lo, hi = t["first_layer"]["min"], t["first_layer"]["max"]
    assert 0.9e-4 <= lo <= hi <= 1.1e-4
    assert t["wall_angle_deviation"] < 3.0


def test_c_grid_cut_outflow_far_field_and_wall(c_grid):
    body, far, result = c_grid
    g = result.points
    t = result.report["topology"]
    n = t["wake_nodes"]
    assert t["cut_gap"] == 0.0
    np.testing.assert_array_equal(g[0, : n + 1], g[0, ::-1][: n + 1])  # coincide pairwise
    np.testing.assert_allclose(g[0, n], body.surface[0])  # the trailing edge
    assert np.all(np.diff(g[0, : n + 1, 0]) < 0)  # the cut runs from the outflow to the TE
    np.testing.assert_allclose(g[0, : n + 1, 1], body.surface[0, 1])  # straight, in +x
    x_out = far.center[0] + far.radius
    np.testing.assert_allclose(g[:, 0, 0], x_out)  # outflow columns
    np.testing.assert_allclose(g[:, -1, 0], x_out)
    assert t["far_field_radius_error"] < 1e-9
    assert result.quality["folded_cells"] == 0
    assert 0.9e-4 <= t["first_layer"]["min"] <= t["first_layer"]["max"] <= 1.1e-4
    assert t["wall_angle_deviation"] < 3.0


@pytest.mark.parametrize("topology, code", [("o", "0012"), ("c", "0012"), ("c", "4412")])
def test_every_method_gives_an_unfolded_grid(topology, code):
    body = load_body(naca=code, te="blunt" if topology == "o" else "sharp")
    far = circle(body, 12)
    worst = {}
    for method in ("tfi", "elliptic", "pinn"):
        settings = make_settings(method, lattice=(97, 25), **FAST_PINN)
        r = mesh_body(body, far, topology, method, 97, 25, settings, wall_spacing=1e-3)
        assert r.quality["folded_cells"] == 0, method
        worst[method] = r.report["topology"]["wall_angle_deviation"]
        if method == "pinn":
            guard = r.report["training"]["guard"]
            assert guard["kept"]["worst_max_angle"] <= guard["elliptic"]["worst_max_angle"] + 1
    # TFI's straight columns leave the wall obliquely; the others at right angles
    assert worst["elliptic"] < 1.0 and worst["pinn"] < 1.0 < worst["tfi"]


@pytest.mark.parametrize("code", ["0012", "4412"])
def test_c_grid_wake_cells_are_smooth_enough_for_a_solver(code):
    """On a y+ ~ 1 C-grid the wake's cells are a chord long and 1e-5 high;
    row heights that wiggle from column to column gave checkMesh 89 degrees there."""
    body = load_body(naca=code, te="sharp")
    r = mesh_body(body, circle(body, 15), "c", "pinn", 320, 90, wall_spacing=1e-5)
    worst = max(a.max() for a in non_orthogonality(r.points).values())
    assert worst <= 20.0
    assert r.quality["folded_cells"] == 0


def test_a_blunt_base_stays_as_drawn(tmp_path):
    """A Selig file with a 0.7 % chord base (as LS(1)-0417's): the base is a
    straight piece of wall with its corners as nodes, no wall node farther than 0.1 % chord
    from the drawn polyline (the periodic spline put them up to 0.36 % off)."""
    body = _base07(tmp_path)
    assert not body.sharp
    r = mesh_body(body, circle(body, 15), "o", "elliptic", 161, 41, wall_spacing=1e-4)
    wall = r.points[0]
    off = segment_distance(wall, body.ring()[:-1]).max() / body.chord
    assert off <= 1e-3
    for corner in (body.surface[0], body.surface[-1]):
        assert np.linalg.norm(wall - corner, axis=1).min() < 1e-12
    assert np.allclose(wall[0], 0.5 * (body.surface[0] + body.surface[-1]))  # the base's middle
    assert r.quality["folded_cells"] == 0


def test_pinn_is_periodic_in_xi(o_grid):
    body, far, _ = o_grid
    settings = make_settings("pinn", lattice=(81, 33), **FAST_PINN)
    r = mesh_body(body, far, "o", "pinn", 81, 33, settings, wall_spacing=1e-4)
    assert r.report["topology"]["seam_gap"] == 0.0
    assert r.quality["folded_cells"] == 0


def test_paper_preset_trains_from_tfi():
    body = load_body(naca="0012", te="blunt")
    settings = make_settings(
        "pinn", "paper", lattice=(41, 17), adam_epochs=20, lbfgs_iterations=5, lbfgs_points=100
    )
    r = mesh_body(body, circle(body, 8), "o", "pinn", 41, 17, settings)
    assert r.report["training"]["warm_start"] == "none"
    assert r.report["topology"]["seam_gap"] == 0.0


def _base07(tmp_path):
    """A Selig file of NACA 4417 opened to a 0.7 % chord base, as LS(1)-0417's."""
    xy = naca4("4417", te="sharp")
    xy[:, 1] += np.where(np.arange(len(xy)) <= len(xy) // 2, 0.5, -0.5) * 0.007 * xy[:, 0]
    return load_body(write_selig(tmp_path / "base07.dat", xy))


def test_a_blunt_c_grid_leaves_the_base_middle_unfolded(tmp_path):
    """The C-grid of a blunt trailing edge: the cut leaves the base's middle
    in +x, the base is wall as drawn (corners as nodes), and the two concave corners where
    the cut meets the base fold no cell."""
    body = _base07(tmp_path)
    r = mesh_body(body, circle(body, 15), "c", "elliptic", 250, 64, wall_spacing=1e-5)
    assert r.quality["folded_cells"] == 0
    n_w, g = r.report["topology"]["wake_nodes"], r.points
    mid = 0.5 * (body.surface[0] + body.surface[-1])
    cut = g[0, : n_w + 1]
    np.testing.assert_allclose(cut[-1], mid, atol=1e-12)  # the cut's start: the base's middle
    np.testing.assert_allclose(cut[:, 1], mid[1], atol=1e-12)
    assert np.all(np.diff(cut[:, 0]) < 0)  # straight downstream
    assert r.report["topology"]["cut_gap"] == 0.0
    wall = g[0, n_w : g.shape[1] - n_w]
    assert segment_distance(wall, body.ring()[:-1]).max() / body.chord <= 1e-3
    base = wall[np.abs(wall[:, 0] - mid[0]) < 1e-12]  # the base's nodes, on the drawn base
    assert len(base) == C_BASE_INTERVALS + 2  # both halves, the middle at both ends
    for corner in (body.surface[0], body.surface[-1]):
        assert np.linalg.norm(wall - corner, axis=1).min() < 1e-12
    assert r.report["topology"]["wall_angle_deviation"] < 0.1
    # the marched grid's worst face, at the corners (84.8); elliptic sweeps that lower the
    # worst angle there while they raise it in the wake (89.4) are not kept
    assert worst_non_orthogonality(g) < 85.0


def _flatback(code: str, base: float):
    """NACA ``code`` opened linearly to a base of ``base`` chords (a flatback section, as
    AH 93-W-480B's 23 % base)."""
    xy = naca4(code, te="sharp")
    xy[:, 1] += np.where(np.arange(len(xy)) <= len(xy) // 2, 0.5, -0.5) * base * xy[:, 0]
    return body_from_points(xy, f"flatback {code}")


@pytest.mark.parametrize(
    "code, base, size, first",
    [
        ("4417", 0.2, (121, 33), 1e-4),
        ("0018", 0.15, (161, 41), 1e-5),
        ("0012", 0.05, (161, 41), 1e-5),
    ],
)
def test_a_thick_base_c_grid_fans_out_unfolded(code, base, size, first):
    """A C-grid around a base of 5 to 20 % chord: the base's columns leave it normal and
    fan out (turned along the base within 0.02 chords, they ran along it: refused, or cells
    of 167 to 178 degrees); no fold, no cell near 180 degrees."""
    body = _flatback(code, base)
    r = mesh_body(body, circle(body, 15), "c", "elliptic", *size, wall_spacing=first)
    assert r.quality["folded_cells"] == 0
    assert r.quality["worst_max_angle"] < 160.0


@pytest.mark.parametrize("size", [(41, 21), (121, 21), (251, 81)])
def test_a_blunt_c_grid_without_a_first_layer_asked_has_no_fold(tmp_path, size):
    """The default first layer of a blunt C-grid is a share of the base's interval (the
    base's rows march down the wake, whose first interval is the base's): a 0.7 % base meshes
    at every size, where half the wall's mean spacing folded the cut."""
    body = _base07(tmp_path)
    r = mesh_body(body, circle(body, 10), "c", "elliptic", *size)
    assert r.quality["folded_cells"] == 0
    assert r.quality["worst_max_angle"] < 170.0


def test_a_blunt_c_grid_that_would_fold_is_refused_and_the_advice_works(tmp_path):
    """A first layer asked taller than the base's interval: the base's and the cut's
    columns, leaving the wall normal, cross. The refusal names --topology o, whose grid of
    the same size has no fold, and the first layer that meshes, which does."""
    body = _base07(tmp_path)
    with pytest.raises(InputError, match="blunt trailing edge.*use --topology o") as info:
        mesh_body(body, circle(body, 10), "c", "elliptic", 121, 21, wall_spacing=0.01)
    message = str(info.value)
    assert "\n" not in message
    first = float(re.search(r"first layer of at most (\S+) ", message)[1])
    r = mesh_body(body, circle(body, 10), "c", "elliptic", 121, 21, wall_spacing=first)
    assert r.quality["folded_cells"] == 0
    for method in ("tfi", "elliptic"):
        r = mesh_body(body, circle(body, 10), "o", method, 121, 21)
        assert r.quality["folded_cells"] == 0 and r.quality["worst_max_angle"] < 180


def test_two_polylines_file(tmp_path):
    body = naca4("0012", points=61, te="blunt")
    th = np.linspace(0, 2 * np.pi, 80, endpoint=False)
    outer = np.column_stack([0.5 + 8 * np.cos(th), 6 * np.sin(th)])  # an ellipse
    text = (
        "\n".join(f"{x},{y}" for x, y in body)
        + "\n\n"
        + "\n".join(f"{x},{y}" for x, y in outer)
        + "\n"
    )
    path = tmp_path / "two.csv"
    path.write_text(text)
    b, far = read_body_and_farfield(path)
    r = mesh_body(b, far, "o", "elliptic", 81, 25, wall_spacing=1e-3)
    assert r.quality["folded_cells"] == 0
    last = r.points[-1]
    assert np.abs(((last[:, 0] - 0.5) / 8) ** 2 + (last[:, 1] / 6) ** 2 - 1).max() < 0.02


@pytest.mark.slow  # the 300 x 80 C-grid at 1e-5 walls where the fold appeared (about 6 s CPU)
def test_a_gap_in_a_round_trailing_edge_is_round_and_gets_a_c_grid(tmp_path):
    """A circle left open by 0.4 % at x = 1 (the IEA root sections): the gap's ends are no
    corners, so the edge is round; the C-grid's cut leaves the gap's middle, smoothed round
    it as round a base of the height facing downstream, with no fold."""
    t = np.linspace(0.004, 2 * np.pi - 0.004, 121)
    body = body_from_points(np.c_[0.5 + 0.5 * np.cos(t), 0.5 * np.sin(t)], "root")
    assert body.rounded and not body.sharp
    r = mesh_body(body, circle(body, 15.0), "c", "elliptic", 300, 80, wall_spacing=1e-5)
    assert r.report["quality"]["folded_cells"] == 0
    assert r.report["quality"]["worst_max_angle"] < 180


@pytest.mark.parametrize("topology", ["o", "c"])
def test_a_three_point_closed_wedge_is_a_body(tmp_path, topology):
    path = write_selig(tmp_path / "wedge.dat", [(1, 0), (0, 0.05), (0, -0.05), (1, 0)])
    body = load_body(path)
    assert body.sharp and np.allclose(body.surface[0], (1, 0))
    grid = mesh_body(body, circle(body, 15.0), topology, "elliptic", 64, 24).points
    assert np.isfinite(grid).all()
