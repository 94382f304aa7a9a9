"""Solver formats (SPEC 8): every writer read back by an independent reader.

Node coordinates are compared with the ``.vts`` of the same grid, read back by VTK; patch
names and sizes with the patches asked for. The readers are in ``export_checks``.
"""

from __future__ import annotations

import io
import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from export_checks import (
    EDGES,
    NI,
    NJ,
    PATCHES,
    T,
    check_cgns,
    check_gmsh,
    check_openfoam,
    check_plot3d,
    check_su2,
    read_su2,
    read_vts,
)
from helpers import EXAMPLES, OutputMessages, wavy_ring
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOLegacy import vtkStructuredGridReader
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLStructuredGridReader

from pinn_engine.errors import InputError
from pinn_engine.io import export
from pinn_engine.io.export.algorithm import GridWriter
from pinn_engine.routes.algorithm import PinnMeshAlgorithm
from pinn_engine.routes.cli import main
from pinn_engine.routes.pyvista_accessor import pinn_mesh, save_mesh


@pytest.fixture(scope="module")
def grid():
    return pinn_mesh(wavy_ring(), size=(NI, NJ), method="tfi", patches=PATCHES)


@pytest.fixture(scope="module")
def reference(grid, tmp_path_factory) -> np.ndarray:
    """The nodes (nj * ni, 3) as written to and read back from a .vts."""
    return read_vts(save_mesh(grid, tmp_path_factory.mktemp("vts") / "grid.vts"))


def test_grid_carries_patch_names_and_indices(grid):
    assert list(grid.field_data["PatchNames"]) == ["wall", "right", "wall", "inlet"]
    i, j = grid.point_data["i"], grid.point_data["j"]
    assert i.reshape(NJ, NI)[3].tolist() == list(range(NI))
    assert j.reshape(NJ, NI)[:, 5].tolist() == list(range(NJ))


@pytest.mark.parametrize("ext", ["vts", "vtk"])
def test_vtk_formats_keep_patches_and_indices(grid, reference, tmp_path, ext):
    path = save_mesh(grid, tmp_path / f"g.{ext}")
    reader = vtkXMLStructuredGridReader() if ext == "vts" else vtkStructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    out = reader.GetOutput()
    np.testing.assert_allclose(vtk_to_numpy(out.GetPoints().GetData()), reference, atol=1e-6)
    names = out.GetFieldData().GetAbstractArray("PatchNames")
    assert [names.GetValue(k) for k in range(4)] == ["wall", "right", "wall", "inlet"]
    assert vtk_to_numpy(out.GetPointData().GetArray("i")).max() == NI - 1


@pytest.mark.parametrize("thickness", [None, T])
def test_plot3d_read_by_vtk(grid, reference, tmp_path, thickness):
    check_plot3d(save_mesh(grid, tmp_path / "g.xyz", extrude=thickness), reference, thickness)


@pytest.mark.parametrize("thickness", [None, T])
def test_cgns_read_by_vtk_and_h5py(grid, reference, tmp_path, thickness):
    pytest.importorskip("h5py")
    check_cgns(save_mesh(grid, tmp_path / "g.cgns", extrude=thickness), reference, thickness)


def test_su2_parsed(grid, reference, tmp_path):
    check_su2(save_mesh(grid, tmp_path / "g.su2"), reference)


@pytest.mark.parametrize("thickness", [None, T])
def test_gmsh_read_by_gmsh(grid, reference, tmp_path, thickness):
    pytest.importorskip("gmsh")
    check_gmsh(save_mesh(grid, tmp_path / "g.msh", extrude=thickness), reference, thickness)


def test_openfoam_case(grid, reference, tmp_path):
    check_openfoam(save_mesh(grid, tmp_path / "case", "openfoam", extrude=T), reference)


def test_openfoam_into_an_existing_case_replaces_only_the_mesh(grid, tmp_path):
    case = tmp_path / "case"
    (case / "system").mkdir(parents=True)
    (case / "system" / "controlDict").write_text("// mine\n")
    (case / "0").mkdir()
    save_mesh(grid, case, "openfoam")
    save_mesh(grid, case, "openfoam", patches=["a", "b", "c", "d"])
    assert (case / "system" / "controlDict").read_text() == "// mine\n"
    assert (case / "0").is_dir() and (case / "system" / "fvSchemes").exists()
    assert "    d\n" in (case / "constant" / "polyMesh" / "boundary").read_text()
    assert sorted(p.name for p in (case / "constant").iterdir()) == ["polyMesh"]


@pytest.mark.parametrize("ext", ["xyz", "cgns", "su2", "msh", "vtk", "openfoam"])
def test_failing_writer_leaves_nothing(grid, tmp_path, monkeypatch, ext):
    def broken(block, path, *args):
        Path(path).write_text("partial")  # a write that stops half-way
        raise OSError("disk full")

    if ext == "openfoam":
        monkeypatch.setattr(
            export.openfoam, "write_polymesh", lambda block, mesh: broken(block, mesh / "points")
        )
        target, fmt = tmp_path / "case", "openfoam"
    elif ext == "vtk":
        monkeypatch.setattr(export.vtkfiles, "write_legacy", broken)
        target, fmt = tmp_path / "g.vtk", None
    else:
        monkeypatch.setitem(export.FORMATS, ext, replace(export.FORMATS[ext], block=broken))
        target, fmt = tmp_path / f"g.{ext}", None
    with pytest.raises(OSError, match="disk full"):
        save_mesh(grid, target, fmt)
    assert list(tmp_path.iterdir()) == []


def test_failing_openfoam_writer_keeps_the_previous_mesh(grid, tmp_path, monkeypatch):
    case = save_mesh(grid, tmp_path / "case", "openfoam")
    before = (case / "constant" / "polyMesh" / "points").read_text()

    def broken(block, mesh):
        (mesh / "points").write_text("partial")
        raise OSError("disk full")

    monkeypatch.setattr(export.openfoam, "write_polymesh", broken)
    with pytest.raises(OSError):
        save_mesh(grid, case, "openfoam", extrude=5.0)
    assert (case / "constant" / "polyMesh" / "points").read_text() == before
    assert sorted(p.name for p in (case / "constant").iterdir()) == ["polyMesh"]


def test_clockwise_or_line_grids_are_refused(grid, tmp_path):
    """(A 3D grid is a hexahedral one: tests/hexa/test_hexa_export.py.)"""
    import pyvista as pv

    flipped = pv.StructuredGrid(grid.x[::-1], grid.y[::-1], grid.z[::-1])  # i reversed
    with pytest.raises(InputError, match=r"^grid: the grid's boundary does not run counter"):
        save_mesh(flipped, tmp_path / "g.su2")
    with pytest.raises(InputError, match=r"expected a 2D structured grid"):
        save_mesh(pv.ImageData(dimensions=(3, 1, 1)).cast_to_structured_grid(), tmp_path / "g.msh")
    assert list(tmp_path.iterdir()) == []


def test_cli_writes_each_format_with_patches(tmp_path, capsys):
    boundary = str(EXAMPLES / "fig2.vtp")
    common = [
        boundary,
        "--method",
        "tfi",
        "--size",
        "9",
        "5",
        "--quiet",
        "--patch",
        "bottom=wall",
        "--patch",
        "top=wall",
    ]
    for out in ("g.su2", "g.msh", "g.xyz", "g.cgns", "g.vtk"):
        assert main([*common, "-o", str(tmp_path / out)]) == 0, capsys.readouterr().err
    assert main([*common, "--format", "openfoam", "-o", str(tmp_path / "case")]) == 0
    assert main([*common, "-o", str(tmp_path / "g3.msh"), "--extrude", "0.5"]) == 0
    assert set(read_su2(tmp_path / "g.su2")["markers"]) == {"wall", "right", "left"}
    assert (tmp_path / "case" / "constant" / "polyMesh" / "boundary").exists()


@pytest.mark.parametrize(
    "args, message",
    [
        (
            ["-o", "g.foo"],
            "g.foo: unknown output format '.foo'; use -o with .vts, .vtk, .xyz, "
            ".cgns, .su2 or .msh, or --format openfoam -o DIR",
        ),
        (
            ["-o", "g.su2", "--extrude", "1"],
            "g.su2: SU2 mesh with markers is 2D only; drop "
            "--extrude T (it applies to .xyz, .cgns, .msh and "
            "OpenFOAM)",
        ),
        (
            ["-o", "g.msh", "--extrude", "-1"],
            "g.msh: extrusion thickness -1.0: must be a number > 0 (--extrude T)",
        ),
        (
            ["-o", "g.msh", "--patch", "up=wall"],
            "patch 'up=wall': expected SIDE=NAME with SIDE "
            "one of bottom, right, top, left (--patch "
            "SIDE=NAME)",
        ),
        (
            ["-o", "g.msh", "--patch", "top=a b"],
            "patch name 'a b': use 1 to 32 letters, digits, '_' or '-' (--patch SIDE=NAME)",
        ),
    ],
)
def test_cli_errors_are_one_line_before_meshing(tmp_path, capsys, monkeypatch, args, message):
    monkeypatch.chdir(tmp_path)
    assert main([str(EXAMPLES / "fig2.vtp"), "--method", "tfi", *args]) == 2
    err = capsys.readouterr().err
    assert err == f"pinn-mesh: error: {message}\n"
    assert list(tmp_path.iterdir()) == []


def test_pyvista_accessor_save_and_route_words(tmp_path):
    import pyvista as pv

    boundary = pv.PolyData(
        np.column_stack([wavy_ring(), np.zeros(len(wavy_ring()))]),
        lines=[len(wavy_ring()) + 1, *range(len(wavy_ring())), 0],
    )
    with pytest.raises(InputError, match=r"no grid to save yet"):
        boundary.pinn_mesh.save(tmp_path / "g.su2")
    boundary.pinn_mesh(size=(NI, NJ), method="tfi", patches="wall right wall inlet")
    mesh = read_su2(boundary.pinn_mesh.save(tmp_path / "g.su2"))
    assert {n: len(e) for n, e in mesh["markers"].items()} == EDGES
    with pytest.raises(InputError, match=r"drop extrude= \(it applies"):
        boundary.pinn_mesh.save(tmp_path / "h.su2", extrude=1.0)
    with pytest.raises(InputError, match=r'format="openfoam"$'):
        boundary.pinn_mesh.save(tmp_path / "h.dat")
    with pytest.raises(InputError, match=r"\(patches=\{"):
        pinn_mesh(wavy_ring(), size=(5, 5), method="tfi", patches={"north": "x"})


def test_vtk_writer_algorithm_after_the_filter(tmp_path):
    """What ParaView's File > Save Data runs, in a plain VTK pipeline."""
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(EXAMPLES / "fig2.vtp"))
    alg = PinnMeshAlgorithm()
    alg.SetInputConnection(0, reader.GetOutputPort())
    alg.SetMethod("tfi")
    alg.SetGridSize(9, 5)
    alg.SetPatchNames("bottom=wall top=wall")
    writer = GridWriter("su2")
    writer.SetInputConnection(alg.GetOutputPort())
    writer.SetFileName(str(tmp_path / "g.su2"))
    assert writer.Write() == 1
    assert set(read_su2(tmp_path / "g.su2")["markers"]) == {"wall", "right", "left"}

    writer.SetExtrudeThickness(2.0)
    with OutputMessages(writer, "ErrorEvent") as messages:
        assert writer.Write() == 0
    assert messages.lines == [
        f"PINN Mesh writer: {tmp_path / 'g.su2'}: SU2 mesh with markers "
        "is 2D only; drop Extrude Thickness (it applies to .xyz, .cgns, "
        ".msh and OpenFOAM)"
    ]

    alg.SetPatchNames("wall wall")
    with OutputMessages(alg, "ErrorEvent") as messages:
        alg.Update()
    assert messages.lines == [
        "PINN Structured Mesh: patch names 'wall wall': give four names "
        "(bottom, right, top, left) or SIDE=NAME items (Patch Names "
        "(bottom right top left, or SIDE=NAME))"
    ]


def test_patch_types_reach_openfoam_and_cgns(tmp_path, capsys):
    """``--patch SIDE=NAME:TYPE`` types the patches (a patch named wall is a
    wall without one): OpenFOAM's wall, symmetryPlane and patch, CGNS's BCWall, BCInflow,
    BCOutflow, BCSymmetryPlane; the grid carries PatchTypes; a bad or a doubled type is a
    one-line error before meshing."""
    h5py = pytest.importorskip("h5py")
    common = [str(EXAMPLES / "fig2.vtp"), "--method", "tfi", "--size", "9", "5", "--quiet"]
    patches = ["--patch", "bottom=wall", "--patch", "top=lid:symmetry"]
    patches += ["--patch", "left=in:inflow", "--patch", "right=out:outflow"]
    assert main([*common, *patches, "--format", "openfoam", "-o", str(tmp_path / "case")]) == 0
    boundary = (tmp_path / "case" / "constant" / "polyMesh" / "boundary").read_text()
    kinds = dict(re.findall(r"(\w+)\s*\{\s*type\s+(\w+);", boundary))
    assert kinds == {
        "wall": "wall",
        "out": "patch",
        "lid": "symmetryPlane",
        "in": "patch",
        "frontAndBack": "empty",
    }
    assert main([*common, *patches, "-o", str(tmp_path / "g.cgns")]) == 0
    with h5py.File(tmp_path / "g.cgns", "r") as f:
        bc = {n: bytes(f[f"Base/{n}/FamilyBC/ data"][()]).decode() for n in kinds if n in f["Base"]}
    assert bc == {"wall": "BCWall", "out": "BCOutflow", "lid": "BCSymmetryPlane", "in": "BCInflow"}
    assert main([*common, *patches, "-o", str(tmp_path / "g.vts")]) == 0
    reader = vtkXMLStructuredGridReader()
    reader.SetFileName(str(tmp_path / "g.vts"))
    reader.Update()
    fd = reader.GetOutput().GetFieldData().GetAbstractArray("PatchTypes")
    assert [fd.GetValue(k) for k in range(4)] == ["wall", "outflow", "symmetry", "inflow"]
    capsys.readouterr()
    for bad, words in (
        ("top=lid:slip", "patch type 'slip' of 'lid'"),
        ("top=wall:inflow", "two types"),
    ):
        assert main([*common, "--patch", "bottom=wall:wall", "--patch", bad, "-o", "x.vts"]) == 2
        err = capsys.readouterr().err
        assert words in err and err.count("\n") == 1


def test_the_openfoam_writer_says_where_the_case_went(tmp_path):
    """Save Data as OpenFOAM makes a folder; the writer says which one
    (a text line in Output Messages, ``GetLastMessage()``); other formats say nothing."""
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(EXAMPLES / "fig2.vtp"))
    alg = PinnMeshAlgorithm()
    alg.SetInputConnection(0, reader.GetOutputPort())
    alg.SetMethod("tfi")
    alg.SetGridSize(9, 5)
    writer = GridWriter("openfoam")
    writer.SetInputConnection(alg.GetOutputPort())
    writer.SetFileName(str(tmp_path / "run1.foam"))
    assert writer.Write() == 1
    case = tmp_path / "run1"
    assert (case / "constant" / "polyMesh" / "boundary").exists()
    assert writer.GetLastMessage() == (
        f"PINN Mesh writer: wrote the OpenFOAM case {case} (mesh in "
        f"{case / 'constant' / 'polyMesh'}; open run1.foam)"
    )
    su2 = GridWriter("su2")
    su2.SetInputConnection(alg.GetOutputPort())
    su2.SetFileName(str(tmp_path / "g.su2"))
    assert su2.Write() == 1
    assert su2.GetLastMessage() == f"PINN Mesh writer: wrote {tmp_path / 'g.su2'} (SU2)"


def test_the_cgns_helper_python_is_the_checkouts_venv():
    """ParaView's Save Data writes CGNS through the checkout's .venv Python (its h5py):
    ``cgns.ROOT`` must be the checkout, the folder holding pyproject.toml."""
    from pinn_engine.io.export import cgns

    assert (cgns.ROOT / "pyproject.toml").is_file()


@pytest.mark.parametrize(
    ("rows", "fmt"),
    [
        (np.array([[0, 9, 10, 99], [100, 999_999, 1_000_000, 5]]), "4(%d %d %d %d)"),
        (np.random.default_rng(0).integers(0, 10**7, (70_000, 4)), "4(%d %d %d %d)"),
        (np.random.default_rng(1).integers(0, 2**40, (50, 2)), "%d  %d x"),
        (np.arange(12, dtype=np.uint32).reshape(4, 3), "9 %d %d %d"),
        (np.zeros((0, 4), dtype=int), "4(%d %d %d %d)"),
        (np.array([3, -1, 0]), "%d"),  # a negative number: the % path
        (np.array([[0.5, 1e-20, 3.0]]), "(%.17g %.17g %.17g)"),
    ],
)
def test_rows_are_written_as_percent_formatting_writes_them(rows, fmt):
    """The text writers' rows (polyMesh faces and labels, SU2 and Gmsh elements): integer
    rows laid out by array operations are the same text as ``%`` formats them."""
    from pinn_engine.io.export.text import write_rows

    out = io.StringIO()
    write_rows(out, rows, fmt)
    table = rows[:, None] if rows.ndim == 1 else rows
    assert out.getvalue() == "".join(fmt % tuple(row) + "\n" for row in table.tolist())
