"""O- and C-grids through the routes (SPEC 9): the command line's grids, reports and one-line
errors, pyvista's accessor, an airfoil meshed as a four-sided domain told its topology."""

from __future__ import annotations

import json

import numpy as np
import pytest
from helpers import write_selig
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLStructuredGridReader

from pinn_engine.bodies.airfoil import load_body, naca4
from pinn_engine.errors import InputError
from pinn_engine.routes.cli import main


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
    dat = write_selig(tmp_path / "foil.dat", naca4("2412", points=61))
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
    dat = write_selig(tmp_path / "f.dat", xy)
    g = pinn_mesh(str(dat), topology="c", size=(121, 21), method="tfi")
    assert g.n_cells == 120 * 20
    with pytest.raises(ValueError, match="topology 'x': use none, o, c"):
        pinn_mesh(None, naca="0012", topology="x", size=(41, 17))


@pytest.mark.parametrize("gap, sharp", [(1e-5, True), (1e-4, True), (1e-3, False)])
def test_a_trailing_edge_open_by_at_most_1e4_chord_is_sharp(tmp_path, capsys, gap, sharp):
    """SPEC 9: a .dat whose trailing edge is open by 1e-5 chord, as many
    public files are, gets a C-grid, closed at the mean point of its two ends; 1e-3 is a
    drawn base, kept as wall: both its corners are nodes of the wall row."""
    xy = naca4("0012", points=81)
    xy[0, 1] += gap / 2
    xy[-1, 1] -= gap / 2
    dat = write_selig(tmp_path / "gap.dat", xy)
    body = load_body(dat)
    assert body.sharp == sharp
    if sharp:
        np.testing.assert_allclose(body.surface[0], [1.0, 0.0], atol=1e-7)
    out = tmp_path / "c.vts"
    argv = [str(dat), "--topology", "c", "--method", "elliptic", "--size", "121", "21"]
    rc = main([*argv, "-o", str(out), "--quiet"])
    assert rc == 0, capsys.readouterr().err
    points = vtk_to_numpy(_read(out).GetPoints().GetData())
    wall = points[:121, :2]
    for corner in body.surface[[0, -1]]:
        assert np.min(np.linalg.norm(wall - corner, axis=1)) < 1e-9


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
