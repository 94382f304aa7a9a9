"""Reading inputs, writing outputs, and the command line (SPEC 5), classical methods."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from helpers import CASES, EXAMPLES, square_ring
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLStructuredGridReader

from pinn_engine.io.fileio import read_boundary_points
from pinn_engine.io.pipeline import load_boundary
from pinn_engine.routes.cli import main


def read_vts(path: Path):
    reader = vtkXMLStructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    return reader.GetOutput()


def test_csv_and_vtp_give_the_same_boundary():
    a = read_boundary_points(EXAMPLES / "wavy.csv")  # x, y columns
    b = read_boundary_points(EXAMPLES / "wavy.vtp")  # x, y, z = 0
    np.testing.assert_allclose(a, b[:, :2], atol=1e-8)
    assert not b[:, 2].any()


def test_aux_lines_from_a_table_are_the_vtp_lines(tmp_path):
    """Auxiliary lines as a .csv table (x,y rows, a blank line between lines) read as the
    same polylines as the .vtp, and a table line of one point is a one-line error."""
    from pinn_engine.errors import InputError
    from pinn_engine.io.fileio import read_aux_lines

    drawn = read_aux_lines(EXAMPLES / "wavy_aux.vtp")
    table = tmp_path / "aux.csv"
    table.write_text(
        "x,y\n"
        + "\n\n".join("\n".join(f"{x:.17g},{y:.17g}" for x, y, *_ in r.points) for r in drawn)
    )
    read = read_aux_lines(table)
    assert len(read) == len(drawn) == 2
    for a, b in zip(read, drawn):
        np.testing.assert_array_equal(a.points, b.points[:, :2])
    table.write_text("0,0\n1,1\n\n2,2\n")
    with pytest.raises(InputError, match="line 1 has fewer than 2 points"):
        read_aux_lines(table)


def test_txt_with_whitespace_and_constant_z(tmp_path):
    ring = square_ring(3)
    path = tmp_path / "b.txt"
    np.savetxt(path, np.column_stack([ring, np.full(len(ring), 7.0)]))
    np.testing.assert_allclose(
        read_boundary_points(path), np.column_stack([ring, np.full(len(ring), 7.0)])
    )


def test_legacy_vtk_reads(tmp_path):
    from vtkmodules.vtkIOLegacy import vtkPolyDataWriter
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

    r = vtkXMLPolyDataReader()
    r.SetFileName(str(EXAMPLES / "fig2.vtp"))
    r.Update()
    w = vtkPolyDataWriter()
    w.SetFileName(str(tmp_path / "fig2.vtk"))
    w.SetInputData(r.GetOutput())
    w.Write()
    np.testing.assert_allclose(
        read_boundary_points(tmp_path / "fig2.vtk"), read_boundary_points(EXAMPLES / "fig2.vtp")
    )


# TFI folds the concave case (refused: test_tfi_folds_cells_on_the_concave_case_...)
@pytest.mark.parametrize(
    ("case", "method"),
    [(c, m) for m in ("tfi", "elliptic") for c in CASES if (c, m) != ("concave", "tfi")],
)
def test_cli_classical_methods_on_every_example(case, method, tmp_path, capsys):
    out = tmp_path / f"{case}_{method}.vts"
    report = tmp_path / "report.json"
    assert (
        main(
            [
                str(EXAMPLES / f"{case}.vtp"),
                "--aux",
                str(EXAMPLES / f"{case}_aux.vtp"),
                "--method",
                method,
                "-o",
                str(out),
                "--report",
                str(report),
            ]
        )
        == 0
    )
    assert f"wrote {out}" in capsys.readouterr().out
    grid = read_vts(out)
    assert grid.GetExtent() == (0, 40, 0, 20, 0, 0)
    q = json.loads(report.read_text())["quality"]
    assert q["boundary_deviation"] <= 1e-9
    if method == "elliptic":
        assert q["folded_cells"] == 0
    pts = vtk_to_numpy(grid.GetPoints().GetData())[:, :2].reshape(21, 41, 2)
    b = load_boundary(EXAMPLES / f"{case}.vtp")
    corners = b.frame.to_user(b.corner_points())
    np.testing.assert_allclose(
        [pts[0, 0], pts[0, -1], pts[-1, -1], pts[-1, 0]], corners, atol=1e-12 * b.frame.scale
    )
    cd = grid.GetCellData()
    assert cd.GetArray("MaxIncludedAngle").GetNumberOfTuples() == 40 * 20
    fd = grid.GetFieldData()
    assert fd.GetAbstractArray("Method").GetValue(0) == method
    assert json.loads(fd.GetAbstractArray("Report").GetValue(0))["quality"] == q


def test_tfi_folds_cells_on_the_concave_case_and_elliptic_does_not(tmp_path):
    """TFI's grid of the concave case folds cells: refused, nothing written; elliptic's
    is written with none."""
    codes, reports = {}, {}
    for method in ("tfi", "elliptic"):
        rep = tmp_path / f"{method}.json"
        out = tmp_path / f"{method}.vts"
        argv = [str(EXAMPLES / "concave.vtp"), "--method", method, "-o", str(out)]
        codes[method] = main([*argv, "--report", str(rep), "--quiet"])
        reports[method] = json.loads(rep.read_text())["quality"] if rep.exists() else None
    assert codes == {"tfi": 2, "elliptic": 0} and reports["tfi"] is None
    assert not (tmp_path / "tfi.vts").exists() and reports["elliptic"]["folded_cells"] == 0


def test_paper_elliptic_run_and_png(tmp_path):
    png = tmp_path / "grid.png"
    out = tmp_path / "g.vts"
    assert (
        main(
            [
                str(EXAMPLES / "fig2.vtp"),
                "--method",
                "elliptic",
                "--preset",
                "paper",
                "-o",
                str(out),
                "--png",
                str(png),
                "--quiet",
            ]
        )
        == 0
    )
    assert png.stat().st_size > 10_000 and png.read_bytes()[:4] == b"\x89PNG"
    report = json.loads(read_vts(out).GetFieldData().GetAbstractArray("Report").GetValue(0))
    assert report["settings"]["elliptic_iterations"] == 1000


def ring_file(tmp_path: Path, points, name="b.csv") -> Path:
    path = tmp_path / name
    np.savetxt(path, np.asarray(points), delimiter=",")
    return path


def bytes_file(path: Path, content: bytes) -> Path:
    path.write_bytes(content)
    return path


def open_polyline_vtp(tmp_path: Path) -> Path:
    from vtkmodules.vtkFiltersSources import vtkLineSource
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

    src = vtkLineSource()
    src.SetPoint1(0, 0, 0)
    src.SetPoint2(1, 1, 0)
    src.SetResolution(10)
    src.Update()
    w = vtkXMLPolyDataWriter()
    path = tmp_path / "open.vtp"
    w.SetFileName(str(path))
    w.SetInputData(src.GetOutput())
    w.Write()
    return path


BAD_INPUTS = {
    "missing file": (lambda d: d / "nope.vtp", "file not found"),
    "unknown format": (lambda d: ring_file(d, square_ring(3), "b.obj"), "unknown format"),
    "not an stl": (lambda d: ring_file(d, square_ring(3), "b.stl"), "not an STL file"),
    "empty file": (lambda d: bytes_file(d / "e.csv", b""), "empty"),
    "binary csv": (lambda d: bytes_file(d / "bin.csv", b"\x00\x01\x02garbage"), "binary"),
    "open polyline": (open_polyline_vtp, "open"),
    "fewer than four corners": (
        lambda d: ring_file(
            d, np.column_stack([np.cos(np.linspace(0, 6.2, 50)), np.sin(np.linspace(0, 6.2, 50))])
        ),
        "clear corners",
    ),
    "self-intersecting": (
        lambda d: ring_file(d, [[0, 0], [1, 1], [1, 0], [0, 1]]),
        "self-intersecting",
    ),
    "repeated point": (
        lambda d: ring_file(d, np.insert(square_ring(8), 20, square_ring(8)[5], axis=0)),
        "repeated|self-intersect",
    ),
    "non-finite": (
        lambda d: ring_file(d, np.where(np.arange(32)[:, None] == 3, np.nan, square_ring(8))),
        "not finite",
    ),
    "not planar": (
        lambda d: ring_file(d, np.column_stack([square_ring(3), np.arange(12.0)])),
        "is not planar",
    ),
}


@pytest.mark.parametrize("name", list(BAD_INPUTS))
def test_bad_boundary_gives_one_line_error_status_2_and_no_output(name, tmp_path, capsys):
    make, message = BAD_INPUTS[name]
    path = make(tmp_path)
    out = tmp_path / "out.vts"
    assert main([str(path), "--method", "tfi", "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("pinn-mesh: error: ")
    assert str(path) in err
    import re

    assert re.search(message, err), err
    assert not out.exists() and not list(tmp_path.glob("*.vts*"))


def test_aux_line_not_ending_on_opposite_sides(tmp_path, capsys):
    from vtkmodules.vtkFiltersSources import vtkLineSource
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

    src = vtkLineSource()
    src.SetPoint1(2.0, 0.0, 0)  # on the bottom of the wavy case
    src.SetPoint2(2.0, 1.0, 0)  # ends inside the domain
    src.Update()
    w = vtkXMLPolyDataWriter()
    w.SetFileName(str(tmp_path / "aux.vtp"))
    w.SetInputData(src.GetOutput())
    w.Write()
    out = tmp_path / "o.vts"
    assert (
        main(
            [
                str(EXAMPLES / "wavy.vtp"),
                "--aux",
                str(tmp_path / "aux.vtp"),
                "--method",
                "tfi",
                "-o",
                str(out),
            ]
        )
        == 2
    )
    err = capsys.readouterr().err
    assert "aux.vtp line 0" in err and "opposite sides" in err
    assert not out.exists()


def test_unknown_option_and_bad_size_exit_2(tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        main([str(EXAMPLES / "wavy.vtp"), "--frobnicate"])
    assert exc.value.code == 2
    assert (
        main(
            [
                str(EXAMPLES / "wavy.vtp"),
                "--method",
                "tfi",
                "--size",
                "1",
                "5",
                "-o",
                str(tmp_path / "o.vts"),
            ]
        )
        == 2
    )
    assert "--size" in capsys.readouterr().err


def test_cli_time_limit_writes_the_best_grid_with_a_warning(tmp_path, capsys):
    out = tmp_path / "fig2.vts"
    args = [str(EXAMPLES / "fig2.vtp"), "-o", str(out), "--size", "21", "11"]
    args += ["--epochs", "100000", "--lbfgs", "0", "--warm-start", "none"]
    assert main([*args, "--time-limit", "1", "--quiet"]) == 0
    assert out.exists()
    err = capsys.readouterr().err
    assert "warning" in err and "its time limit of 1 s ran out during adam" in err
    assert "a larger --time-limit (0: none)" in err
