"""Bad inputs, failing training, interruption and damaged models.

Every row of the robustness table (docs/robustness.md) names the test here that backs it.
Error rows run the command in-process and check: exit status 2, one ``pinn-mesh: error:``
line that names the file and the problem, and no output file (complete or partial).
"""

from __future__ import annotations

import json
import math
import os
import re
import signal
import subprocess
import sys
import sysconfig
import time
from pathlib import Path

import numpy as np
import pytest
from helpers import EXAMPLES, square_ring, wavy_ring
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter, vtkXMLStructuredGridReader

from pinn_engine.errors import InputError, TrainingError
from pinn_engine.geometry.boundary import Boundary
from pinn_engine.io import childread, fileio
from pinn_engine.io.pipeline import load_boundary
from pinn_engine.kinds.four_sided.mesher import Mesher
from pinn_engine.routes.cli import main
from pinn_engine.settings import make_settings

# the command as installed into the environment running the tests (its console script)
PINN_MESH = Path(sysconfig.get_path("scripts")) / "pinn-mesh"


# ---------------------------------------------------------------- helpers


def csv(path: Path, points, header: str | None = None) -> Path:
    rows = [",".join(repr(float(v)) for v in row) for row in np.asarray(points, dtype=float)]
    path.write_text("\n".join(([header] if header else []) + rows) + "\n")
    return path


def polydata(points, lines=(), polys=(), arrays=None) -> vtkPolyData:
    points = np.asarray(points, dtype=float)
    if points.shape[1] == 2:
        points = np.column_stack([points, np.zeros(len(points))])
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(points), deep=True))
    poly = vtkPolyData()
    poly.SetPoints(pts)
    for cells_of, setter in ((lines, poly.SetLines), (polys, poly.SetPolys)):
        if cells_of:
            cells = vtkCellArray()
            for ids in cells_of:
                cells.InsertNextCell(len(ids), list(ids))
            setter(cells)
    for name, values in (arrays or {}).items():
        arr = numpy_to_vtk(np.ascontiguousarray(values, dtype=float), deep=True)
        arr.SetName(name)
        poly.GetPointData().AddArray(arr)
    return poly


def vtp(path: Path, poly: vtkPolyData) -> Path:
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(str(path))
    writer.SetInputData(poly)
    writer.Write()
    return path


def aux_file(path: Path, *lines) -> Path:
    """Auxiliary polylines (each a list of points) in one ``.vtp``."""
    pts = np.vstack([np.asarray(line, dtype=float) for line in lines])
    ids, start = [], 0
    for line in lines:
        ids.append(range(start, start + len(line)))
        start += len(line)
    return vtp(path, polydata(pts, lines=ids))


def put(path: Path, data: bytes | str) -> Path:
    """Write ``data`` to ``path`` and return the path."""
    if isinstance(data, str):
        data = data.encode()
    path.write_bytes(data)
    return path


def run_cli(argv: list[str], capsys) -> tuple[int, str, str]:
    rc = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return rc, captured.out, captured.err


def assert_clean_error(rc: int, err: str, folder: Path, pattern: str, names: str | None):
    assert rc == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("pinn-mesh: error: "), err
    assert re.search(pattern, lines[0]), lines[0]
    if names:
        assert names in lines[0], lines[0]
    assert not list(folder.glob("**/*.vts")) and not list(folder.glob("**/*.part*"))


def grid_points(path: Path) -> np.ndarray:
    reader = vtkXMLStructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutput()
    ni, nj = (
        grid.GetDimensions()[:2] if False else (grid.GetExtent()[1] + 1, grid.GetExtent()[3] + 1)
    )
    return vtk_to_numpy(grid.GetPoints().GetData())[:, :2].reshape(nj, ni, 2)


def tfi(points, corners=None) -> np.ndarray:
    b = Boundary.from_points(np.asarray(points, dtype=float), corners)
    return Mesher(make_settings("tfi")).fit(b).predict(11, 7).points


# ---------------------------------------------------------------- boundary files: errors


def ring_with(points_fn):
    return lambda d: csv(d / "b.csv", points_fn())


def _nan_point():
    ring = square_ring(4)
    ring[5, 0] = np.nan
    return ring


def _inf_point():
    ring = square_ring(4)
    ring[2, 1] = np.inf
    return ring


def _near_180_corner():
    # a triangle with a fourth "corner" whose interior angle is 178.6 degrees
    return [[0, 0], [2, 0], [1, 1.5], [0.5, 0.77]]


def _ambiguous_corners():
    # five vertices turn by 90, 90, 90, 45, 45 degrees: which four are the corners?
    return [[0, 0], [1, 0], [1.5, 0.5], [1.5, 1], [0, 1]]


def _repeated_point():
    ring = square_ring(8)
    return np.insert(ring, 20, ring[5], axis=0)


def _spike():
    return [[0, 0], [1, 0], [1, 1], [0.5, 1], [0.5, 1.5], [0.5, 1.0 + 1e-3], [0, 1]]


def _tiny_far_away():
    return square_ring(3) * 1e-7 + 1e8  # 1e8 has an ulp of 1.5e-8: 7 steps across


def _write_z(d, z):
    ring = square_ring(3)
    np.savetxt(d / "b.csv", np.column_stack([ring, z(len(ring))]), delimiter=",")
    return d / "b.csv"


def _damaged_vtp(d):
    data = (EXAMPLES / "wavy.vtp").read_bytes()
    (d / "b.vtp").write_bytes(data[: len(data) // 2])
    return d / "b.vtp"


def _two_curves(d):
    a, b = square_ring(2), square_ring(2) + 3
    pts = np.vstack([a, b])
    return vtp(d / "b.vtp", polydata(pts, polys=[range(8), range(8, 16)]))


def _open_polyline(d):
    ring = square_ring(3)
    return vtp(d / "b.vtp", polydata(ring, lines=[range(len(ring))]))


BAD_BOUNDARIES = {
    # name: (make the file in folder d, expected message regex)
    "missing file": (lambda d: d / "nope.csv", "file not found"),
    "unknown format": (lambda d: csv(d / "b.obj", square_ring(3)), "unknown format '.obj'"),
    "text named .stl": (lambda d: csv(d / "b.stl", square_ring(3)), "not an STL file"),
    "no extension": (lambda d: csv(d / "boundary", square_ring(3)), "unknown format"),
    "directory": (lambda d: (d / "dir.csv").mkdir() or d / "dir.csv", "is a directory"),
    "empty file": (lambda d: put(d / "e.csv", b""), "file is empty"),
    "binary file named .csv": (lambda d: put(d / "b.csv", bytes(range(256)) * 4), "binary"),
    "not UTF-8 text": (lambda d: put(d / "b.csv", b"0,0\n\xff\xfe,1\n"), "not UTF-8"),
    "text that is not numbers": (
        lambda d: put(d / "b.csv", "x,y\n0,0\n1,zero\n"),
        "line 3 is not numeric",
    ),
    "wrong number of columns": (lambda d: put(d / "b.csv", "0,0\n1,0,0,0\n"), "4 columns"),
    "damaged .vtp": (_damaged_vtp, "damaged or unreadable"),
    "not a VTK file named .vtp": (lambda d: put(d / "b.vtp", "hello"), "not a VTK XML"),
    "open polyline": (_open_polyline, "open"),
    "several curves": (_two_curves, "2 separate curves"),
    "too few points": (ring_with(lambda: [[0, 0], [1, 0], [0, 1]]), "needs at least 4"),
    "all points the same": (ring_with(lambda: [[1, 1]] * 6), "all coincide"),
    "all points on a line": (
        ring_with(lambda: [[0, 0], [1, 0], [2, 0], [3, 0]]),
        "doubles back|no area",
    ),
    "NaN point": (ring_with(_nan_point), "point 5 is not finite"),
    "infinite point": (ring_with(_inf_point), "point 2 is not finite"),
    "huge coordinates": (ring_with(lambda: square_ring(3) * 1e300), "beyond"),
    "tiny domain far from the origin": (ring_with(_tiny_far_away), "significant digits"),
    "fewer than four clear corners": (
        ring_with(
            lambda: np.column_stack(
                [np.cos(np.linspace(0, 6.2, 40)), np.sin(np.linspace(0, 6.2, 40))]
            )
        ),
        "fewer than four clear corners.*--corners",
    ),
    "corner angle near 180 degrees": (
        ring_with(_near_180_corner),
        "4th-largest turn is below 20.*1.4 at point 3",
    ),
    "nearly collinear corners (ambiguous)": (
        ring_with(_ambiguous_corners),
        "5th-largest turn is close to the 4th",
    ),
    "self-intersecting": (ring_with(lambda: [[0, 0], [1, 1], [1, 0], [0, 1]]), "self-intersecting"),
    "repeated point": (ring_with(_repeated_point), "repeated further along"),
    "zero-width spike": (ring_with(_spike), "doubles back|self-intersecting"),
    "not planar": (
        lambda d: _write_z(d, lambda n: np.arange(n, dtype=float)),
        "is not planar: its points lie up to .* off their best-fit plane",
    ),
    "NaN z": (
        lambda d: _write_z(d, lambda n: np.where(np.arange(n) == 2, np.nan, 0.0)),
        "point 2 has a non-finite z",
    ),
}


@pytest.mark.parametrize("name", list(BAD_BOUNDARIES))
def test_bad_boundary_is_a_clear_error(name, tmp_path, capsys):
    make, pattern = BAD_BOUNDARIES[name]
    path = make(tmp_path)
    rc, _, err = run_cli([path, "--method", "tfi", "-o", tmp_path / "out" / "g.vts"], capsys)
    assert_clean_error(rc, err, tmp_path, pattern, str(path))


def test_too_many_points_is_a_clear_error(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(fileio, "MAX_POINTS", 100)
    path = csv(tmp_path / "b.csv", square_ring(30))
    rc, _, err = run_cli([path, "--method", "tfi", "-o", tmp_path / "g.vts"], capsys)
    assert_clean_error(rc, err, tmp_path, "more than 100 rows", str(path))


def test_vtk_reader_crash_is_a_clear_error_not_a_crash(tmp_path, capsys):
    """A damaged file that makes VTK's reader abort (``std::bad_alloc`` on a huge point
    count) is read in a child process: a clear error, and this process lives on."""
    text = (EXAMPLES / "wavy.vtp").read_text()
    damaged = tmp_path / "wavy.vtp"
    damaged.write_text(text.replace('NumberOfPoints="240"', 'NumberOfPoints="999999999999"'))
    rc, _, err = run_cli([damaged, "--method", "tfi", "-o", tmp_path / "g.vts"], capsys)
    # VTK 9.7 aborts; a VTK that refuses the count itself gives its own message
    pattern = r"is damaged or unreadable \((VTK's reader crashed \(SIGABRT\) on it|VTK: .+)\)"
    assert_clean_error(rc, err, tmp_path, pattern, "wavy.vtp")


@pytest.mark.skipif(os.name == "nt", reason="POSIX signals")
def test_a_crash_of_the_reading_child_is_named(tmp_path, capsys, monkeypatch):
    """Whatever kills the reading child is named in the error; the file is not read here."""
    code = "import os, sys; sys.stdout.write('reading\\n'); sys.stdout.flush(); os.abort()"
    monkeypatch.setattr(childread, "_CHILD_CODE", code)
    monkeypatch.setattr(childread, "_READ", childread.OrderedDict())
    rc, _, err = run_cli(
        [EXAMPLES / "wavy.vtp", "--method", "tfi", "-o", tmp_path / "g.vts"], capsys
    )
    assert_clean_error(rc, err, tmp_path, r"VTK's reader crashed \(SIGABRT\) on it", "wavy.vtp")


def test_a_refused_run_leaves_no_reading_child_for_the_next(tmp_path, capsys, monkeypatch):
    """A run refused before it reads its files ends the child that started reading them: the
    next run in this process (a notebook, the test session) reads by a child of its own."""
    monkeypatch.setattr(childread, "_READ", childread.OrderedDict())
    refused = [EXAMPLES / "wavy.vtp", "--adapt", "field.vti", "-o", tmp_path / "a.vts"]
    assert run_cli(refused, capsys)[0] == 2
    assert childread._PENDING == []
    test_a_crash_of_the_reading_child_is_named(tmp_path, capsys, monkeypatch)


def test_files_are_read_and_written_without_forking(tmp_path, monkeypatch):
    """No fork of this process (it may run threads: ParaView, a notebook, torch): VTK files
    are read by a new Python, the grid is written here."""
    import multiprocessing

    def no_fork(*args, **kwargs):
        raise AssertionError("forked")

    monkeypatch.setattr(os, "fork", no_fork)
    monkeypatch.setattr(multiprocessing, "get_context", no_fork)
    monkeypatch.setattr(childread, "_READ", childread.OrderedDict())
    started = []
    real_popen = childread.subprocess.Popen

    def counting_popen(command, **kwargs):
        started.append(command)
        return real_popen(command, **kwargs)

    monkeypatch.setattr(childread.subprocess, "Popen", counting_popen)
    ring = fileio.read_boundary_points(EXAMPLES / "wavy.vtp")
    assert len(started) == 1 and started[0][0] == sys.executable
    fileio.read_boundary_points(EXAMPLES / "wavy.vtp")  # the same content: read once
    assert len(started) == 1
    from vtkmodules.vtkIOLegacy import vtkPolyDataWriter

    for binary in (False, True):
        legacy = tmp_path / f"ring{int(binary)}.vtk"
        writer = vtkPolyDataWriter()
        writer.SetFileName(str(legacy))
        writer.SetInputData(polydata(ring, lines=[list(range(len(ring))) + [0]]))
        if binary:
            writer.SetFileTypeToBinary()
        writer.Write()
        np.testing.assert_allclose(fileio.read_boundary_points(legacy), ring, atol=1e-9)
        assert len(started) == 2 + binary
    from pinn_engine.io.pipeline import to_vtk

    result = Mesher(make_settings("tfi")).fit(load_boundary(EXAMPLES / "wavy.vtp")).predict(5, 4)
    fileio.write_vts(to_vtk(result), tmp_path / "g.vts")
    assert grid_points(tmp_path / "g.vts").shape == (4, 5, 2)


# ---------------------------------------------------------------- boundary files: repairs


def test_duplicated_consecutive_points_are_dropped(tmp_path):
    ring = square_ring(6)
    doubled = np.repeat(ring, 2, axis=0)
    near = ring.copy()
    near = np.insert(near, 7, near[7] + 3e-9, axis=0)  # closer than 1e-7 of the diagonal
    closed = np.vstack([ring, ring[:1]])
    reference = tfi(ring)
    for variant in (doubled, near, closed):
        np.testing.assert_allclose(tfi(variant), reference, atol=1e-12)


def test_micro_segments_are_merged_and_do_not_make_corners():
    ring = wavy_ring()
    rng = np.random.default_rng(0)
    noisy = ring.copy()
    for k in (5, 30, 24, 60):  # mid-side and at a corner (24): 1e-9 steps in random directions
        noisy = np.insert(noisy, k + 1, noisy[k] + rng.normal(0, 1e-9, 2), axis=0)
    b = Boundary.from_points(noisy)
    assert len(b.ring) == len(ring)
    np.testing.assert_allclose(tfi(noisy), tfi(ring), atol=1e-12)


def test_named_corners_survive_merging_of_their_duplicates():
    ring = square_ring(4)
    doubled = np.repeat(ring, 2, axis=0)  # each point twice; name the second copies
    b = Boundary.from_points(doubled, (1, 9, 17, 25))
    np.testing.assert_allclose(
        b.frame.to_user(b.corner_points()), [[0, 0], [1, 0], [1, 1], [0, 1]], atol=1e-12
    )
    with pytest.raises(InputError, match="named corners 0 and 1 are the same point"):
        Boundary.from_points(doubled, (0, 1, 17, 25))


def test_clockwise_ring_and_any_start_give_the_same_grid():
    ring = wavy_ring()
    reference = tfi(ring)
    for variant in (ring[::-1], np.roll(ring, 17, axis=0), np.roll(ring[::-1], 5, axis=0)):
        np.testing.assert_allclose(tfi(variant), reference, atol=1e-12)


def test_corner_near_180_degrees_meshes_when_named(tmp_path, capsys):
    path = csv(tmp_path / "b.csv", _near_180_corner())
    out = tmp_path / "g.vts"
    rc, _, err = run_cli(
        [
            path,
            "--corners",
            0,
            1,
            2,
            3,
            "--method",
            "elliptic",
            "--size",
            9,
            9,
            "-o",
            out,
            "--quiet",
        ],
        capsys,
    )
    assert rc == 0, err
    pts = grid_points(out)
    np.testing.assert_allclose(
        [pts[0, 0], pts[0, -1], pts[-1, -1], pts[-1, 0]],
        [[0, 0], [2, 0], [1, 1.5], [0.5, 0.77]],
        atol=1e-12,
    )


def test_ambiguous_corners_mesh_when_named(tmp_path, capsys):
    path = csv(tmp_path / "b.csv", _ambiguous_corners())
    rc, _, err = run_cli(
        [path, "--corners", 0, 1, 3, 4, "--method", "tfi", "-o", tmp_path / "g.vts", "--quiet"],
        capsys,
    )
    assert rc == 0, err


def test_very_unequal_side_lengths(tmp_path, capsys):
    # a 1000:1 strip, one segment on each short side and 2000 on each long side
    t = np.linspace(0, 1000, 2001)[:-1]
    ring = np.vstack(
        [np.column_stack([t, 0 * t]), [[1000, 0]], np.column_stack([1000 - t, 1 + 0 * t]), [[0, 1]]]
    )
    path = csv(tmp_path / "strip.csv", ring)
    report = tmp_path / "r.json"
    rc, _, err = run_cli(
        [
            path,
            "--method",
            "elliptic",
            "--size",
            201,
            5,
            "-o",
            tmp_path / "g.vts",
            "--report",
            report,
            "--quiet",
        ],
        capsys,
    )
    assert rc == 0, err
    q = json.loads(report.read_text())["quality"]
    assert q["folded_cells"] == 0 and q["boundary_deviation"] <= 1e-12


@pytest.mark.parametrize(
    "scale, offset", [(1e-6, 0.0), (1e8, 0.0), (1.0, 1e5), (1e-3, 1e5), (1e3, -3e7), (1e-6, 1e5)]
)
def test_huge_and_tiny_scales_and_offsets(scale, offset, tmp_path, capsys):
    """Everything runs in a normalised frame: the grid is the unit case, scaled and shifted."""
    ring = wavy_ring()
    shift = np.array([offset, -0.5 * offset])
    reference = tfi(ring)
    path = csv(tmp_path / "b.csv", ring * scale + shift)
    out = tmp_path / "g.vts"
    rc, _, err = run_cli([path, "--method", "tfi", "--size", 11, 7, "-o", out, "--quiet"], capsys)
    assert rc == 0, err
    # the input itself carries about eps * |offset| of rounding
    tol = 1e-9 * scale + 4 * np.spacing(abs(offset) + 2 * scale)
    np.testing.assert_allclose(grid_points(out), reference * scale + shift, rtol=0, atol=tol)


def test_constant_z_header_and_separators_are_accepted(tmp_path, capsys):
    ring = square_ring(4)
    z = np.full(len(ring), 1e5) + np.random.default_rng(1).normal(0, 1e-9, len(ring))
    text = "# exported\nX;Y;Z\n" + "\n".join(f"{x};{y};{float(v)!r}" for (x, y), v in zip(ring, z))
    path = tmp_path / "b.txt"
    path.write_text(text)
    rc, _, err = run_cli([path, "--method", "tfi", "-o", tmp_path / "g.vts", "--quiet"], capsys)
    assert rc == 0, err


# ---------------------------------------------------------------- auxiliary lines


@pytest.fixture
def square_csv(tmp_path) -> Path:
    return csv(tmp_path / "square.csv", square_ring(10, size=2.0))


def aux_error(tmp_path, capsys, square_csv, aux: Path, pattern: str, names: str | None = None):
    rc, _, err = run_cli(
        [square_csv, "--aux", aux, "--method", "tfi", "-o", tmp_path / "g.vts"], capsys
    )
    assert_clean_error(rc, err, tmp_path, pattern, names or str(aux))


def test_aux_line_not_ending_on_two_opposite_sides(tmp_path, capsys, square_csv):
    aux = aux_file(tmp_path / "aux.vtp", [[0.6, 0.0], [2.0, 0.8]])
    aux_error(tmp_path, capsys, square_csv, aux, "line 0: does not end on two opposite sides")


def test_aux_line_crossing_the_boundary(tmp_path, capsys, square_csv):
    aux = aux_file(tmp_path / "aux.vtp", [[0.6, 0.0], [1.0, 2.5], [1.4, 2.0]])
    aux_error(tmp_path, capsys, square_csv, aux, "line 0: crosses the boundary")


def test_aux_line_outside_the_domain(tmp_path, capsys, square_csv):
    # from the bottom at x = 1 round the outside of the square to the top at x = 1
    around = [[1.0, 0.0], [1.0, -1.0], [3.0, -1.0], [3.0, 3.0], [1.0, 3.0], [1.0, 2.0]]
    aux = aux_file(tmp_path / "aux.vtp", around)
    aux_error(tmp_path, capsys, square_csv, aux, "line 0: lies outside the domain")


def test_aux_line_that_is_a_closed_curve(tmp_path, capsys, square_csv):
    loop = [[0.5, 0.5], [1.5, 0.5], [1.5, 1.5], [0.5, 1.5]]
    aux = vtp(tmp_path / "aux.vtp", polydata(loop, lines=[[0, 1, 2, 3, 0]]))
    aux_error(tmp_path, capsys, square_csv, aux, "closed curve")


def test_aux_lines_crossing_each_other_inconsistently(tmp_path, capsys, square_csv):
    # a straight bottom-top line at x = 1 (xi = 0.5) and a left-right line at eta = 0.1 that
    # bulges up to y = 1.8: they cross where the first says eta = 0.9 and the second 0.1
    vertical = [[1.0, 0.0], [1.0, 2.0]]
    bulge = [[0.0, 0.2], [0.9, 1.8], [1.1, 1.8], [2.0, 0.2]]
    aux = aux_file(tmp_path / "aux.vtp", vertical, bulge)
    aux_error(
        tmp_path,
        capsys,
        square_csv,
        aux,
        r"auxiliary lines '.*line 0' and '.*line 1' cross inconsistently",
        "aux.vtp",
    )


def test_aux_lines_in_swapped_order_crossing_inconsistently(tmp_path, capsys, square_csv):
    # two bottom-top lines, A left of B at the bottom and right of B at the top, that cross
    # near the bottom although their computational images cross at mid-height
    a = [[0.4, 0.0], [1.6, 0.3], [1.6, 2.0]]
    b = [[1.6, 0.0], [0.4, 0.3], [0.4, 2.0]]
    aux = aux_file(tmp_path / "aux.vtp", a, b)
    aux_error(tmp_path, capsys, square_csv, aux, "cross inconsistently")


def test_aux_lines_crossing_consistently_are_accepted(tmp_path, capsys, square_csv):
    # an X of two straight bottom-top lines and a straight left-right line: all agree
    a = [[0.4, 0.0], [1.6, 2.0]]
    b = [[1.6, 0.0], [0.4, 2.0]]
    c = [[0.0, 1.0], [2.0, 1.0]]
    aux = aux_file(tmp_path / "aux.vtp", a, b, c)
    rc, _, err = run_cli(
        [square_csv, "--aux", aux, "--method", "tfi", "-o", tmp_path / "g.vts", "--quiet"], capsys
    )
    assert rc == 0, err


def test_aux_xi_eta_arrays_must_be_complete_and_in_range(tmp_path, capsys, square_csv):
    line = [[0.5, 0.5], [1.5, 1.5]]
    only_xi = vtp(tmp_path / "a1.vtp", polydata(line, lines=[[0, 1]], arrays={"xi": [0.2, 0.8]}))
    aux_error(tmp_path, capsys, square_csv, only_xi, "only one of the point-data arrays")
    outside = vtp(
        tmp_path / "a2.vtp",
        polydata(line, lines=[[0, 1]], arrays={"xi": [0.2, 1.8], "eta": [0.1, 0.2]}),
    )
    aux_error(tmp_path, capsys, square_csv, outside, "within \\[0, 1\\]")


def test_damaged_aux_file(tmp_path, capsys):
    data = (EXAMPLES / "wavy_aux.vtp").read_bytes()
    aux = tmp_path / "aux.vtp"
    aux.write_bytes(data[: len(data) // 2])
    rc, _, err = run_cli(
        [EXAMPLES / "wavy.vtp", "--aux", aux, "--method", "tfi", "-o", tmp_path / "g.vts"], capsys
    )
    assert_clean_error(rc, err, tmp_path, "damaged or unreadable", str(aux))


# ---------------------------------------------------------------- options


@pytest.mark.parametrize(
    "options, pattern",
    [
        pytest.param(
            ["--size", "1", "5"], "--size 1 5: each side must have 2 to", id="size below 2"
        ),
        pytest.param(["--size", "20000", "20000"], "at most 4,000,000 nodes", id="size too large"),
        pytest.param(["--size", "30000", "3"], "--size 30000 3", id="side too long"),
        pytest.param(["--seed", "-1"], "--seed -1", id="seed"),
        pytest.param(["--lambda2", "nan"], "--lambda2 nan", id="lambda2"),
        pytest.param(
            ["--neurons", "0"], "--neurons 0: must be a whole number from 1 to 4096", id="neurons"
        ),
        pytest.param(["--device", "gpu7"], "--device 'gpu7'", id="device"),
        pytest.param(
            ["--epochs", "-3"], "--epochs -3: must be a whole number from 0 to 1000000", id="epochs"
        ),
        pytest.param(
            ["--corners", "0", "1", "2", "9999"],
            "corner index out of range",
            id="corner out of range",
        ),
        pytest.param(
            ["--corners", "0", "0", "2", "3"], "four different point indices", id="corners repeated"
        ),
        pytest.param(["-o", "out.dat"], "unknown output format '.dat'", id="output format"),
    ],
)
def test_bad_option_values_are_clear_errors(options, pattern, tmp_path, capsys):
    argv = [EXAMPLES / "wavy.vtp", "--method", "tfi", "-o", tmp_path / "g.vts", *options]
    rc, _, err = run_cli(argv, capsys)
    assert_clean_error(
        rc, err, tmp_path, re.escape(pattern) if "\\" not in pattern else pattern, None
    )


@pytest.mark.parametrize(
    "options",
    [["--frobnicate"], ["--size", "a", "b"], ["--method", "magic"], ["--corners", "1", "2"]],
)
def test_unknown_options_exit_2_in_one_line(options, capsys):
    with pytest.raises(SystemExit) as exc:
        main([str(EXAMPLES / "wavy.vtp"), *options])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("pinn-mesh: error: ") and err.count("\n") == 1
    assert err.endswith("(pinn-mesh -h lists the options)\n")


def test_unwritable_output_is_a_clear_error(tmp_path, capsys):
    blocker = tmp_path / "file.txt"
    blocker.write_text("not a folder")
    out_dir = tmp_path / "out.vts"
    out_dir.mkdir()
    for out, pattern in (
        (blocker / "g.vts", "g.vts: cannot be written: .*file.txt. is not a folder"),
        (out_dir, "is a directory"),
    ):
        rc, _, err = run_cli(
            [EXAMPLES / "wavy.vtp", "--method", "tfi", "-o", out, "--quiet"], capsys
        )
        assert rc == 2 and re.search(pattern, err), err
        assert len(err.strip().splitlines()) == 1


# ---------------------------------------------------------------- training that goes wrong

QUICK = ["--epochs", "60", "--lbfgs", "5", "--size", "21", "11", "--quiet"]


def nan_after(real, calls: set[int]):
    """Wrap ``total_loss`` so that the listed calls (1-based) return NaN."""
    count = [0]

    def total_loss(*args, **kwargs):
        count[0] += 1
        loss = real(*args, **kwargs)
        return loss * float("nan") if count[0] in calls else loss

    return total_loss


def test_nan_loss_during_adam_recovers(tmp_path, capsys, monkeypatch):
    from pinn_engine.kinds.four_sided import problem as training

    monkeypatch.setattr(training, "total_loss", nan_after(training.total_loss, {20, 21}))
    report = tmp_path / "r.json"
    rc, _, err = run_cli(
        [EXAMPLES / "wavy.vtp", *QUICK, "-o", tmp_path / "g.vts", "--report", report], capsys
    )
    assert rc == 0, err
    rep = json.loads(report.read_text())
    assert rep["training"]["recoveries"] == 2
    assert rep["quality"]["boundary_deviation"] <= 1e-9
    assert np.all(np.isfinite(grid_points(tmp_path / "g.vts")))


def test_exploding_loss_during_adam_recovers(monkeypatch):
    from pinn_engine.kinds.four_sided import problem as training

    real, count = training.total_loss, [0]

    def exploding(*args, **kwargs):
        count[0] += 1
        loss = real(*args, **kwargs)
        return loss * 1e9 if count[0] == 30 else loss

    monkeypatch.setattr(training, "total_loss", exploding)
    b = load_boundary(EXAMPLES / "wavy.vtp")
    mesher = Mesher(make_settings("pinn", adam_epochs=60, lbfgs_iterations=0)).fit(b)
    assert mesher.model_.info["recoveries"] == 1
    assert np.all(np.isfinite(mesher.predict(11, 7).points))


def test_persistent_nan_ends_with_a_clear_error_and_no_output(tmp_path, capsys, monkeypatch):
    from pinn_engine.kinds.four_sided import problem as training

    monkeypatch.setattr(
        training, "total_loss", nan_after(training.total_loss, set(range(10, 10_000)))
    )
    rc, _, err = run_cli([EXAMPLES / "wavy.vtp", *QUICK, "-o", tmp_path / "g.vts"], capsys)
    assert_clean_error(rc, err, tmp_path, "training diverged .* after 3 recoveries", None)
    with pytest.raises(TrainingError):
        b = load_boundary(EXAMPLES / "wavy.vtp")
        Mesher(make_settings("pinn", adam_epochs=60, lbfgs_iterations=0)).fit(b)


def test_nan_in_lambda1_annealing_recovers(monkeypatch):
    from pinn_engine.neural import trainer as training

    real, count = training.annealed_lambda, [0]

    def once_nan(*args, **kwargs):
        count[0] += 1
        return float("nan") if count[0] == 3 else real(*args, **kwargs)

    monkeypatch.setattr(training, "annealed_lambda", once_nan)
    b = load_boundary(EXAMPLES / "wavy.vtp")
    mesher = Mesher(make_settings("pinn", "paper", adam_epochs=60, lbfgs_iterations=0)).fit(b)
    assert count[0] > 3  # the NaN update was skipped and annealing went on
    assert math.isfinite(mesher.model_.info["lambda1"])
    assert all(math.isfinite(v) for v in mesher.model_.history["lambda1"])


def test_nan_during_lbfgs_falls_back_to_the_adam_result(monkeypatch):
    from pinn_engine.kinds.four_sided import problem as training

    monkeypatch.setattr(
        training, "total_loss", nan_after(training.total_loss, set(range(41, 10_000)))
    )
    b = load_boundary(EXAMPLES / "wavy.vtp")
    mesher = Mesher(make_settings("pinn", adam_epochs=40, lbfgs_iterations=5)).fit(b)
    assert mesher.model_.info["lbfgs_accepted"] is False
    assert np.all(np.isfinite(mesher.predict(11, 7).points))


def test_non_finite_grid_is_a_clear_error(tmp_path, capsys, monkeypatch):
    from pinn_engine.kinds.four_sided.model import TrainedModel

    monkeypatch.setattr(TrainedModel, "grid", lambda self, ni, nj: np.full((nj, ni, 2), np.nan))
    rc, _, err = run_cli([EXAMPLES / "wavy.vtp", *QUICK, "-o", tmp_path / "g.vts"], capsys)
    assert_clean_error(rc, err, tmp_path, "non-finite grid points", None)


def test_folded_cells_are_refused_with_or_without_fail_on_folded(tmp_path, capsys):
    base = [EXAMPLES / "concave.vtp", "--method", "tfi", "--report", tmp_path / "r.json"]
    for fail in ([], ["--fail-on-folded"]):
        rc, _, err = run_cli([*base, "-o", tmp_path / "b.vts", *fail], capsys)
        assert_clean_error(
            rc,
            err.splitlines()[-1],
            tmp_path,
            "the grid is not written: 13 of 800 cells are folded .*; try --method elliptic",
            None,
        )
        assert not (tmp_path / "r.json").exists()


# ---------------------------------------------------------------- interruption, atomic writes


def _answer_ctrl_c() -> None:
    """In the child before it runs the command: Ctrl-C's default action, which a suite run in
    the background (a shell's ``&``) has set to ignored and a child would inherit, as any
    program started so keeps ignoring it."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def start(args: list, tmp_path: Path) -> subprocess.Popen:
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    return subprocess.Popen(
        [str(PINN_MESH), *map(str, args)],
        cwd=tmp_path,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=_answer_ctrl_c,
    )


def wait_for(predicate, timeout: float) -> bool:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return True
        time.sleep(0.05)
    return False


# Seconds within which an interrupted run must have ended: generous, for loaded test
# machines; the runs interrupted here would otherwise take hours (training) or many seconds.
PROMPT = 15.0


@pytest.mark.slow  # two commands started, trained and interrupted (5 to 10 s)
def test_interrupt_during_training_ends_promptly_without_output(tmp_path):
    """Ctrl-C (SIGINT) and SIGTERM, each sent to a run that is training (in parallel)."""
    runs = {}
    for sig in (signal.SIGINT, signal.SIGTERM):
        folder = tmp_path / sig.name
        folder.mkdir()
        runs[sig] = (
            folder,
            start(
                [
                    EXAMPLES / "wavy.vtp",
                    "--epochs",
                    "1000000",
                    "--lbfgs",
                    "0",
                    "-o",
                    folder / "g.vts",
                    "--report",
                    folder / "r.json",
                ],
                folder,
            ),
        )
    for sig, (folder, proc) in runs.items():
        first = proc.stderr.readline()  # the first progress line: training is under way
        assert "[adam" in first, first + proc.stderr.read()
        sent = time.monotonic()
        proc.send_signal(sig)
        try:
            _, err = proc.communicate(timeout=2 * PROMPT)
        finally:
            proc.kill()
        assert time.monotonic() - sent < PROMPT, sig.name
        assert proc.returncode == 130, (sig.name, err)
        assert err.strip().splitlines()[-1] == "pinn-mesh: interrupted; no output written"
        assert "Traceback" not in err
        assert list(folder.iterdir()) == []  # no grid, no report, no temporary file


@pytest.mark.slow  # a 1200 x 1200 grid, so that the writing can be interrupted (4 to 6 s)
def test_interrupt_during_writing_leaves_no_partial_file(tmp_path):
    out = tmp_path / "g.vts"
    out.write_bytes(b"the previous grid")
    proc = start(
        [EXAMPLES / "wavy.vtp", "--method", "tfi", "--size", "1200", "1200", "-o", out], tmp_path
    )
    # the summary comes after the files are written: the temporary file says writing started
    assert wait_for(lambda: list(tmp_path.glob(".g.vts.*.part")), 4 * PROMPT)
    sent = time.monotonic()
    proc.send_signal(signal.SIGINT)
    try:
        _, err = proc.communicate(timeout=2 * PROMPT)
    finally:
        proc.kill()
    assert time.monotonic() - sent < PROMPT
    assert proc.returncode == 130 and "interrupted; no output written" in err, err
    assert "Traceback" not in err
    assert out.read_bytes() == b"the previous grid"  # the old file is untouched
    assert [p.name for p in tmp_path.iterdir()] == ["g.vts"]


def test_writer_failing_midway_leaves_no_partial_file(tmp_path, monkeypatch):
    from vtkmodules.vtkIOXML import vtkXMLStructuredGridWriter

    class HalfWriter(vtkXMLStructuredGridWriter):
        def Write(self):  # noqa: N802 - VTK's name
            Path(self.GetFileName()).write_bytes(b"<VTKFile half")
            return 0

    monkeypatch.setattr(fileio, "vtkXMLStructuredGridWriter", HalfWriter)
    from pinn_engine.io.pipeline import to_vtk

    result = Mesher(make_settings("tfi")).fit(load_boundary(EXAMPLES / "wavy.vtp")).predict(5, 5)
    (tmp_path / "g.vts").write_bytes(b"the previous grid")
    with pytest.raises(OSError, match="VTK could not write"):
        fileio.write_vts(to_vtk(result), tmp_path / "g.vts")
    assert [p.name for p in tmp_path.iterdir()] == ["g.vts"]
    assert (tmp_path / "g.vts").read_bytes() == b"the previous grid"


@pytest.mark.skipif(os.name == "nt", reason="POSIX signals")
def test_a_process_killed_while_writing_leaves_the_target_as_it_was(tmp_path):
    """The grid is written in the process itself: killed midway (SIGKILL, a crash), the
    target keeps its old content; only the temporary file is left beside it."""
    out = tmp_path / "g.vts"
    out.write_bytes(b"the previous grid")
    script = f"""
import os, signal
from pathlib import Path
from vtkmodules.vtkIOXML import vtkXMLStructuredGridWriter
from pinn_engine.io import fileio
from pinn_engine.kinds.four_sided.mesher import Mesher
from pinn_engine.io.pipeline import load_boundary, to_vtk
from pinn_engine.settings import make_settings

class DyingWriter(vtkXMLStructuredGridWriter):
    def Write(self):
        Path(self.GetFileName()).write_bytes(b"<VTKFile half")
        os.kill(os.getpid(), signal.SIGKILL)

fileio.vtkXMLStructuredGridWriter = DyingWriter
boundary = load_boundary({str(EXAMPLES / "wavy.vtp")!r})
fileio.write_vts(to_vtk(Mesher(make_settings("tfi")).fit(boundary).predict(5, 5)), {str(out)!r})
"""
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, timeout=300)
    assert done.returncode == -signal.SIGKILL, done.stderr
    assert out.read_bytes() == b"the previous grid"
    assert {p.name for p in tmp_path.iterdir()} - {"g.vts"} <= {
        p.name for p in tmp_path.glob(".g.vts.*.part")
    }


@pytest.mark.slow  # two command-line processes writing at once
def test_two_runs_writing_the_same_output_at_once(tmp_path):
    out = tmp_path / "g.vts"
    procs = [
        start(
            [EXAMPLES / name, "--method", "elliptic", "--size", "61", "31", "-o", out, "--quiet"],
            tmp_path,
        )
        for name in ("wavy.vtp", "fig2.vtp")
    ]
    for proc in procs:
        _, err = proc.communicate(timeout=120)
        assert proc.returncode == 0, err
    assert grid_points(out).shape == (31, 61, 2)  # one complete grid, whichever came last
    assert [p.name for p in tmp_path.iterdir()] == ["g.vts"]
    assert (out.stat().st_mode & 0o777) == 0o666 & ~current_umask()


def current_umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


# ---------------------------------------------------------------- saved models


@pytest.fixture(scope="module")
def saved_model(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("model")
    model = folder / "m.pt"
    assert (
        main(
            [
                str(EXAMPLES / "wavy.vtp"),
                "--epochs",
                "20",
                "--lbfgs",
                "0",
                "--size",
                "5",
                "5",
                "-o",
                str(folder / "g.vts"),
                "--save-model",
                str(model),
                "--quiet",
            ]
        )
        == 0
    )
    return model


def _rewrite_model(src: Path, dst: Path, change) -> Path:
    import torch

    payload = torch.load(src, map_location="cpu", weights_only=True)
    change(payload)
    torch.save(payload, dst)
    return dst


MODEL_CASES = {
    "missing": (lambda m, d: d / "none.pt", "model file not found"),
    "random bytes": (
        lambda m, d: put(d / "x.pt", np.random.default_rng(7).bytes(2000)),
        "not a readable pinn-mesh model",
    ),
    "bytes read as a newer pickle protocol": (  # torch warns before it raises
        lambda m, d: put(d / "p.pt", b"\x80\xd2" + np.random.default_rng(8).bytes(2000)),
        "not a readable pinn-mesh model",
    ),
    "truncated": (
        lambda m, d: put(d / "t.pt", m.read_bytes()[:1000]),
        "not a readable pinn-mesh model",
    ),
    "another format version": (
        lambda m, d: _rewrite_model(m, d / "v.pt", lambda p: p.update(format="pinn-mesh-model/0")),
        "not a pinn-mesh model of format",
    ),
    "missing weights": (
        lambda m, d: _rewrite_model(m, d / "w.pt", lambda p: p.pop("state")),
        "damaged or incompatible model",
    ),
    "unknown settings": (
        lambda m, d: _rewrite_model(m, d / "s.pt", lambda p: p["settings"].update(bogus=1)),
        "damaged or incompatible model",
    ),
    "another boundary": (lambda m, d: m, "trained for a different boundary"),
}


@pytest.mark.parametrize("name", list(MODEL_CASES))
def test_bad_saved_model_is_a_clear_error(name, saved_model, tmp_path, capsys):
    make, pattern = MODEL_CASES[name]
    model = make(saved_model, tmp_path)
    boundary = EXAMPLES / ("fig2.vtp" if name == "another boundary" else "wavy.vtp")
    rc, _, err = run_cli([boundary, "--load-model", model, "-o", tmp_path / "g.vts"], capsys)
    assert_clean_error(rc, err, tmp_path, pattern, str(model))


def test_saving_a_model_into_a_new_folder_and_loading_it(saved_model, tmp_path, capsys):
    rc, _, err = run_cli(
        [
            EXAMPLES / "wavy.vtp",
            "--load-model",
            saved_model,
            "--save-model",
            tmp_path / "new" / "m.pt",
            "-o",
            tmp_path / "g.vts",
            "--quiet",
        ],
        capsys,
    )
    assert rc == 0, err
    assert (tmp_path / "new" / "m.pt").is_file()


if __name__ == "__main__":  # pragma: no cover
    sys.exit(pytest.main([__file__, "-q"]))
