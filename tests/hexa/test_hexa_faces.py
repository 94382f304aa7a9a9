"""A six-faced domain's faces by the input's own FaceId (SPEC 11, amended): corner 0's ties,
``--patch faceN=NAME`` on every route, and the summary line and report saying which input
face each of imin ... kmax is; the bend's patches checked against the OpenFOAM export's
faces, where they lie (the bend: radii 1 and 2, ends at y = 0 and x = 0, floor and top)."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest
import pyvista as pv
from export_checks import foam_list
from helpers import EXAMPLES

from pinn_engine.errors import InputError
from pinn_engine.hexa.block import first_corner
from pinn_engine.routes.cli import main
from pinn_engine.routes.hexa_algorithm import PinnHexaAlgorithm

BEND_STL, BEND = EXAMPLES / "hexa_bend.stl", EXAMPLES / "hexa_bend.vtp"
SIZE = ("5", "4", "3")
# make_hexa.py's faces of the bend: 0 inner wall, 1 outer, 2 the end at y = 0, 3 the end at
# x = 0, 4 floor, 5 top; where each lies (a function of the face centres that is zero there)
WHERE = {
    "inner": lambda c: np.hypot(c[:, 0], c[:, 1]) - 1.0,
    "outer": lambda c: np.hypot(c[:, 0], c[:, 1]) - 2.0,
    "inlet": lambda c: c[:, 1],
    "outlet": lambda c: c[:, 0],
    "walls": lambda c: c[:, 2] * (c[:, 2] - 0.8),
}
CHORD = 0.1  # a coarse face's centre is off the arc by its chord's sag (0.04); faces are 0.8 apart
NAMED = ["face0=inner:wall", "face1=outer:wall", "face2=inlet:inflow", "face3=outlet:outflow"]
NAMED += ["face4=walls:wall", "face5=walls:wall"]
# the sides the bend's faces are: corner 0 is (0, 1, 0), which ties (1, 0, 0) on x + y + z
BEND_SIDES = {"imin": 3, "imax": 2, "jmin": 0, "jmax": 1, "kmin": 4, "kmax": 5}


def test_corner_zero_ties_go_to_the_smallest_x_then_y_then_z():
    points = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [5, 5, 5.0]])
    assert first_corner(points, [0, 1, 2, 3]) == 2  # x + y + z ties, then x and y, z
    points[2, 2] += 1e-3  # no longer a tie: (0, 1, 0) has the smallest x of the other two
    assert first_corner(points, [0, 1, 2, 3]) == 1
    points[1] += [1e-9, 0, 0]  # within 1e-6 of the diagonal: still a tie, y decides
    assert first_corner(points, [0, 1, 2]) == 1


def _patch_centres(case) -> dict[str, np.ndarray]:
    """Patch name -> the centres of its boundary faces in an OpenFOAM case."""
    mesh = case / "constant" / "polyMesh"
    points = np.array([ln.strip("()").split() for ln in foam_list(mesh / "points")], float)
    faces = [list(map(int, ln[2:-1].split())) for ln in foam_list(mesh / "faces")]
    boundary = (mesh / "boundary").read_text()
    found = re.findall(r"(\w+)\s*\{[^}]*?nFaces\s+(\d+);\s*startFace\s+(\d+);", boundary)
    return {
        name: np.array([points[f].mean(axis=0) for f in faces[int(s) : int(s) + int(n)]])
        for name, n, s in found
    }


def test_the_bend_example_names_the_faces_it_drew(tmp_path, capsys):
    case, report = tmp_path / "case", tmp_path / "run.json"
    argv = [str(BEND_STL), "--method", "tfi", "--size", *SIZE, "--format", "openfoam"]
    argv += ["-o", str(case), "--report", str(report)]
    assert main([*argv, *(f"--patch={item}" for item in NAMED)]) == 0
    line = capsys.readouterr().out
    assert "faces face0=jmin face1=jmax face2=imax face3=imin face4=kmin face5=kmax" in line
    assert json.loads(report.read_text())["faces"] == BEND_SIDES
    centres = _patch_centres(case)
    assert sorted(centres) == sorted(WHERE)
    for name, off in WHERE.items():
        np.testing.assert_allclose(off(centres[name]), 0.0, atol=CHORD, err_msg=name)


def test_an_stl_numbers_its_faces_by_their_first_triangle(tmp_path, capsys):
    tagged = pv.read(BEND).triangulate()
    ids = np.asarray(tagged.cell_data["FaceId"])
    triangles = tagged.regular_faces[::-1]  # the last triangle first
    reversed_stl = tmp_path / "reversed.stl"
    pv.PolyData.from_regular_faces(tagged.points, triangles).save(reversed_stl)
    out = tmp_path / "g.vts"
    assert main([str(reversed_stl), "--method", "tfi", "--size", *SIZE, "-o", str(out)]) == 0
    listed = re.search(r"faces ((?:face\d=\w+ ?)+)", capsys.readouterr().out).group(1).split()
    order = dict(item.split("=") for item in listed)
    assert list(order) == [f"face{n}" for n in range(6)]
    # face0 is the face of the file's first triangle: the tagged bend's last
    assert BEND_SIDES[order["face0"]] == ids[-1]


@pytest.mark.parametrize("route", ["pyvista", "filter"])
def test_face_names_on_pyvista_and_the_filter(route):
    patches = {"face0": "inner:wall", "face4": "floor", "imin": "outlet"}
    expected = ["outlet", "imax", "inner", "jmax", "floor", "kmax"]
    surface = pv.read(BEND)
    if route == "pyvista":
        grid = surface.pinn_mesh(size=(5, 4, 3), method="tfi", patches=patches)
    else:
        alg = PinnHexaAlgorithm(route="pyvista")
        alg.SetInputDataObject(0, surface)
        alg.SetMethod("tfi")
        alg.SetGridSize(5, 4, 3)
        alg.SetPatchNames("face0=inner:wall face4=floor imin=outlet")
        alg.Update()
        assert alg.GetPatchNames() == tuple(expected)
        grid = pv.wrap(alg.GetOutput())
    assert list(grid.field_data["PatchNames"]) == expected
    assert list(grid.field_data["PatchTypes"])[2] == "wall"
    assert list(grid.field_data["FaceIds"]) == list(BEND_SIDES.values())


def test_an_unknown_face_is_refused_in_each_routes_words(tmp_path, capsys):
    out = tmp_path / "g.vts"
    argv = [str(BEND), "--method", "tfi", "--size", *SIZE, "-o", str(out)]
    assert main([*argv, "--patch", "face9=wall"]) == 2
    err = capsys.readouterr().err.strip()
    assert "face0, face1" in err and "faceN=NAME" in err and "\n" not in err
    assert not out.exists()
    with pytest.raises(InputError, match=r"face5 \(patches="):
        pv.read(BEND).pinn_mesh(size=(5, 4, 3), method="tfi", patches={"face7": "wall"})


def test_spacing_and_orthogonal_take_faces_by_their_faceid(tmp_path, capsys):
    """``--spacing face3=H --orthogonal face3`` act on the side the input's face 3 became
    (the bend's end at x = 0, imin): the grid of ``imin=H``; a face the surface lacks is
    one line naming its faces."""
    grids = []
    for name in ("face3", "imin"):
        out = tmp_path / f"{name}.vts"
        argv = [str(BEND), "--method", "elliptic", "--size", *SIZE, "-o", str(out), "--quiet"]
        assert main([*argv, "--spacing", f"{name}=0.05", "--orthogonal", name]) == 0
        grids.append(pv.read(out).points)
    np.testing.assert_array_equal(grids[0], grids[1])
    out = tmp_path / "g.vts"
    argv = [str(BEND), "--method", "tfi", "--size", *SIZE, "-o", str(out)]
    assert main([*argv, "--spacing", "face9=0.05"]) == 2
    err = capsys.readouterr().err.strip()
    assert "--spacing face9: the surface has no face9 (its faces: face0, face1" in err
    assert "\n" not in err and not out.exists()
