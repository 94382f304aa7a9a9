"""Reading boundaries and auxiliary lines, writing grids.

VTK only (no pyvista), so that the ParaView plugin can use it.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkObject
from vtkmodules.vtkCommonDataModel import vtkPolyData, vtkStructuredGrid
from vtkmodules.vtkFiltersCore import vtkStripper
from vtkmodules.vtkIOLegacy import vtkPolyDataReader
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLStructuredGridWriter

from .errors import InputError

BOUNDARY_FORMATS = (".vtp", ".vtk", ".csv", ".txt")
AUX_FORMATS = (".vtp", ".vtk")


@dataclass(frozen=True)
class RawLine:
    """A polyline as read: points (n, 2) and optional per-point (xi, eta) overrides."""

    points: np.ndarray
    xi_eta: np.ndarray | None
    name: str


@contextlib.contextmanager
def _quiet_vtk():
    """Silence VTK's own error printing; we report problems ourselves, once."""
    previous = vtkObject.GetGlobalWarningDisplay()
    vtkObject.GlobalWarningDisplayOff()
    try:
        yield
    finally:
        vtkObject.SetGlobalWarningDisplay(previous)


def _check_file(path: Path, formats: tuple[str, ...]) -> str:
    src = str(path)
    if not path.exists():
        raise InputError("file not found", src)
    if path.is_dir():
        raise InputError("is a directory, not a file", src)
    if path.suffix.lower() not in formats:
        raise InputError(f"unknown format {path.suffix or '(none)'!r}; use one of "
                         + ", ".join(formats), src)
    if path.stat().st_size == 0:
        raise InputError("file is empty", src)
    return src


def read_polydata(path: Path) -> vtkPolyData:
    """Read a ``.vtp`` or legacy ``.vtk`` polydata file."""
    src = str(path)
    reader = vtkXMLPolyDataReader() if path.suffix.lower() == ".vtp" else vtkPolyDataReader()
    with _quiet_vtk():
        if isinstance(reader, vtkPolyDataReader):
            reader.SetFileName(src)
            if not reader.IsFilePolyData():
                raise InputError("not a VTK polydata file", src)
        else:
            if not reader.CanReadFile(src):
                raise InputError("not a VTK XML polydata file", src)
            reader.SetFileName(src)
        reader.Update()
    out = reader.GetOutput()
    if out is None or out.GetNumberOfPoints() == 0:
        raise InputError("holds no points", src)
    return out


def _xy(points: np.ndarray, source: str) -> np.ndarray:
    if points.shape[1] == 3:
        z = points[:, 2]
        finite = np.isfinite(z)
        if finite.any() and np.ptp(z[finite]) > 1e-9 * max(1.0, float(np.abs(z[finite]).max())):
            raise InputError("z is not constant; the domain must lie in a plane z = const",
                             source)
    return np.ascontiguousarray(points[:, :2], dtype=float)


def polylines_of(poly: vtkPolyData) -> list[tuple[np.ndarray, bool]]:
    """Point-id lists of the polylines and polygons in ``poly``, with a closed flag.

    Line segments are joined into polylines by ``vtkStripper``.
    """
    found: list[tuple[np.ndarray, bool]] = []
    polys = poly.GetPolys()
    if polys is not None and polys.GetNumberOfCells():
        for k in range(poly.GetNumberOfCells()):
            cell = poly.GetCell(k)
            if cell.GetCellDimension() == 2:
                ids = np.array([cell.GetPointId(i) for i in range(cell.GetNumberOfPoints())])
                found.append((ids, True))
    lines = poly.GetLines()
    if lines is not None and lines.GetNumberOfCells():
        only_lines = vtkPolyData()
        only_lines.SetPoints(poly.GetPoints())
        only_lines.SetLines(lines)
        stripper = vtkStripper()
        stripper.SetInputData(only_lines)
        stripper.JoinContiguousSegmentsOn()
        stripper.Update()
        strips = stripper.GetOutput()
        pts = strips.GetPoints()  # the stripper keeps the input's points and their ids
        for k in range(strips.GetNumberOfCells()):
            cell = strips.GetCell(k)
            ids = np.array([cell.GetPointId(i) for i in range(cell.GetNumberOfPoints())])
            closed = len(ids) > 2 and (
                ids[0] == ids[-1] or pts.GetPoint(ids[0]) == pts.GetPoint(ids[-1]))
            found.append((ids, closed))
    return found


def boundary_points(poly: vtkPolyData, source: str = "boundary input") -> np.ndarray:
    """The (x, y) ring of the single closed polyline or polygon in ``poly``."""
    cells = polylines_of(poly)
    if not cells:
        raise InputError("holds no polyline or polygon cell", source)
    if len(cells) > 1:
        raise InputError(f"holds {len(cells)} separate curves; the boundary must be one "
                         "closed polyline", source)
    ids, closed = cells[0]
    if not closed:
        raise InputError("boundary polyline is open (its last point is not its first)", source)
    pts = vtk_to_numpy(poly.GetPoints().GetData()).astype(float)[ids]
    if len(ids) > 1 and ids[0] == ids[-1]:
        pts = pts[:-1]
    return _xy(pts, source)


def read_table(path: Path) -> np.ndarray:
    """Read ``x,y[,z]`` rows (comma or whitespace separated, optional header)."""
    src = str(path)
    data = path.read_bytes()
    if b"\0" in data:
        raise InputError("is a binary file, not a text table of x,y rows", src)
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError("is not UTF-8 text; expected rows of x,y", src) from exc
    rows = []
    for number, line in enumerate(text.splitlines(), start=1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        fields = [f for f in line.replace(",", " ").replace(";", " ").split() if f]
        try:
            values = [float(f) for f in fields]
        except ValueError:
            if not rows and number == 1:
                continue  # a header row
            raise InputError(f"line {number} is not numeric: {line[:40]!r}", src) from None
        if len(values) not in (2, 3):
            raise InputError(f"line {number} has {len(values)} columns; expected x,y or x,y,z",
                             src)
        if rows and len(values) != len(rows[0]):
            raise InputError(f"line {number} has {len(values)} columns, earlier lines "
                             f"{len(rows[0])}", src)
        rows.append(values)
    if not rows:
        raise InputError("holds no x,y rows", src)
    return _xy(np.array(rows, dtype=float), src)


def read_boundary_points(path: str | os.PathLike) -> np.ndarray:
    """The boundary ring (n, 2) of a ``.vtp``, ``.vtk``, ``.csv`` or ``.txt`` file."""
    path = Path(path)
    src = _check_file(path, BOUNDARY_FORMATS)
    if path.suffix.lower() in (".csv", ".txt"):
        return read_table(path)
    return boundary_points(read_polydata(path), src)


def aux_lines_of(poly: vtkPolyData, source: str = "auxiliary input") -> list[RawLine]:
    """Every open polyline of ``poly``, with its ``xi``/``eta`` point data when present."""
    pd = poly.GetPointData()
    arrays = [pd.GetArray(n) for n in ("xi", "eta")]
    xi_eta_all = None
    if all(a is not None for a in arrays):
        xi_eta_all = np.stack([vtk_to_numpy(a).astype(float) for a in arrays], axis=1)
    pts_all = vtk_to_numpy(poly.GetPoints().GetData()).astype(float)
    lines = []
    for k, (ids, closed) in enumerate(polylines_of(poly)):
        name = f"{source} line {k}"
        if closed:
            raise InputError("is a closed curve; an auxiliary line must be open", name)
        if len(ids) < 2:
            raise InputError("has fewer than 2 points", name)
        pts = _xy(pts_all[ids], name)
        if not np.all(np.isfinite(pts)):
            raise InputError("has a non-finite point", name)
        xe = xi_eta_all[ids] if xi_eta_all is not None else None
        lines.append(RawLine(points=pts, xi_eta=xe, name=name))
    if not lines:
        raise InputError("holds no polyline", source)
    return lines


def read_aux_lines(path: str | os.PathLike) -> list[RawLine]:
    """Auxiliary polylines from a ``.vtp`` or ``.vtk`` file."""
    path = Path(path)
    src = _check_file(path, AUX_FORMATS)
    return aux_lines_of(read_polydata(path), src)


def write_vts(grid: vtkStructuredGrid, path: str | os.PathLike) -> Path:
    """Write ``grid`` atomically: the file is complete or absent, never half-written."""
    path = Path(path)
    if path.suffix.lower() != ".vts":
        raise InputError("output must be a .vts file", str(path))
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=path.parent)
    os.close(fd)
    try:
        writer = vtkXMLStructuredGridWriter()
        writer.SetFileName(tmp)
        writer.SetInputData(grid)
        writer.SetDataModeToAppended()
        writer.SetCompressorTypeToZLib()
        if writer.Write() != 1:
            raise OSError(f"VTK could not write {path}")
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return path
