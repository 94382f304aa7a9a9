"""Reading boundaries and auxiliary lines, writing grids.

VTK only (no pyvista), so that the ParaView plugin can use it.
"""

from __future__ import annotations

import contextlib
import os
import re
import signal
import tempfile
from pathlib import Path

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkLogger, vtkObject, vtkOutputWindow, vtkStringOutputWindow
from vtkmodules.vtkCommonDataModel import vtkPolyData, vtkStructuredGrid
from vtkmodules.vtkFiltersCore import vtkStripper
from vtkmodules.vtkIOLegacy import vtkPolyDataReader
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLStructuredGridWriter

from pinn_engine.errors import InputError
from pinn_engine.geometry.auxlines import RawLine
from pinn_engine.geometry.boundary import MAX_POINTS

BOUNDARY_FORMATS = (".vtp", ".vtk", ".csv", ".txt")
AUX_FORMATS = (".vtp", ".vtk")
MAX_FILE_BYTES = 256 * 1024 * 1024  # larger inputs are refused before reading


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

    def first_error() -> str | None:
        text = window.GetOutput() or ""
        if isinstance(text, bytes):  # VTK hands back bytes when the text is not UTF-8
            text = text.decode("utf-8", errors="replace")
        found = re.search(r"ERROR:[^\n]*\n[^\n]*?\): ([^\n]*)", text)
        if not found and "ERROR" not in text:
            return None
        message = found.group(1) if found else text
        message = "".join(c if c.isprintable() and c.isascii() else "?" for c in message)
        return " ".join(message.split())[:100] or "error"

    try:
        yield first_error
    finally:
        vtkOutputWindow.SetInstance(previous_window)
        vtkObject.SetGlobalWarningDisplay(previous_display)
        vtkLogger.SetStderrVerbosity(previous_verbosity)


PROBE_TIMEOUT = 60.0  # seconds a probing read may take before the file counts as damaged


def _limit_memory(extra: int) -> None:
    """Cap this process's address space at its current size plus ``extra`` bytes (Linux)."""
    try:
        import resource

        with open("/proc/self/statm") as f:
            current = int(f.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
        resource.setrlimit(resource.RLIMIT_AS, (current + extra, resource.RLIM_INFINITY))
    except (ImportError, OSError, ValueError):
        pass


def _forked(function, timeout: float | None = None, memory: int | None = None) -> str | None:
    """Run ``function()`` in a forked child process and wait for it, staying interruptible.

    Returns None when the child ended normally and ``function`` returned None or True; the
    text that ``function`` returned; or what happened to the child. On Ctrl-C or SIGTERM in
    the parent, or after ``timeout`` seconds, the child is killed. ``memory`` caps the child's
    extra address space, so that a damaged size field fails fast instead of swapping. The
    child leaves with ``os._exit``: no Python clean-up runs twice.
    """
    import time

    read_end, write_end = os.pipe()
    held = {signal.SIGINT, signal.SIGTERM}
    # Hold the signals over the fork: a Ctrl-C landing in Python's fork hooks would be
    # swallowed there ("Exception ignored"); held, it reaches the parent's wait loop below.
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, held)
    try:
        pid = os.fork()
    except BaseException:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)
        raise
    if pid == 0:  # the child (it starts with no pending signals)
        code = 1
        try:
            import faulthandler

            signal.signal(signal.SIGINT, signal.SIG_DFL)
            signal.signal(signal.SIGTERM, signal.SIG_DFL)
            signal.pthread_sigmask(signal.SIG_SETMASK, previous)
            os.close(read_end)
            faulthandler.disable()
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, 1)
            os.dup2(devnull, 2)
            if memory:
                _limit_memory(memory)
            answer = function()
            if isinstance(answer, str):
                os.write(write_end, answer.encode("utf-8", "replace")[:4000])
                code = 3
            else:
                code = 0 if answer in (None, True) else 1
        finally:
            os._exit(code)
    deadline = time.monotonic() + timeout if timeout else None
    delay, done, status = 0.001, 0, 0
    try:
        os.close(write_end)
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)  # a held Ctrl-C lands here
        while True:
            done, status = os.waitpid(pid, os.WNOHANG)
            if done:
                break
            if deadline is not None and time.monotonic() > deadline:
                return f"did not finish in {timeout:g} s"
            time.sleep(delay)
            delay = min(delay * 2, 0.05)
        message = os.read(read_end, 4096).decode("utf-8", "replace")
    finally:
        os.close(read_end)
        if not done:
            with contextlib.suppress(OSError):
                os.kill(pid, signal.SIGKILL)
                os.waitpid(pid, 0)
    if os.WIFSIGNALED(status):
        return f"crashed ({signal.Signals(os.WTERMSIG(status)).name})"
    code = os.WEXITSTATUS(status)
    if code == 3:
        return message
    return None if code == 0 else f"failed (status {code})"


def _probe_read(path: Path) -> str | None:
    """Read ``path`` with VTK in a forked child first; what is wrong with it, if anything.

    VTK's readers can abort the whole process (``std::bad_alloc`` on a damaged size field) or
    crash on a malformed file. A probe in a child process, with a memory cap, turns that into
    a clear error instead of a crash or a long stall. Where ``fork`` is missing (Windows) no
    probe is made.
    """
    if not hasattr(os, "fork") or os.environ.get("PINN_MESH_NO_FORK"):
        return None

    def read() -> str | None:
        with _captured_vtk_errors() as vtk_error:
            _vtk_reader(path).Update()
            error = vtk_error()
        return f"VTK: {error}" if error else None

    memory = 2**30 + 64 * path.stat().st_size
    problem = _forked(read, PROBE_TIMEOUT, memory)
    if problem is None or problem.startswith("failed"):  # the probe itself could not run
        return None
    if problem.startswith("crashed") or problem.startswith("did not"):
        return f"VTK's reader {problem} on it"
    return problem


def _vtk_reader(path: Path):
    reader = vtkXMLPolyDataReader() if path.suffix.lower() == ".vtp" else vtkPolyDataReader()
    reader.SetFileName(str(path))
    return reader


def read_polydata(path: Path) -> vtkPolyData:
    """Read a ``.vtp`` or legacy ``.vtk`` polydata file."""
    src = str(path)
    reader = _vtk_reader(path)
    with _captured_vtk_errors():
        if isinstance(reader, vtkPolyDataReader):
            if not reader.IsFilePolyData():
                raise InputError("not a VTK polydata file", src)
        elif not reader.CanReadFile(src):
            raise InputError("not a VTK XML polydata file", src)
    problem = _probe_read(path)
    if problem:
        raise InputError(f"is damaged or unreadable ({problem})", src)
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
        only_lines = vtkPolyData()
        only_lines.SetPoints(poly.GetPoints())
        only_lines.SetLines(poly.GetLines())
        stripper = vtkStripper()
        stripper.SetInputData(only_lines)
        stripper.JoinContiguousSegmentsOn()
        with _quiet_vtk():
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


def read_table(path: Path) -> np.ndarray:
    """Read ``x,y[,z]`` rows (comma or whitespace separated, optional header)."""
    src = str(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(f"cannot be read ({exc.strerror or exc})", src) from None
    if b"\0" in data:
        raise InputError("is a binary file, not a text table of x,y rows", src)
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError("is not UTF-8 text; expected rows of x,y", src) from exc
    rows: list[list[float]] = []
    header = False
    for number, line in enumerate(text.splitlines(), start=1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        fields = [f for f in line.replace(",", " ").replace(";", " ").split() if f]
        try:
            values = [float(f) for f in fields]
        except ValueError:
            if not rows and not header:
                header = True  # one header row before the data
                continue
            raise InputError(f"line {number} is not numeric: {line[:40]!r}", src) from None
        if len(values) not in (2, 3):
            raise InputError(f"line {number} has {len(values)} columns; expected x,y or x,y,z", src)
        if rows and len(values) != len(rows[0]):
            raise InputError(
                f"line {number} has {len(values)} columns, earlier lines {len(rows[0])}", src
            )
        rows.append(values)
        if len(rows) > MAX_POINTS:
            raise InputError(f"holds more than {MAX_POINTS} rows; resample it", src)
    if not rows:
        raise InputError("holds no x,y rows", src)
    return _checked(np.array(rows, dtype=float), src)


def read_boundary_points(path: str | os.PathLike) -> np.ndarray:
    """The boundary ring (n, 2) or (n, 3) of a ``.vtp``, ``.vtk``, ``.csv`` or ``.txt`` file."""
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


def read_aux_lines(path: str | os.PathLike) -> list[RawLine]:
    """Auxiliary polylines from a ``.vtp`` or ``.vtk`` file."""
    path = Path(path)
    src = _check_file(path, AUX_FORMATS)
    return aux_lines_of(read_polydata(path), src)


@contextlib.contextmanager
def _signals_deferred():
    """Hold SIGINT and SIGTERM back (delivered on exit) around a few critical lines."""
    sigs = {signal.SIGINT, signal.SIGTERM}
    try:
        old = signal.pthread_sigmask(signal.SIG_BLOCK, sigs)
    except (AttributeError, ValueError, OSError):  # no POSIX masks (Windows)
        yield
        return
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike, suffix: str = ".part"):
    """Yield a temporary name next to ``path``; on success it replaces ``path`` atomically.

    On any failure or interruption the temporary file is removed and ``path`` is untouched,
    so the file is complete or absent, never half-written. Concurrent writers of the same
    ``path`` each use their own temporary name; the last to finish wins.
    """
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(
            f"cannot create its folder {str(path.parent)!r} ({exc.strerror or exc})", str(path)
        ) from None
    fd, tmp = tempfile.mkstemp(
        prefix=f".{path.name}.",
        suffix=f".part{suffix}" if suffix != ".part" else suffix,
        dir=path.parent,
    )
    os.close(fd)
    try:
        yield Path(tmp)
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600; give the usual permissions
        with _signals_deferred():
            os.replace(tmp, path)
    finally:
        with _signals_deferred():
            with contextlib.suppress(FileNotFoundError):
                os.unlink(tmp)


def write_text_atomic(path: str | os.PathLike, text: str) -> Path:
    """Write a text file atomically (complete or absent)."""
    with atomic_path(path) as tmp:
        tmp.write_text(text)
    return Path(path)


def write_vts(grid: vtkStructuredGrid, path: str | os.PathLike) -> Path:
    """Write ``grid`` atomically: the file is complete or absent, never half-written.

    VTK writes a temporary file beside ``path`` that then replaces ``path`` in one step. The
    writing runs in a forked child process (where ``fork`` exists): VTK's long stretches of
    C++ cannot be interrupted, a child can, so Ctrl-C or SIGTERM end the command at once.
    """
    path = Path(path)
    if path.suffix.lower() != ".vts":
        raise InputError("output must be a .vts file", str(path))
    with atomic_path(path) as tmp:
        writer = vtkXMLStructuredGridWriter()
        writer.SetFileName(str(tmp))
        writer.SetInputData(grid)
        writer.SetDataModeToAppended()
        writer.SetCompressorTypeToZLib()

        def write() -> bool:
            with _quiet_vtk():
                ok = writer.Write() == 1
            if ok:
                with open(tmp, "rb+") as f:
                    os.fsync(f.fileno())
            return ok

        if hasattr(os, "fork") and not os.environ.get("PINN_MESH_NO_FORK"):
            problem = _forked(write)
        else:
            problem = None if write() else "failed"
        if problem:
            raise OSError(f"VTK could not write {path} ({problem}; disk full or not writable?)")
    return path
