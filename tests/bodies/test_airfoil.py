"""O- and C-grids around airfoils (SPEC 9): readers, NACA sections, topology, CLI."""

from __future__ import annotations

import json

import numpy as np
import pytest
from vtkmodules.vtkIOXML import vtkXMLStructuredGridReader

from pinn_engine.bodies.airfoil import body_from_points, circle, load_body, naca4, read_dat
from pinn_engine.bodies.bodygrid import C_BASE_INTERVALS
from pinn_engine.classical.spacing import exact_stretch
from pinn_engine.errors import InputError
from pinn_engine.geometry.boundary import segment_distance
from pinn_engine.io.pipeline import read_body_and_farfield
from pinn_engine.kinds.body.mesh import mesh_body
from pinn_engine.quality import non_orthogonality, worst_non_orthogonality
from pinn_engine.routes.cli import main
from pinn_engine.settings import make_settings

FAST_PINN = {"lbfgs_iterations": 10, "lbfgs_points": 200}


def _selig(path, xy, name="TEST"):
    path.write_text(name + "\n" + "\n".join(f"{x:.7f} {y:.7f}" for x, y in xy) + "\n")
    return path


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


def test_selig_and_lednicer_give_the_same_airfoil(tmp_path):
    xy = naca4("2412", points=41)
    a, name = read_dat(_selig(tmp_path / "a.dat", xy, "NACA 2412"))
    n = 41
    upper, lower = xy[:n][::-1], xy[n - 1 :]
    text = (
        "NACA 2412\n41. 41.\n\n"
        + "\n".join(f"{x} {y}" for x, y in upper)
        + "\n\n"
        + "\n".join(f"{x} {y}" for x, y in lower)
        + "\n"
    )
    (tmp_path / "b.dat").write_text(text)
    b, _ = read_dat(tmp_path / "b.dat")
    assert name == "NACA 2412"
    np.testing.assert_allclose(a, xy, atol=1e-6)
    np.testing.assert_allclose(b, xy, atol=1e-6)


@pytest.mark.parametrize(
    "text, words",
    [
        ("name\n1 0\n0.5 x\n", "not an 'x y' row"),
        ("name\n1 0\n0 0\n", "at least 3"),
        ("just a name\n", "no 'x y' coordinate rows"),
    ],
)
def test_bad_dat_files_fail_in_one_line(tmp_path, text, words):
    path = tmp_path / "bad.dat"
    path.write_text(text)
    with pytest.raises(InputError, match=words) as info:
        read_dat(path)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("code", ["12", "00a2", "0000", "2012"])
def test_bad_naca_codes(code):
    with pytest.raises(InputError, match="NACA"):
        naca4(code)


def test_naca_sections():
    sharp, blunt = naca4("0012"), naca4("0012", te="blunt")
    np.testing.assert_allclose(sharp[0], sharp[-1])
    assert blunt[0, 1] - blunt[-1, 1] == pytest.approx(0.00252, abs=2e-5)
    assert np.ptp(sharp[:, 1]) == pytest.approx(0.12, abs=2e-3)
    body = load_body(naca="4412")
    assert body.sharp and body.chord == pytest.approx(1.0, abs=1e-3)
    np.testing.assert_allclose(body.mid_chord, (0.5, 0.0), atol=3e-3)


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
    return load_body(_selig(tmp_path / "base07.dat", xy))


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


def test_a_blunt_c_grid_that_would_fold_is_refused_and_the_advice_works(tmp_path):
    """A first layer (here the default, half the mean spacing) taller than the base's half
    and its first wake interval: the base's and the cut's columns, leaving the wall normal,
    cross. The refusal names --topology o, whose grid of the same size has no fold."""
    body = _base07(tmp_path)
    with pytest.raises(InputError, match="blunt trailing edge.*use --topology o") as info:
        mesh_body(body, circle(body, 10), "c", "tfi", 121, 21)
    assert "\n" not in str(info.value)
    for method in ("tfi", "elliptic"):
        r = mesh_body(body, circle(body, 10), "o", method, 121, 21)
        assert r.quality["folded_cells"] == 0 and r.quality["worst_max_angle"] < 180


def test_farfield_must_enclose_the_body():
    body = load_body(naca="0012")
    with pytest.raises(InputError, match="at least 1 chord"):
        circle(body, 0.4)


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


def test_exact_stretching():
    """The body grids' distributions: spacing.py's Vinokur stretching, end intervals exact."""
    s = exact_stretch(41, 1e-4)[0]
    assert s[1] == pytest.approx(1e-4, rel=1e-8) and np.all(np.diff(s) > 0)
    t = exact_stretch(61, 2e-3, 1e-2)[0]
    assert t[1] == pytest.approx(2e-3, rel=1e-8) and 1 - t[-2] == pytest.approx(1e-2, rel=1e-8)
    columns = exact_stretch(30, np.array([1e-5, 1e-3]), None, lines=2)
    np.testing.assert_allclose(columns[:, 1], [1e-5, 1e-3], rtol=1e-8)
    assert (np.diff(columns, axis=1) > 0).all()


def _read(path):
    reader = vtkXMLStructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    return reader.GetOutput()


def test_cli_o_and_c_grids(tmp_path, capsys):
    out = tmp_path / "o.vts"
    rc = main(
        [
            "--naca",
            "0012",
            "--topology",
            "o",
            "--method",
            "tfi",
            "--size",
            "61",
            "21",
            "--spacing",
            "bottom=1e-3",
            "-o",
            str(out),
            "--report",
            str(tmp_path / "o.json"),
            "--quiet",
        ]
    )
    assert rc == 0
    grid = _read(out)
    fd = grid.GetFieldData()
    assert fd.GetAbstractArray("Topology").GetValue(0) == "o"
    names = [fd.GetAbstractArray("PatchNames").GetValue(k) for k in range(4)]
    assert names == ["wall", "seam", "farfield", "seam"]
    report = json.loads((tmp_path / "o.json").read_text())
    assert report["topology"]["seam_gap"] == 0.0
    dat = _selig(tmp_path / "foil.dat", naca4("2412", points=61))
    out = tmp_path / "c.vts"
    assert (
        main(
            [
                str(dat),
                "--topology",
                "c",
                "--method",
                "elliptic",
                "--size",
                "121",
                "21",
                "--farfield",
                "8",
                "-o",
                str(out),
                "--quiet",
            ]
        )
        == 0
    )
    fd = _read(out).GetFieldData()
    assert fd.GetAbstractArray("Topology").GetValue(0) == "c"
    assert fd.GetArray("WakeNodes").GetValue(0) > 0


@pytest.mark.parametrize(
    "argv, words",
    [
        (["--naca", "0012", "--method", "tfi"], "--topology o or c"),
        (["--naca", "0012", "--topology", "o", "--method", "mgnet"], "mgnet"),
        (["--naca", "0012", "--topology", "o", "--spacing", "top=1e-3"], "bottom=H"),
        (["--naca", "0012", "--topology", "c", "--extrude", "0.1", "-o", "x.msh"], "Gmsh in 2D"),
        (["--naca", "00x2", "--topology", "o"], "NACA"),
        (
            ["--naca", "0012", "--topology", "o", "--method", "tfi", "--orthogonal", "bottom"],
            "right angles",
        ),
    ],
)
def test_cli_errors_are_one_line(tmp_path, capsys, argv, words):
    rc = main(
        argv
        + ["--size", "41", "17", "--quiet"]
        + ([] if "-o" in argv else ["-o", str(tmp_path / "g.vts")])
    )
    err = capsys.readouterr().err
    assert rc == 2 and words in err and err.count("\n") == 1


def test_pyvista_routes(tmp_path):
    pv = pytest.importorskip("pyvista")
    from pinn_engine.routes.pyvista_accessor import pinn_mesh

    grid = pinn_mesh(
        None,
        naca="0012",
        topology="o",
        size=(61, 21),
        method="elliptic",
        farfield=10,
        spacing={"bottom": 1e-3},
        orthogonal="bottom",
    )
    assert grid.dimensions == (61, 21, 1)
    assert grid.field_data["Topology"][0] == "o"
    pts = grid.points.reshape(21, 61, 3)
    np.testing.assert_array_equal(pts[:, 0], pts[:, -1])
    r = np.linalg.norm(pts[-1, :, :2] - (0.5, 0.0), axis=1)
    np.testing.assert_allclose(r, 10.0, atol=2e-3)  # mid-chord of the blunt section
    xy = naca4("2412", points=61)
    body = pv.lines_from_points(np.column_stack([xy, np.zeros(len(xy))]))
    c = body.pinn_mesh(size=(121, 21), method="tfi", topology="c", farfield=8)
    assert c.field_data["Topology"][0] == "c"
    assert list(c.field_data["PatchNames"]) == ["wall", "outflow", "farfield", "outflow"]
    dat = _selig(tmp_path / "f.dat", xy)
    g = pinn_mesh(str(dat), topology="c", size=(121, 21), method="tfi")
    assert g.n_cells == 120 * 20
    with pytest.raises(ValueError, match="topology 'x': use none, o, c"):
        pinn_mesh(None, naca="0012", topology="x", size=(41, 17))


def test_inside_polygon_needs_no_matplotlib():
    """The far-field polyline's inside test (even-odd rule): points of a concave star."""
    from pinn_engine.bodies.airfoil import inside_polygon

    th = np.linspace(0, 2 * np.pi, 10, endpoint=False)
    r = np.where(np.arange(10) % 2 == 0, 2.0, 1.0)
    star = np.column_stack([r * np.cos(th), r * np.sin(th)])
    pts = np.array([[0.0, 0.0], [1.9, 0.0], [3.0, 0.0], [1.5 * np.cos(th[1]), 1.5 * np.sin(th[1])]])
    assert inside_polygon(pts, star).tolist() == [True, True, False, False]


@pytest.mark.parametrize("gap, sharp", [(1e-5, True), (1e-4, True), (1e-3, False)])
def test_a_trailing_edge_open_by_at_most_1e4_chord_is_sharp(tmp_path, capsys, gap, sharp):
    """SPEC 9: a .dat whose trailing edge is open by 1e-5 chord, as many
    public files are, gets a C-grid, closed at the mean point of its two ends; 1e-3 is a
    drawn base, whose C-grid folds at this coarse size and is refused."""
    xy = naca4("0012", points=81)
    xy[0, 1] += gap / 2
    xy[-1, 1] -= gap / 2
    dat = _selig(tmp_path / "gap.dat", xy)
    body = load_body(dat)
    assert body.sharp == sharp
    if sharp:
        np.testing.assert_allclose(body.surface[0], [1.0, 0.0], atol=1e-7)
    out = tmp_path / "c.vts"
    argv = [str(dat), "--topology", "c", "--method", "tfi", "--size", "121", "21", "-o", str(out)]
    rc = main([*argv, "--quiet"])
    err = capsys.readouterr().err
    assert (rc, out.exists()) == ((0, True) if sharp else (2, False)), err
    if not sharp:
        assert "blunt trailing edge (a base of 0.001 chords)" in err and "--topology o" in err


@pytest.mark.parametrize("te", ["sharp", "blunt"])
def test_an_airfoil_meshed_as_a_four_sided_domain_is_told_to_choose_a_topology(te):
    """The filter with its default topology says the input looks like a
    body and names Topology O-grid or C-grid (not Closed or Corner Indices); pyvista names
    its keyword; an open four-sided outline keeps its own message."""
    pv = pytest.importorskip("pyvista")
    from pinn_engine.routes.airfoil_algorithm import AirfoilSource
    from pinn_engine.routes.algorithm import PinnMeshAlgorithm
    from pinn_engine.routes.pyvista_accessor import pinn_mesh

    source = AirfoilSource()
    source.SetNACA("2412")
    source.SetSharpTrailingEdge(te == "sharp")
    alg = PinnMeshAlgorithm()
    alg.SetInputConnection(0, source.GetOutputPort())
    alg.SetMethod("tfi")
    alg.Update()
    assert "looks like an airfoil or another body" in alg.GetLastError()
    assert "choose Topology O-grid or C-grid to mesh around it" in alg.GetLastError()
    source.Update()
    with pytest.raises(InputError, match='topology="o" or "c"'):
        pinn_mesh(pv.wrap(source.GetOutputDataObject(0)), method="tfi")
    three_sides = np.array([[0.0, 1.0], [0.0, 0.0], [2.0, 0.0], [2.0, 1.0]])
    with pytest.raises(InputError, match="open") as info:
        pinn_mesh(pv.lines_from_points(np.c_[three_sides, np.zeros(4)]), method="tfi")
    assert "body" not in str(info.value)


def _flatback_ring(start_mid_base: bool) -> np.ndarray:
    """NACA 0030 opened to a flatback base of 0.2 chord, closed by its base drawn as part
    of the ring: from the base's middle (1, 0) as NuMAD files start, or from its corner."""
    xy = naca4("0030", 101)
    n = len(xy) // 2
    xy[:, 1] += np.where(np.arange(len(xy)) <= n, 0.5, -0.5) * 0.2 * xy[:, 0]
    if start_mid_base:
        return np.vstack([[[1.0, 0.0], [1.0, 0.05]], xy, [[1.0, -0.05], [1.0, 0.0]]])
    return np.vstack([xy, [[1.0, 0.0]], xy[:1]])


@pytest.mark.parametrize("start_mid_base", [True, False])
def test_the_trailing_edge_is_found_from_the_shape_not_the_file_start(start_mid_base):
    body = body_from_points(_flatback_ring(start_mid_base), "numad")
    assert not body.sharp and not body.rounded
    assert np.allclose(body.surface[0], (1.0, 0.1)) and np.allclose(body.surface[-1], (1.0, -0.1))
    assert body.te_gap == pytest.approx(0.2)


def test_a_sharp_trailing_edge_is_its_corner_where_the_file_starts_elsewhere():
    xy = naca4("2412", 81)
    ring = np.vstack([xy[30:-1], xy[:31]])  # starts on the upper surface, closed
    body = body_from_points(ring, "shifted")
    assert body.sharp and np.allclose(body.surface[0], (1.0, 0.0))


def _openfast_file(path, xy, reference=(0.25, 0.0)):
    """An OpenFAST (AeroDyn) airfoil file: NumCoords, '!' comments, the reference point."""
    rows = "".join(f" {x:.12e} {y:.12e}\n" for x, y in xy)
    path.write_text(
        f"  {len(xy) + 1}   NumCoords   ! The number of coordinates (incl. the reference)\n"
        "! x-y coordinate of airfoil reference\n!  x/c        y/c\n"
        f" {reference[0]:.6f}       {reference[1]:g}\n"
        "! coordinates of airfoil shape\n! interpolation to 200 points\n!  x/c        y/c\n" + rows
    )
    return path


def test_an_openfast_coords_file_is_read_without_its_reference_point(tmp_path):
    xy = naca4("2412", 81)[::-1]  # clockwise, as many OpenFAST files run
    got, name = read_dat(_openfast_file(tmp_path / "AF05_Coords.txt", xy))
    assert name == "AF05_Coords" and np.allclose(got, xy)
    body = load_body(tmp_path / "AF05_Coords.txt")
    assert body.sharp and np.allclose(body.surface[0], (1.0, 0.0))


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


def test_the_wall_stays_within_the_tolerance_of_sparse_points_round_a_bend():
    """A section drawn with few points, evenly in x, round a blunt nose: the spline through
    them swings 1.1 % chord off the polyline there; the wall is held within 0.05 %."""
    from pinn_engine.bodies.bodygrid import WALL_HOLD, BodyCurve

    x = np.linspace(0.0, 1.0, 41)
    upper = np.c_[x, 0.3 * np.sqrt(x) * (1 - x) + 0.02 * (1 - x)]
    xy = np.vstack([upper[::-1], (upper * (1, -1))[1:]])
    xy[0] = xy[-1] = (1.0, 0.0)
    body = body_from_points(xy, "wedge")
    curve = BodyCurve(body)
    wall = curve.at(np.linspace(0, curve.length, 4001))
    off = segment_distance(wall, body.ring()[:-1]) / body.chord
    assert off.max() <= WALL_HOLD * (1 + 1e-9)


@pytest.mark.parametrize("topology", ["o", "c"])
def test_a_three_point_closed_wedge_is_a_body(tmp_path, topology):
    path = _selig(tmp_path / "wedge.dat", [(1, 0), (0, 0.05), (0, -0.05), (1, 0)])
    body = load_body(path)
    assert body.sharp and np.allclose(body.surface[0], (1, 0))
    grid = mesh_body(body, circle(body, 15.0), topology, "elliptic", 64, 24).points
    assert np.isfinite(grid).all()
