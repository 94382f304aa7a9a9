"""First-cell spacing and orthogonal patches of six-faced 3D domains (SPEC 7 on SPEC 11's
patches): first edges within 10 % of H, grid lines within 2 degrees of the normal
on the curved bump floor, opposite and adjacent patches, no folds, the distribution's
control terms, and the command line's refusals."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import ROOT, refused

from pinn_engine.hexa import volume
from pinn_engine.hexa.spacing import node_params
from pinn_engine.kinds.hexa.mesh import mesh_surface
from pinn_engine.routes.cli import main
from pinn_engine.settings import make_settings

DATA = ROOT / "example_data"
BUMP, BEND = str(DATA / "hexa_bump_box.vtp"), str(DATA / "hexa_bend.vtp")
SIZE = (13, 11, 11)  # small, unequal
SPACING_TOL = 0.1  # SPEC 7: first edges within 10 % of H
ANGLE_TOL = 2.0  # SPEC 7: grid lines within 2 degrees of 90
RIM = 2  # SPEC 7: the two nodes nearest the patch's rim are excepted from the angles
AXIS = {"imin": (0, 0), "imax": (0, -1), "jmin": (1, 0), "jmax": (1, -1), "kmin": (2, 0)}


def _wall(g: np.ndarray, patch: str) -> tuple[np.ndarray, np.ndarray]:
    axis, end = AXIS[patch]
    moved = np.moveaxis(g, axis, 0)
    return moved[end], moved[1 if end == 0 else -2]


def _first_edge_ratios(g: np.ndarray, patch: str, h: float) -> np.ndarray:
    """First edge / H at the patch's nodes but its four corners."""
    wall, first = _wall(g, patch)
    ratio = np.linalg.norm(first - wall, axis=-1) / h
    ratio[[0, 0, -1, -1], [0, -1, 0, -1]] = 1.0
    return ratio


def _angle_deviation(g: np.ndarray, patch: str) -> float:
    """Largest deviation from 90 degrees between the first edge leaving a patch node and the
    patch's chords through the node's neighbours, the rim's two nodes aside."""
    wall, first = _wall(g, patch)
    na, nb = wall.shape[:2]
    edge = (first - wall)[RIM : na - RIM, RIM : nb - RIM]
    chords = (
        (wall[2:] - wall[:-2])[RIM - 1 : na - RIM - 1, RIM : nb - RIM],
        (wall[:, 2:] - wall[:, :-2])[RIM : na - RIM, RIM - 1 : nb - RIM - 1],
    )
    worst = 0.0
    for c in chords:
        cos = np.einsum("abk,abk->ab", c, edge) / (
            np.linalg.norm(c, axis=-1) * np.linalg.norm(edge, axis=-1)
        )
        worst = max(worst, float(np.abs(90.0 - np.degrees(np.arccos(cos))).max()))
    return worst


TRAINED = pytest.param("pinn", marks=pytest.mark.slow)  # the network trains: 2 to 3 s


@pytest.mark.parametrize("method", ["tfi", "elliptic", TRAINED])
def test_spacing_sets_the_first_edges_on_the_bump_floor(method):
    h = 0.005
    r = mesh_surface(BUMP, make_settings(method, size=SIZE, spacing={"kmin": h}))
    ratios = _first_edge_ratios(r.grid, "kmin", h)
    assert np.abs(ratios - 1.0).max() <= SPACING_TOL
    assert r.cells["Folded"].sum() == 0
    edges = np.linalg.norm(np.diff(r.grid, axis=2), axis=-1)
    assert (np.diff(edges, axis=2) > 0).all()  # growing away from the floor along k
    plain = mesh_surface(BUMP, make_settings(method, size=SIZE))
    assert np.median(_first_edge_ratios(plain.grid, "kmin", h)) > 2.0  # not by chance
    if method == "pinn":  # within 0.5 / 2 degrees of the spaced Winslow grid
        spaced = make_settings("elliptic", size=SIZE, spacing={"kmin": h})
        ref = mesh_surface(BUMP, spaced).cells["MaxIncludedAngle"]
        angles = r.cells["MaxIncludedAngle"]
        assert angles.mean() <= ref.mean() + 0.5 and angles.max() <= ref.max() + 2.0


@pytest.mark.parametrize("method", ["elliptic", TRAINED])
def test_orthogonal_floor_leaves_the_bump_along_its_normal(method):
    r = mesh_surface(
        BUMP, make_settings(method, size=SIZE, spacing={"kmin": 0.005}, orthogonal=("kmin",))
    )
    assert _angle_deviation(r.grid, "kmin") <= ANGLE_TOL
    assert np.abs(_first_edge_ratios(r.grid, "kmin", 0.005) - 1.0).max() <= SPACING_TOL
    assert r.cells["Folded"].sum() == 0
    plain = mesh_surface(BUMP, make_settings("elliptic", size=SIZE, spacing={"kmin": 0.005}))
    assert _angle_deviation(plain.grid, "kmin") > 10.0  # the bump's slopes: lines lean


def test_orthogonal_without_spacing_keeps_cells_unfolded():
    r = mesh_surface(BUMP, make_settings("elliptic", size=SIZE, orthogonal=("kmin",)))
    assert _angle_deviation(r.grid, "kmin") <= ANGLE_TOL
    assert r.cells["Folded"].sum() == 0


@pytest.mark.parametrize(
    "size, spacing, orthogonal",
    [
        # opposite (the two ends of the arc, lines 1.6 to 3.1 long: 2D's shared stretching
        # gives each its own first spacing over about six cells, so 21 nodes along i)
        ((21, 9, 9), {"imin": 0.01, "imax": 0.01}, ("imin", "imax")),
        (SIZE, {"jmin": 0.01}, ("jmin", "imin")),  # adjacent: they share an edge
    ],
)
def test_opposite_and_adjacent_patches_of_the_bend(size, spacing, orthogonal):
    r = mesh_surface(
        BEND, make_settings("elliptic", size=size, spacing=spacing, orthogonal=orthogonal)
    )
    for patch, h in spacing.items():
        assert np.abs(_first_edge_ratios(r.grid, patch, h) - 1.0).max() <= SPACING_TOL
    for patch in orthogonal:
        assert _angle_deviation(r.grid, patch) <= ANGLE_TOL
    assert r.cells["Folded"].sum() == 0


def test_control_terms_keep_a_stretched_box_grid():
    """On a box the grid at tensor-product stretched parameters solves the controlled
    Winslow equations (Spekreijse's construction is exact there); without the control terms
    it does not."""
    size = (9, 8, 7)
    params = node_params(size, {"kmin": np.full((9, 8), 0.01), "imax": np.full((8, 7), 0.03)})
    g = params * np.array([2.0, 1.0, 0.6])
    assert np.abs(volume.winslow_residual(g, params)).max() < 1e-12
    assert np.abs(volume.winslow_residual(g)).max() > 1e-4
    solved, _ = volume.winslow(volume.tfi(g, params), params=params)
    np.testing.assert_allclose(solved, g, atol=1e-8)


@pytest.mark.parametrize(
    "extra, words",
    [
        (["--spacing", "bottom=0.01"], "PATCH one of imin, imax, jmin, jmax, kmin, kmax"),
        (["--spacing", "kmin=0.5", "--method", "tfi"], "shorter than half of the shortest edge"),
        (["--spacing", "kmin=0.01", "--load-model", "m.pt"], "a saved map keeps the spacing"),
        (["--orthogonal", "kmin", "--load-model", "m.pt"], "a saved map keeps the spacing"),
        (["--orthogonal", "kmin,floor"], "unknown patch 'floor'"),
        (["--orthogonal", "kmin", "--method", "tfi"], "use --method elliptic"),
        (["--orthogonal", "kmin,kmax", "--size", "7", "7", "3", "--method", "elliptic"], "along k"),
    ],
)
def test_cli_refuses_bad_patch_options(tmp_path, capsys, extra, words):
    out = tmp_path / "g.vts"
    err = refused(capsys, [BUMP, "--size", "7", "7", "7", *extra, "-o", str(out)], out)
    assert words in err


def test_cli_spacing_and_orthogonal_write_and_report(tmp_path, capsys):
    out = tmp_path / "g.vts"
    argv = [BUMP, "--size", *map(str, SIZE), "--spacing", "kmin=0.005", "--orthogonal", "kmin"]
    argv += ["--method", "elliptic"]
    assert main([*argv, "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "kmin: first edges 0.005..0.005, grid lines within 0.00 deg of the normal" in text
    import pyvista as pv

    grid = pv.read(str(out))
    assert grid.dimensions == SIZE
    assert int(np.asarray(grid.cell_data["Folded"]).sum()) == 0
