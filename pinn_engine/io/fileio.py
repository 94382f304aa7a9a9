"""Reading boundaries and auxiliary lines, writing grids.

VTK only (no pyvista), so that the ParaView plugin can use it.

The library leaves its host process alone: it never forks it (forking a process that runs
threads, as ParaView, a notebook, a Dask worker or torch's thread pool do, can deadlock the
child). Grids are written in this process to a temporary file beside the target that then
replaces it (``io.atomic.atomic_path``). VTK files (``.vtp``, ``.vtk``), whose readers crash on
damaged files, are read by a new Python started for the purpose (:mod:`.childread`);
``.csv`` and ``.txt`` tables are read here, in Python. What the child costs, measured
(``read_polydata`` on ``example_data/wavy.vtp``, 240 points, 9 reads each, from a process
with torch loaded, on a shared 2-core machine at load average 6): 217 ms a read (149-224),
against 0.3 ms reading in this process and 38 ms (22-46) for the forked probe it replaces;
on a 200 000-point ring (3.8 MB): 318 ms against 54 ms and 212 ms. Most of it is the child's
Python and VTK starting; a file of the same content is read once per process, and the
command line reads all of a run's files in one child started before it imports the engine.
"""

from __future__ import annotations

import contextlib
import logging
import os
from pathlib import Path

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkLogger, vtkObject, vtkOutputWindow, vtkStringOutputWindow
from vtkmodules.vtkCommonDataModel import vtkPolyData, vtkStructuredGrid
from vtkmodules.vtkIOXML import vtkXMLStructuredGridWriter

from pinn_engine.errors import InputError
from pinn_engine.geometry.auxlines import RawLine
from pinn_engine.geometry.boundary import MAX_POINTS
from pinn_engine.io import childread
from pinn_engine.io.atomic import atomic_path as atomic_path
from pinn_engine.io.atomic import check_writable as check_writable
from pinn_engine.io.atomic import umask as umask
from pinn_engine.io.atomic import write_text_atomic as write_text_atomic
from pinn_engine.io.childread import MAX_FILE_BYTES

log = logging.getLogger(__name__)
BOUNDARY_FORMATS = (".vtp", ".vtk", ".csv", ".txt")
AUX_FORMATS = BOUNDARY_FORMATS  # auxiliary lines and block edges: polylines or tables


@contextlib.contextmanager
def quiet_vtk():
    """Silence VTK's own error printing; we report problems ourselves, once."""
    previous = vtkObject.GetGlobalWarningDisplay()
    vtkObject.GlobalWarningDisplayOff()
    try:
        yield
    finally:
        vtkObject.SetGlobalWarningDisplay(previous)


def check_file(path: Path, formats: tuple[str, ...]) -> str:
    """``path`` as the name messages give it, once it is a readable, non-empty file of one
    of ``formats`` no larger than ``MAX_FILE_BYTES``; else an ``InputError`` saying which."""
    src = str(path)
    if not path.exists():
        raise InputError("file not found", src)
    if path.is_dir():
        raise InputError("is a directory, not a file", src)
    if path.suffix.lower() not in formats:
        raise InputError(
            f"unknown format {path.suffix or '(none)'!r}; use one of " + ", ".join(formats), src
        )
    try:
        size = path.stat().st_size
        with open(path, "rb"):
            pass
    except OSError as exc:
        raise InputError(f"cannot be read ({exc.strerror or exc})", src) from None
    if size == 0:
        raise InputError("file is empty", src)
    if size > MAX_FILE_BYTES:
        raise InputError(
            f"file is too large ({size / 2**20:.0f} MiB; at most {MAX_FILE_BYTES // 2**20} MiB)",
            src,
        )
    return src


@contextlib.contextmanager
def _captured_vtk_errors():
    """Collect VTK's error text (also its logger's) instead of printing it; yields a getter."""
    previous_window = vtkOutputWindow.GetInstance()
    window = vtkStringOutputWindow()
    previous_display = vtkObject.GetGlobalWarningDisplay()
    previous_verbosity = vtkLogger.GetCurrentVerbosityCutoff()  # the stderr sink's level
    vtkOutputWindow.SetInstance(window)
    vtkObject.GlobalWarningDisplayOn()
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)

    def error() -> str | None:
        return childread.first_error(window.GetOutput())

    try:
        yield error
    finally:
        vtkOutputWindow.SetInstance(previous_window)
        vtkObject.SetGlobalWarningDisplay(previous_display)
        vtkLogger.SetStderrVerbosity(previous_verbosity)


def _vtk_reader(path: Path):
    """VTK's reader of ``path`` by its extension (an STL reader merges coincident points).

    VTK's polydata readers and filters are imported where a polydata file is read: a run
    from a point file (an airfoil's ``.dat``, a ``.csv``) starts 0.03 s sooner without them.
    """
    from vtkmodules.vtkIOGeometry import vtkSTLReader
    from vtkmodules.vtkIOLegacy import vtkPolyDataReader
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

    readers = {".vtp": vtkXMLPolyDataReader, ".stl": vtkSTLReader}
    reader = readers.get(path.suffix.lower(), vtkPolyDataReader)()
    reader.SetFileName(str(path))
    return reader


def read_polydata(path: Path) -> vtkPolyData:
    """Read a ``.vtp``, legacy ``.vtk`` or ``.stl`` polydata file (in a child process:
    :func:`.childread.read`)."""
    from vtkmodules.vtkIOLegacy import vtkPolyDataReader

    src = str(path)
    reader = _vtk_reader(path)
    with _captured_vtk_errors():
        if isinstance(reader, vtkPolyDataReader):
            if not reader.IsFilePolyData():
                raise InputError("not a VTK polydata file", src)
        elif not reader.CanReadFile(src):
            kind = "an STL" if path.suffix.lower() == ".stl" else "a VTK XML polydata"
            raise InputError(f"not {kind} file", src)
    read = childread.read(path)
    if read is not None:
        problem, data = read
        if problem:
            raise InputError(f"is damaged or unreadable ({problem})", src)
        reader = vtkPolyDataReader()  # what the child's VTK wrote: well-formed
        reader.ReadFromInputStringOn()
        reader.SetBinaryInputString(data, len(data))
    with _captured_vtk_errors() as vtk_error:
        reader.Update()
        error = vtk_error()
    if error:
        raise InputError(f"is damaged or unreadable (VTK: {error})", src)
    out = reader.GetOutput()
    if out is None or out.GetNumberOfPoints() == 0:
        raise InputError("holds no points", src)
    return out


def _checked(points: np.ndarray, source: str) -> np.ndarray:
    """The points (n, 2) or (n, 3) as float, refusing too many and a non-finite z (x and y
    are checked with the shape); the plane they lie in is found by ``plane.Plane.fit``."""
    if len(points) > MAX_POINTS:
        raise InputError(
            f"holds {len(points)} points; at most {MAX_POINTS} are accepted (resample it)", source
        )
    pts = np.ascontiguousarray(points, dtype=float)
    if pts.shape[1] == 3 and not np.all(np.isfinite(pts[:, 2])):
        bad = int(np.flatnonzero(~np.isfinite(pts[:, 2]))[0])
        raise InputError(f"point {bad} has a non-finite z (NaN or infinity)", source)
    return pts


def _cell_ids(cells, npts: int) -> list[np.ndarray]:
    """Point-id lists of a ``vtkCellArray``, refusing ids outside ``0..npts-1``."""
    offsets = vtk_to_numpy(cells.GetOffsetsArray()).astype(np.int64)
    conn = vtk_to_numpy(cells.GetConnectivityArray()).astype(np.int64)
    if len(conn) and (conn.min() < 0 or conn.max() >= npts):
        raise ValueError("a cell refers to a point that does not exist")
    return [conn[offsets[k] : offsets[k + 1]] for k in range(len(offsets) - 1)]


def polylines_of(poly: vtkPolyData, source: str = "input") -> list[tuple[np.ndarray, bool]]:
    """Point-id lists of the polylines and polygons in ``poly``, with a closed flag.

    Line segments are joined into polylines by ``vtkStripper``.
    """
    found: list[tuple[np.ndarray, bool]] = []
    npts = poly.GetNumberOfPoints()
    try:
        polys = (
            [ids for ids in _cell_ids(poly.GetPolys(), npts) if len(ids)]
            if poly.GetPolys() is not None
            else []
        )
        lines = _cell_ids(poly.GetLines(), npts) if poly.GetLines() is not None else []
    except ValueError as exc:
        raise InputError(f"is damaged: {exc}", source) from None
    found.extend((ids, True) for ids in polys)
    if lines:
        from vtkmodules.vtkFiltersCore import vtkStripper

        only_lines = vtkPolyData()
        only_lines.SetPoints(poly.GetPoints())
        only_lines.SetLines(poly.GetLines())
        stripper = vtkStripper()
        stripper.SetInputData(only_lines)
        stripper.JoinContiguousSegmentsOn()
        with quiet_vtk():
            stripper.Update()
        strips = stripper.GetOutput()
        xyz = vtk_to_numpy(strips.GetPoints().GetData())  # the stripper keeps point ids
        for ids in _cell_ids(strips.GetLines(), strips.GetNumberOfPoints()):
            if len(ids) == 0:
                continue
            closed = len(ids) > 2 and (
                ids[0] == ids[-1] or bool(np.array_equal(xyz[ids[0]], xyz[ids[-1]]))
            )
            found.append((ids, closed))
    return found


def boundary_points(poly: vtkPolyData, source: str = "boundary input") -> np.ndarray:
    """The (x, y, z) ring of the single closed polyline or polygon in ``poly``."""
    cells = polylines_of(poly, source)
    if not cells:
        raise InputError("holds no polyline or polygon cell", source)
    if len(cells) > 1:
        raise InputError(
            f"holds {len(cells)} separate curves; the boundary must be one closed polyline", source
        )
    ids, closed = cells[0]
    if not closed:
        raise InputError(
            "boundary polyline is open (its last point is not its first); {close}", source
        )
    pts = vtk_to_numpy(poly.GetPoints().GetData()).astype(float)[ids]
    if len(ids) > 1 and ids[0] == ids[-1]:
        pts = pts[:-1]
    return _checked(pts, source)


def _table_text(path: Path) -> str:
    """A text table's contents, refused when it cannot be read or is not UTF-8 text."""
    src = str(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(f"cannot be read ({exc.strerror or exc})", src) from None
    if b"\0" in data:
        raise InputError("is a binary file, not a text table of x,y rows", src)
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError("is not UTF-8 text; expected rows of x,y", src) from exc


def _table_groups(text: str, src: str) -> list[list[list[float]]]:
    """The ``x,y[,z]`` rows of a table (comma or whitespace separated, optional header),
    in groups that blank lines separate."""
    groups: list[list[list[float]]] = [[]]
    header = False
    count = 0
    for number, line in enumerate(text.splitlines(), start=1):
        line = line.strip()
        if not line:
            if groups[-1]:
                groups.append([])
            continue
        if line.startswith("#"):
            continue
        fields = [f for f in line.replace(",", " ").replace(";", " ").split() if f]
        try:
            values = [float(f) for f in fields]
        except ValueError:
            if not count and not header:
                header = True  # one header row before the data
                continue
            raise InputError(f"line {number} is not numeric: {line[:40]!r}", src) from None
        if len(values) not in (2, 3):
            raise InputError(f"line {number} has {len(values)} columns; expected x,y or x,y,z", src)
        first = next((g[0] for g in groups if g), None)
        if first is not None and len(values) != len(first):
            raise InputError(
                f"line {number} has {len(values)} columns, earlier lines {len(first)}", src
            )
        groups[-1].append(values)
        count += 1
        if count > MAX_POINTS:
            raise InputError(f"holds more than {MAX_POINTS} rows; resample it", src)
    groups = [g for g in groups if g]
    if not groups:
        raise InputError("holds no x,y rows", src)
    return groups


def read_table(path: Path) -> np.ndarray:
    """Read ``x,y[,z]`` rows (comma or whitespace separated, optional header; blank lines
    are skipped)."""
    src = str(path)
    rows = [row for group in _table_groups(_table_text(path), src) for row in group]
    return _checked(np.array(rows, dtype=float), src)


def read_table_lines(path: Path) -> list[np.ndarray]:
    """The polylines of a text table: ``x,y[,z]`` rows, one polyline a group of rows that
    blank lines separate (gnuplot's convention)."""
    src = str(path)
    groups = _table_groups(_table_text(path), src)
    return [_checked(np.array(g, dtype=float), src) for g in groups]


def read_boundary_points(path: str | os.PathLike) -> np.ndarray:
    """The boundary ring (n, 2) or (n, 3) of a ``.vtp``, ``.vtk``, ``.csv`` or ``.txt`` file."""
    path = Path(path)
    src = check_file(path, BOUNDARY_FORMATS)
    if path.suffix.lower() in (".csv", ".txt"):
        return read_table(path)
    return boundary_points(read_polydata(path), src)


def read_rings(path: str | os.PathLike) -> list[np.ndarray]:
    """Every closed curve (n, 2) or (n, 3) of a ``.vtp``/``.vtk`` file, or the one ring of a
    ``.csv``/``.txt`` table: a multi-block domain's boundary and holes (SPEC 10)."""
    path = Path(path)
    src = check_file(path, BOUNDARY_FORMATS)
    if path.suffix.lower() in (".csv", ".txt"):
        return [read_table(path)]
    poly = read_polydata(path)
    xyz = vtk_to_numpy(poly.GetPoints().GetData()).astype(float)
    rings = []
    for k, (ids, closed) in enumerate(polylines_of(poly, src)):
        if not closed:
            raise InputError(
                f"curve {k} is open; the boundary and its holes are closed polylines", src
            )
        rings.append(_checked(xyz[ids[:-1] if ids[0] == ids[-1] else ids], src))
    if not rings:
        raise InputError("holds no polyline or polygon cell", src)
    return rings


def aux_lines_of(poly: vtkPolyData, source: str = "auxiliary input") -> list[RawLine]:
    """Every open polyline of ``poly``, with its ``xi``/``eta`` point data when present."""
    pd = poly.GetPointData()
    arrays = [pd.GetArray(n) for n in ("xi", "eta")]
    xi_eta_all = None
    if any(a is not None for a in arrays):
        if any(a is None for a in arrays):
            raise InputError(
                "has only one of the point-data arrays xi and eta; give both or neither", source
            )
        if any(a.GetNumberOfComponents() != 1 for a in arrays):
            raise InputError("point-data arrays xi and eta must have one component", source)
        xi_eta_all = np.stack([vtk_to_numpy(a).astype(float) for a in arrays], axis=1)
    pts_all = vtk_to_numpy(poly.GetPoints().GetData()).astype(float)
    lines = []
    for k, (ids, closed) in enumerate(polylines_of(poly, source)):
        name = f"{source} line {k}"
        if closed:
            raise InputError("is a closed curve; an auxiliary line must be open", name)
        if len(ids) < 2:
            raise InputError("has fewer than 2 points", name)
        pts = _checked(pts_all[ids], name)
        if not np.all(np.isfinite(pts)):
            raise InputError("has a non-finite point", name)
        xe = xi_eta_all[ids] if xi_eta_all is not None else None
        lines.append(RawLine(points=pts, xi_eta=xe, name=name))
    if not lines:
        raise InputError("holds no polyline", source)
    return lines


def table_aux_lines(path: Path, source: str) -> list[RawLine]:
    """The open polylines of a ``.csv``/``.txt`` table, one a group of rows that blank
    lines separate (as :func:`read_table_lines`), named as lines of ``source``."""
    lines = read_table_lines(path)
    for k, points in enumerate(lines):
        if len(points) < 2:
            raise InputError(f"line {k} has fewer than 2 points", source)
    return [RawLine(p, None, f"{source} line {k}") for k, p in enumerate(lines)]


def read_aux_lines(path: str | os.PathLike) -> list[RawLine]:
    """Auxiliary polylines from a ``.vtp`` or ``.vtk`` file (with their ``xi``/``eta``
    point data, if any), or a ``.csv``/``.txt`` table (:func:`table_aux_lines`)."""
    path = Path(path)
    src = check_file(path, AUX_FORMATS)
    if path.suffix.lower() in (".csv", ".txt"):
        return table_aux_lines(path, src)
    return aux_lines_of(read_polydata(path), src)


# zlib's fastest level: on a 129 x 41 O-grid's file 5.3 ms against the default's 7.4 ms
# (raw), for 0.8 % more bytes; every reader of zlib-compressed VTK XML reads it
VTS_ZLIB_LEVEL = 1


def write_vts(grid: vtkStructuredGrid, path: str | os.PathLike) -> Path:
    """Write ``grid`` atomically (:func:`atomic_path`): complete or absent, never half-written.

    VTK writes in this process, never in a fork of it (forking a process that runs threads
    can deadlock). Ctrl-C or SIGTERM during the writing take effect when VTK's call returns
    (a 1200 x 1200 grid: 3.4-4.4 s on a shared 2-core machine at load average 7); the
    temporary file is then removed and ``path`` is left as it was.
    """
    path = Path(path)
    if path.suffix.lower() != ".vts":
        raise InputError("output must be a .vts file", str(path))
    with atomic_path(path) as tmp:
        writer = vtkXMLStructuredGridWriter()
        writer.SetFileName(str(tmp))
        writer.SetInputData(grid)
        writer.SetDataModeToAppended()
        writer.EncodeAppendedDataOff()  # raw bytes: base64 costs a third more bytes and time
        writer.SetCompressorTypeToZLib()
        writer.SetCompressionLevel(VTS_ZLIB_LEVEL)
        with quiet_vtk():
            ok = writer.Write() == 1
        if not ok:
            raise OSError(f"VTK could not write {path} (disk full or not writable?)")
    return path
