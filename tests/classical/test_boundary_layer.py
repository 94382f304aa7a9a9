"""Boundary-layer meshes (SPEC 7): first-edge spacing, wall orthogonality, their routes."""

from __future__ import annotations

import json

import numpy as np
import pytest
from helpers import EXAMPLES, wavy_ring

from pinn_engine.classical.elliptic import controlled_solve
from pinn_engine.classical.spacing import param_grid, stretch, uniform_params
from pinn_engine.classical.tfi import tfi_at
from pinn_engine.errors import PinnMeshError
from pinn_engine.io.pipeline import load_boundary
from pinn_engine.kinds.four_sided.mesher import Mesher
from pinn_engine.quality import boundary_nodes, first_edges, folded_cells, grid_lines_angle
from pinn_engine.routes.algorithm import PinnMeshAlgorithm
from pinn_engine.routes.cli import main
from pinn_engine.settings import make_settings

BUMP = EXAMPLES / "bump_channel.vtp"  # channel of height 1, a smooth bump on the floor
H = 1e-3


@pytest.fixture(scope="module")
def bump():
    return load_boundary(BUMP)


def check_floor(result, boundary, h=H, angle=None, growth_limit=1.6):
    """First edges off the floor within 10 % of h (corners aside), monotone growth along
    every line leaving it, no fold, boundary nodes on the boundary."""
    grid = boundary.frame.to_unit(result.points)
    edges = np.linalg.norm(np.diff(grid, axis=0), axis=-1) * boundary.frame.scale
    assert np.all(np.abs(edges[0, 1:-1] / h - 1) <= 0.1), edges[0].min() / h
    growth = edges[1:] / edges[:-1]
    assert growth[: len(growth) // 2].min() > 1.0  # the lower half grows monotonically
    assert growth.max() < growth_limit
    assert not folded_cells(grid).any()
    assert boundary.deviation(boundary_nodes(grid)).max() < 1e-12
    if angle is not None:
        assert grid_lines_angle(grid)["bottom"][2:-2].max() <= angle
    return grid


def test_stretching_is_monotone_with_the_requested_end_spacings():
    for first, last in ((1e-3, None), (None, 1e-2), (1e-4, 1e-2), (0.05, 0.01), (1e-6, 1e-6)):
        s = stretch(
            41,
            None if first is None else np.array([first]),
            None if last is None else np.array([last]),
        )[0]
        d = np.diff(s)
        assert s[0] == 0 and s[-1] == 1 and (d > 0).all()
        if first is not None:  # Vinokur's end slopes: the first interval within a factor 1.5
            assert 0.66 < d[0] / first < 1.5
        if last is not None:
            assert 0.66 < d[-1] / last < 1.5
    np.testing.assert_array_equal(stretch(5, None, None)[0], np.linspace(0, 1, 5))
    np.testing.assert_array_equal(param_grid(6, 4, {}), uniform_params(6, 4))


def test_parameter_controls_keep_the_distribution_on_a_rectangle():
    """On a rectangle the stretched TFI grid is x(s, t) with s, t harmonic: the elliptic grid
    with the distribution's control functions is that grid (Spekreijse's formulation)."""
    ni, nj = 21, 15
    p = param_grid(ni, nj, {"bottom": np.full(ni, 2e-3), "left": np.full(nj, 1e-2)})
    grid = np.stack([3 * p[..., 0], p[..., 1]], axis=-1)
    shaken = grid.copy()
    shaken[1:-1, 1:-1] += 1e-3 * np.random.default_rng(0).normal(size=(nj - 2, ni - 2, 2))
    solved, _ = controlled_solve(grid, p, initial=shaken)
    np.testing.assert_allclose(solved, grid, atol=1e-9)


def test_tfi_first_edges_on_a_curved_floor(bump):
    result = Mesher(make_settings("tfi", spacing={"bottom": H})).fit(bump).predict(81, 41)
    check_floor(result, bump)
    floor = result.report["sides"]["bottom"]
    assert abs(floor["first_edge_median"] / H - 1) < 0.02
    assert result.report["sides"]["top"]["first_edge_median"] > 10 * H


@pytest.mark.slow  # a fine elliptic solve with spacing (about 2.5 s)
def test_elliptic_first_edges_and_orthogonality_on_a_curved_floor(bump):
    result = (
        Mesher(make_settings("elliptic", spacing={"bottom": H}, orthogonal="bottom"))
        .fit(bump)
        .predict(81, 41)
    )
    check_floor(result, bump, angle=2.0)
    assert result.report["sides"]["bottom"]["max_angle_deviation"] <= 2.0


def test_elliptic_orthogonal_without_spacing(bump):
    plain = Mesher(make_settings("elliptic")).fit(bump).predict(41, 21)
    ortho = Mesher(make_settings("elliptic", orthogonal="bottom")).fit(bump).predict(41, 21)
    assert plain.report["sides"]["bottom"]["max_angle_deviation"] > 10
    assert ortho.report["sides"]["bottom"]["max_angle_deviation"] <= 2.0
    assert ortho.quality["folded_cells"] == 0


def test_spacing_at_both_ends_of_both_directions_stays_conforming(bump):
    """Left/right spacing places the floor's and the roof's nodes too (the same xi)."""
    h = 2e-3
    spacing = {"bottom": H, "top": h, "left": h, "right": h}
    result = Mesher(make_settings("tfi", spacing=spacing)).fit(bump).predict(41, 31)
    grid = bump.frame.to_unit(result.points)
    edges = {k: v * bump.frame.scale for k, v in first_edges(grid).items()}
    for side, target in spacing.items():
        assert np.all(np.abs(edges[side][1:-1] / target - 1) <= 0.1), side
    # the first edge along the floor from each corner is the left/right spacing
    floor = np.linalg.norm(np.diff(grid[0], axis=0), axis=-1) * bump.frame.scale
    assert abs(floor[0] / h - 1) < 0.1 and abs(floor[-1] / h - 1) < 0.1
    assert bump.deviation(boundary_nodes(grid)).max() < 1e-12
    assert not folded_cells(grid).any()


def test_pinn_first_edges_and_orthogonality_without_folds(bump):
    settings = make_settings("pinn", lattice=(41, 21), spacing={"bottom": H}, orthogonal="bottom")
    result = Mesher(settings).fit(bump).predict(41, 21)
    check_floor(result, bump, angle=2.0, growth_limit=2.0)  # 20 cells from 1e-3 to 1
    assert result.report["training"]["start"] == "orthogonal"  # orthogonal.py


def test_pinn_on_a_steep_wall_and_saved_model(tmp_path):
    """A Gaussian bump 40 % of the height: the orthogonal start's first row is normal to the
    wall as the grid sees it; a saved model gives the same grid."""
    steep = load_boundary(EXAMPLES / "hard" / "bump.vtp")
    settings = make_settings(
        "pinn", lattice=(41, 21), spacing={"bottom": H}, orthogonal="bottom", lbfgs_iterations=20
    )
    mesher = Mesher(settings).fit(steep)
    result = mesher.predict(41, 21)
    check_floor(result, steep, angle=2.0, growth_limit=2.5)
    mesher.save(tmp_path / "m.pt")
    again = Mesher.load(tmp_path / "m.pt", steep).predict(41, 21)
    np.testing.assert_allclose(again.points, result.points, atol=1e-6)


def test_pinn_orthogonal_without_spacing(bump):
    settings = make_settings("pinn", lattice=(41, 21), orthogonal="bottom")
    result = Mesher(settings).fit(bump).predict(41, 21)
    assert result.report["sides"]["bottom"]["max_angle_deviation"] <= 2.0
    assert result.quality["folded_cells"] == 0


def test_pinn_orthogonal_on_every_side():
    """Four wavy sides, all orthogonal: within 2 degrees everywhere, no fold."""
    from pinn_engine.geometry.boundary import Boundary

    wavy = Boundary.from_points(wavy_ring(40))
    settings = make_settings(
        "pinn", lattice=(41, 21), orthogonal="bottom,right,top,left", lbfgs_iterations=20
    )
    result = Mesher(settings).fit(wavy).predict(41, 21)
    assert result.quality["folded_cells"] == 0
    for side in ("bottom", "right", "top", "left"):
        assert result.report["sides"][side]["max_angle_deviation"] <= 2.0, side


def test_settings_validation():
    s = make_settings("pinn", spacing="bottom=1e-3,top=0.01", orthogonal="left, bottom")
    assert s.spacing == (("bottom", 1e-3), ("top", 0.01))
    assert s.orthogonal == ("bottom", "left")
    assert make_settings("tfi", spacing={"left": 2}).spacing == (("left", 2.0),)
    for bad in ("floor=1", "bottom=-1", "bottom=nan", "bottom", ["bottom=1", "bottom=2"]):
        with pytest.raises(ValueError):
            make_settings("tfi", spacing=bad)
    with pytest.raises(ValueError, match="orthogonal"):
        make_settings("tfi", orthogonal="bottom")
    with pytest.raises(ValueError, match="unknown side"):
        make_settings("elliptic", orthogonal="roof")


def test_spacing_larger_than_the_domain_is_refused(bump):
    with pytest.raises(PinnMeshError, match="spacing bottom=0.9"):
        Mesher(make_settings("tfi", spacing={"bottom": 0.9})).fit(bump)


def test_cli_options_and_report(tmp_path, capsys):
    out, report = tmp_path / "g.vts", tmp_path / "r.json"
    code = main(
        [
            str(BUMP),
            "--method",
            "elliptic",
            "--size",
            "41",
            "21",
            "--spacing",
            "bottom=1e-3",
            "--orthogonal",
            "bottom",
            "-o",
            str(out),
            "--report",
            str(report),
        ]
    )
    assert code == 0
    err = capsys.readouterr().err
    assert "bottom: first edges" in err
    sides = json.loads(report.read_text())["sides"]
    assert set(sides) == {"bottom", "right", "top", "left"}
    assert abs(sides["bottom"]["first_edge_median"] / 1e-3 - 1) < 0.1
    assert sides["bottom"]["max_angle_deviation"] <= 2.0
    code = main([str(BUMP), "--method", "tfi", "--orthogonal", "bottom", "-o", str(out)])
    assert code == 2
    assert "orthogonal" in capsys.readouterr().err
    assert main([str(BUMP), "--method", "tfi", "--spacing", "bottom:1", "-o", str(out)]) == 2
    assert "SIDE=H" in capsys.readouterr().err


def test_accessor_and_filter_options():
    import pyvista as pv

    from pinn_engine.routes.pyvista_accessor import pinn_mesh

    boundary = pv.read(BUMP)
    grid = pinn_mesh(
        boundary, size=(41, 21), method="elliptic", spacing={"bottom": H}, orthogonal="bottom"
    )
    first = grid.field_data["FirstEdge_bottom"]
    assert len(first) == 3 and abs(first[1] / H - 1) < 0.1
    assert grid.field_data["WallAngleDeviation_bottom"][0] <= 2.0
    assert grid.field_data["GrowthRatio_bottom"][0] > 1.0
    again = boundary.pinn_mesh(size=(41, 21), method="tfi", spacing="bottom=0.001")
    assert abs(again.field_data["FirstEdge_bottom"][1] / H - 1) < 0.1

    alg = PinnMeshAlgorithm()
    alg.SetSpacing(H, 0, 0, 0)
    alg.SetOrthogonal(1, 0, 0, 0)
    s = alg.GetSettings()
    assert s.spacing == (("bottom", H),) and s.orthogonal == ("bottom",)
    alg.SetSpacing(0, 0, 0, 0)
    alg.SetOrthogonal(0, 0, 0, 0)
    assert alg.GetSettings().spacing == () and alg.GetSettings().orthogonal == ()
    alg.SetSpacing("left=0.01")
    assert alg.GetSpacing() == (("left", 0.01),)


def test_tfi_evaluated_at_uniform_parameters_is_the_tfi_grid(bump):
    from pinn_engine.classical.tfi import tfi_grid
    from pinn_engine.geometry.boundary_fit import ArcLengthFit

    np.testing.assert_allclose(
        tfi_at(bump)(uniform_params(9, 5)), tfi_grid(ArcLengthFit(bump).sample, 9, 5), atol=1e-15
    )
