"""The six-faced 3D routes: the VTK algorithm behind PINN Structured Mesh (Hexahedral)
and pyvista's ``surface.pinn_mesh(size=(ni, nj, nk))``."""

from __future__ import annotations

import json

import numpy as np
import pytest
import pyvista as pv
from helpers import ROOT, OutputMessages

from pinn_engine.errors import InputError
from pinn_engine.hexa.orthogonal import inner_angles
from pinn_engine.hexa.spacing import first_edges
from pinn_engine.io.export import BOX_SIDES
from pinn_engine.kinds.hexa.mesh import mesh_surface
from pinn_engine.routes.cli import main
from pinn_engine.routes.filters import folded_warning
from pinn_engine.routes.hexa_algorithm import PinnHexaAlgorithm, refold_hint
from pinn_engine.settings import HEXA_METHOD, HEXA_METHODS, make_settings

BEND = ROOT / "example_data" / "hexa_bend.vtp"
SIZE = (11, 9, 7)  # small and unequal: a swapped direction shows in the dimensions
PATCHES = {"imin": "inlet:inflow", "kmin": "floor:wall"}  # two faces named and typed
NAMED = ["inlet", "imax", "jmin", "jmax", "floor", "kmax"]  # PatchNames with PATCHES
TYPED = ["inflow", "patch", "patch", "patch", "wall", "patch"]  # PatchTypes with PATCHES
H = 0.01  # a first edge off the floor, well below half its shortest leaving edge


@pytest.fixture(scope="module")
def bend() -> pv.PolyData:
    return pv.read(BEND)


def _nodes(grid: pv.StructuredGrid) -> np.ndarray:
    """The grid's points as (ni, nj, nk, 3), as the engine holds them."""
    return np.asarray(grid.points).reshape(*grid.dimensions[::-1], 3).transpose(2, 1, 0, 3)


@pytest.mark.parametrize("method", HEXA_METHODS)
def test_accessor_gives_the_command_lines_grid(bend, method):
    grid = bend.pinn_mesh(size=SIZE, method=method)
    assert isinstance(grid, pv.StructuredGrid) and grid.dimensions == SIZE
    np.testing.assert_allclose(
        _nodes(grid), mesh_surface(str(BEND), make_settings(method, size=SIZE)).grid
    )
    for name in ("MaxIncludedAngle", "MinIncludedAngle", "ScaledJacobian", "Folded"):
        assert grid.cell_data[name].shape == (grid.n_cells,)
    assert grid.cell_data["Folded"].sum() == 0 and grid.cell_data["ScaledJacobian"].min() > 0.5
    np.testing.assert_allclose(  # VTK's own measure, on the grid as handed over
        grid.cell_data["ScaledJacobian"],
        grid.cell_quality("scaled_jacobian").cell_data["scaled_jacobian"],
    )
    assert list(grid.field_data["Method"]) == [method]
    assert list(grid.field_data["PatchNames"]) == list(BOX_SIDES)
    report = json.loads(grid.field_data["Report"][0])
    assert report["size"] == list(SIZE) and report["cells"] == grid.n_cells
    assert report["quality"]["min_scaled_jacobian"] == grid.cell_data["ScaledJacobian"].min()
    assert bend.pinn_mesh.last is grid


def test_faceid_chooses_the_3d_route_and_its_defaults(bend):
    grid = bend.pinn_mesh(size=(5, 5, 5))
    assert list(grid.field_data["Method"]) == [HEXA_METHOD]


@pytest.mark.parametrize(
    ("call", "error", "text"),
    [
        (
            lambda s: s.pinn_mesh(size=(2, 9, 7)),
            ValueError,
            "size=(2, 9, 7): each needs at least 3",
        ),
        (lambda s: s.pinn_mesh(size=(11, 9)), ValueError, "takes three sizes"),
        (lambda s: s.pinn_mesh(aux=s), InputError, "aux= applies to 2D domains"),
        (lambda s: s.pinn_mesh(cell_size=0.1), InputError, "cell_size= applies to 2D domains"),
        (lambda s: s.pinn_mesh(method="mgnet"), ValueError, "unknown method 'mgnet'"),
        (
            lambda s: pv.Sphere().pinn_mesh(size=(5, 5, 5)),
            InputError,
            "input: found 1 faces at edges sharper than 40 degrees; a six-faced domain needs 6 "
            "(try another face_angle= or a FaceId cell array)",
        ),
        (
            lambda s: s.pinn_mesh(size=SIZE, patches={"bottom": "wall"}),
            InputError,
            "SIDE one of imin, imax, jmin, jmax, kmin, kmax, face0, face1, face2, face3, face4, "
            'face5 (patches={"imin": "inlet", "face3": "wall", ...})',
        ),
        (
            lambda s: s.pinn_mesh(size=SIZE, method="tfi", orthogonal="kmin"),
            InputError,
            'orthogonal= kmin: use method="elliptic" or pinn',
        ),
    ],
)
def test_accessor_refuses_in_one_line(bend, call, error, text):
    with pytest.raises(error) as caught:
        call(bend)
    assert text in str(caught.value) and "\n" not in str(caught.value)


def test_algorithm_reports_once_in_the_panels_words_and_recovers(bend):
    alg = PinnHexaAlgorithm()
    with OutputMessages(alg, "ErrorEvent") as said:
        alg.SetGridSize(*SIZE)
        alg.SetInputDataObject(0, pv.Sphere())
        alg.Update()
        alg.Update()  # nothing changed: not said again
        assert alg.GetOutput().GetNumberOfPoints() == 0
        line = (
            "PINN Structured Mesh (Hexahedral): input: found 1 faces at edges sharper than 40 "
            "degrees; a six-faced domain needs 6 (try another Face Angle or a FaceId cell array)"
        )
        assert alg.GetLastError() == line
        assert said.lines == [line]
        alg.SetGridSize(2, 9, 7)
        alg.SetInputDataObject(0, bend)
        alg.Update()
        assert alg.GetLastError() == (
            "PINN Structured Mesh (Hexahedral): invalid settings: Grid Size 2 9 7: each needs at "
            "least 3 nodes"
        )
        alg.SetGridSize(*SIZE)
        alg.Update()
        assert alg.GetLastError() == "" and pv.wrap(alg.GetOutput()).dimensions == SIZE


def test_folded_warning_names_each_routes_fix():
    report = {"quality": {"folded_cells": 2}, "cells": 480, "method": "elliptic"}
    assert folded_warning(report, "paraview", refold_hint("paraview")) == (
        "2 of 480 cells are folded; try another Grid Size or a finer triangulation where the "
        "surface bends sharply (the cell array Folded marks the cells)"
    )
    tfi = {**report, "method": "tfi"}
    assert folded_warning(tfi, "pyvista", refold_hint("pyvista")).endswith('method="elliptic"')


def _first_edges_off_the_floor(nodes: np.ndarray) -> np.ndarray:
    """The first edges leaving kmin, its four corners aside (as the engine measures them)."""
    return first_edges(nodes, "kmin")[1:-1, 1:-1]


@pytest.mark.parametrize(
    ("method", "spacing", "orthogonal"),
    [("tfi", ("kmin=0.01", "imax=0.02"), ""), ("elliptic", (f"kmin={H}",), "kmin")],
)
def test_algorithm_takes_the_command_lines_patch_options(
    bend, tmp_path, method, spacing, orthogonal
):
    """Patch Names, First Edge Spacing and Orthogonal Patches give the grid and patches of
    the command line's --patch, --spacing and --orthogonal."""
    out = tmp_path / "g.vts"
    argv = [str(BEND), "--size", *map(str, SIZE), "--method", method, "--quiet", "-o", str(out)]
    argv += [w for side, name in PATCHES.items() for w in ("--patch", f"{side}={name}")]
    argv += [w for item in spacing for w in ("--spacing", item)]
    argv += ["--orthogonal", orthogonal] if orthogonal else []
    assert main(argv) == 0
    alg = PinnHexaAlgorithm()
    alg.SetInputDataObject(0, bend)
    alg.SetGridSize(*SIZE)
    alg.SetMethod(method)
    alg.SetPatchNames(" ".join(f"{side}={name}" for side, name in PATCHES.items()))
    alg.SetSpacing(" ".join(spacing))
    alg.SetOrthogonal(orthogonal)
    alg.Update()
    assert alg.GetLastError() == ""
    grid, expected = pv.wrap(alg.GetOutput()), pv.read(out)
    np.testing.assert_allclose(grid.points, expected.points, rtol=0, atol=1e-12)
    for field, values in (("PatchNames", NAMED), ("PatchTypes", TYPED)):
        assert list(grid.field_data[field]) == list(expected.field_data[field]) == values
    np.testing.assert_allclose(_first_edges_off_the_floor(_nodes(grid)), H, rtol=0.01)


@pytest.mark.parametrize(
    ("setter", "value", "line"),
    [
        (
            "SetPatchNames",
            "imin=inlet bottom=wall",
            "patch 'bottom=wall': expected SIDE=NAME with SIDE one of imin, imax, jmin, jmax, "
            "kmin, kmax, face0, face1, face2, face3, face4, face5 (Patch Names (imin imax jmin "
            "jmax kmin kmax, or SIDE=NAME or faceN=NAME))",
        ),
        (
            "SetPatchNames",
            "kmin=floor:hot",
            "patch type 'hot' of 'floor': use wall, inflow, outflow, farfield, symmetry, patch "
            "(Patch Names (imin imax jmin jmax kmin kmax, or SIDE=NAME or faceN=NAME))",
        ),
        (
            "SetSpacing",
            "floor=0.01",
            "First Edge Spacing floor=0.01: write PATCH=H with H > 0, PATCH one of imin, imax, "
            "jmin, jmax, kmin, kmax or faceN",
        ),
        (
            "SetSpacing",
            "kmin=0.9",
            "First Edge Spacing kmin=0.9: the first edge must be shorter than half of the "
            "shortest edge leaving kmin (0.4)",
        ),
        (
            "SetOrthogonal",
            "kmin",
            "Orthogonal Patches kmin: use Method elliptic or pinn (tfi's grid lines cannot turn "
            "to a patch's normal)",
        ),
    ],
)
def test_algorithm_refuses_patch_options_in_the_panels_words(bend, setter, value, line):
    alg = PinnHexaAlgorithm()
    alg.SetInputDataObject(0, bend)
    alg.SetGridSize(*SIZE)
    alg.SetMethod("tfi")
    with OutputMessages(alg, "ErrorEvent") as said:
        getattr(alg, setter)(value)
        alg.Update()
    assert said.lines == [f"PINN Structured Mesh (Hexahedral): {line}"] == [alg.GetLastError()]
    assert alg.GetOutput().GetNumberOfPoints() == 0
    getattr(alg, setter)("")  # the setting cleared: a grid again
    alg.Update()
    assert alg.GetLastError() == "" and pv.wrap(alg.GetOutput()).dimensions == SIZE


def test_accessor_patches_spacing_and_orthogonal_reach_the_grid(bend):
    grid = bend.pinn_mesh(
        size=SIZE, method="elliptic", patches=PATCHES, spacing={"kmin": H}, orthogonal=["kmin"]
    )
    assert list(grid.field_data["PatchNames"]) == NAMED
    assert list(grid.field_data["PatchTypes"]) == TYPED
    nodes = _nodes(grid)
    np.testing.assert_allclose(_first_edges_off_the_floor(nodes), H, rtol=0.01)
    assert inner_angles(nodes, "kmin").max() < 1.0  # degrees off the floor's normal
    walls = json.loads(grid.field_data["Report"][0])["walls"]  # what the panel can show
    assert list(walls) == ["kmin"]
    assert H * 0.99 <= walls["kmin"]["first_edge"]["min"] <= walls["kmin"]["first_edge"]["max"]
    assert walls["kmin"]["first_edge"]["max"] <= H * 1.01
    assert walls["kmin"]["max_angle_deviation"] < 1.0
    plain = bend.pinn_mesh(size=SIZE, method="elliptic")
    assert _first_edges_off_the_floor(_nodes(plain)).min() > 2 * H  # the spacing did it


def test_patch_settings_take_strings_sequences_and_mappings():
    alg = PinnHexaAlgorithm()
    assert alg.GetPatchNames() == BOX_SIDES
    alg.SetPatchNames(PATCHES)
    assert alg.GetPatchNames() == tuple(NAMED)
    alg.SetPatchNames(["a", "a", "b", "b", "c", "c"])  # six names, one a face
    assert alg.GetPatchNames() == ("a", "a", "b", "b", "c", "c")
    alg.SetSpacing({"kmin": 0.002})
    assert alg.GetSpacing() == ("kmin=0.002",)
    alg.SetOrthogonal("kmin,kmax")
    stamp = alg.GetMTime()
    alg.SetOrthogonal(["kmin", "kmax"])  # the same faces: no new update
    assert alg.GetOrthogonal() == ("kmin", "kmax") and alg.GetMTime() == stamp
    alg.SetSpacing(None)
    assert alg.GetSpacing() == ()
