"""VTK files read by a new Python: the protection against damaged files that crash VTK's
readers, for all of a run's files by one child started as soon as the run knows them.

VTK's readers abort the process (``std::bad_alloc``), crash (SIGSEGV) or stall on damaged
files, legacy ``.vtk`` (ASCII and binary) and XML ``.vtp`` alike. Some of these crashes
depend on what else is in memory (a damaged offset that reads past an array): a ``.vtp`` that
a separate probe read cleanly 20 times in 20 still aborted this process in 4 reads of 5. So
a child reads the files, with a memory cap and a timeout, and this process only parses what
the child's VTK wrote from the data it read: well-formed. The child is a new Python
(``subprocess``), never a fork of this process: forking a process that runs threads
(ParaView, a notebook, a Dask worker, torch's thread pool) can deadlock the child.

The child costs about 0.18 s, mostly its Python and VTK starting. :func:`prefetch` starts
one child for all the files a run names (a boundary and its auxiliary lines: one start, not
one a file) before the run imports the engine, so that the child reads while this process
imports. Stdlib only, for that reason. A process that reads the files of many runs (a batch
worker) asks for one long-lived child instead (:func:`serve`), which reads file after file.
"""

from __future__ import annotations

import atexit
import hashlib
import json
import logging
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from collections import OrderedDict
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import IO

log = logging.getLogger(__name__)
VTK_FORMATS = (".vtp", ".vtk", ".stl")  # the files VTK's readers read
MAX_FILE_BYTES = 256 * 1024 * 1024  # larger inputs are refused before reading
PROBE_TIMEOUT = 60.0  # seconds reading in the child may take before the file counts as damaged
PROBE_MEMORY = 2**30  # extra address space the child may take, plus 64 bytes a byte of file
Key = tuple[str, bytes]  # a file's reader (its extension) and the digest of its content
Read = tuple[str | None, bytes]  # what is wrong with a file (None: nothing), its polydata

# The child: a new Python (started, never forked) that imports VTK alone (without numpy where
# VTK allows), caps its address space (Linux) and, for each file, says "reading", reads it and
# prints the lengths of VTK's error text and of the polydata (binary legacy VTK), then both.
# Arguments: the extra address space, this process's sys.path (JSON), the files; or "--serve"
# and the files on stdin, one a line, each after its own extra address space and a tab.
_CHILD_CODE = """\
import json, os, sys
extra, paths = int(sys.argv[1]), sys.argv[3:]
sys.path[:0] = json.loads(sys.argv[2])
serving = paths == ["--serve"]
kinds = {".vtp", ".stl"} if serving else {os.path.splitext(path)[1].lower() for path in paths}
def vtk():
    from vtkmodules.vtkCommonCore import vtkLogger, vtkOutputWindow, vtkStringOutputWindow
    from vtkmodules.vtkIOLegacy import vtkPolyDataReader, vtkPolyDataWriter
    readers = {}
    if ".vtp" in kinds:
        from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
        readers[".vtp"] = vtkXMLPolyDataReader
    if ".stl" in kinds:
        from vtkmodules.vtkIOGeometry import vtkSTLReader
        readers[".stl"] = vtkSTLReader
    return vtkLogger, vtkOutputWindow, vtkStringOutputWindow, vtkPolyDataWriter, readers
sys.modules["numpy"] = None
try:
    vtkLogger, vtkOutputWindow, vtkStringOutputWindow, vtkPolyDataWriter, readers = vtk()
except ImportError:  # a VTK that needs numpy
    del sys.modules["numpy"]
    vtkLogger, vtkOutputWindow, vtkStringOutputWindow, vtkPolyDataWriter, readers = vtk()
from vtkmodules.vtkIOLegacy import vtkPolyDataReader as Legacy
from vtkmodules.vtkCommonCore import vtkObject
vtkObject.GlobalWarningDisplayOn()
vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
def cap(extra):
    try:
        import resource
        with open("/proc/self/statm") as f:
            size = int(f.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
        hard = resource.getrlimit(resource.RLIMIT_AS)[1]
        cap = size + extra if hard == resource.RLIM_INFINITY else min(size + extra, hard)
        resource.setrlimit(resource.RLIMIT_AS, (cap, hard))
    except (ImportError, OSError, ValueError):
        pass
def text_of(window):
    text = window.GetOutput() or ""
    return text if isinstance(text, bytes) else text.encode("utf-8", "replace")
out = sys.stdout.buffer
def one(path):
    window = vtkStringOutputWindow()
    vtkOutputWindow.SetInstance(window)
    reader = readers.get(os.path.splitext(path)[1].lower(), Legacy)()
    reader.SetFileName(path)
    out.write(b"reading\\n")
    out.flush()
    reader.Update()
    text, data = text_of(window), b""
    if b"ERROR" not in text:
        writer = vtkPolyDataWriter()
        writer.SetInputData(reader.GetOutput())
        writer.SetFileTypeToBinary()
        writer.WriteToOutputStringOn()
        writer.Write()
        data = writer.GetOutputStdString()
        if isinstance(data, str):  # VTK hands back str when the bytes happen to be UTF-8
            data = data.encode("utf-8", "surrogateescape")
        text = text_of(window)
    out.write(b"%d %d\\n" % (len(text), len(data)) + text + data)
    out.flush()
if serving:
    for line in sys.stdin:
        extra, path = line.rstrip("\\n").split("\\t", 1)
        cap(int(extra))
        one(path)
else:
    cap(extra)
    for path in paths:
        one(path)
"""
_MARKER = b"reading\n"
_READ: OrderedDict[Key, bytes] = OrderedDict()  # clean data of the files read, newest last
_READ_KEPT = 16  # files kept, each up to 16 MiB of clean data
_KEPT_BYTES = 16 << 20


def first_error(text: str | bytes | None) -> str | None:
    """The first error in VTK's output text, as one short printable line; None if none."""
    text = text or ""
    if isinstance(text, bytes):  # VTK hands back bytes when the text is not UTF-8
        text = text.decode("utf-8", errors="replace")
    found = re.search(r"ERROR:[^\n]*\n[^\n]*?\): ([^\n]*)", text)
    if not found and "ERROR" not in text:
        return None
    message = found.group(1) if found else text
    message = "".join(c if c.isprintable() and c.isascii() else "?" for c in message)
    return " ".join(message.split())[:100] or "error"


def _child_python() -> str | None:
    """The Python to start the reading child with: this one, where it is a Python
    interpreter; None where Python is embedded in another program (ParaView's GUI:
    ``sys.executable`` is then that program, or empty)."""
    exe = sys.executable
    return exe if exe and Path(exe).name.lower().startswith("python") else None


def _key(path: Path) -> Key:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return path.suffix.lower(), h.digest()


def _death(code: int) -> str:
    """What a child's exit status ``code`` (not 0) says happened to it."""
    if code < 0:  # POSIX: killed by a signal
        try:
            return f"crashed ({signal.Signals(-code).name})"
        except ValueError:
            return f"crashed (signal {-code})"
    if code >= 0xC0000000:  # Windows: an NTSTATUS exception code (access violation ...)
        return f"crashed (exception 0x{code:08X})"
    if code == 3 and os.name == "nt":  # Windows: abort()
        return "crashed (abort)"
    return f"failed (status {code})"


def _parse(out: bytes, keys: list[Key], status: int | None) -> dict[Key, Read]:
    """The files' results from the child's output, for the files it got to. The file it
    was reading when it died (``status``: its exit status, None if it was stopped at the
    timeout) is damaged; those after it are not in the result."""
    results: dict[Key, Read] = {}
    pos = 0
    for key in keys:
        if not out.startswith(_MARKER, pos):  # never got here: no VTK, or died before
            break
        pos += len(_MARKER)
        end = out.find(b"\n", pos)
        sizes = out[pos:end].split() if end >= 0 else []
        whole = len(sizes) == 2 and end + 1 + int(sizes[0]) + int(sizes[1]) <= len(out)
        if not whole:  # died or stopped while reading this file
            if status is None:
                results[key] = (f"VTK's reader did not finish in {PROBE_TIMEOUT:g} s on it", b"")
            elif status != 0:
                results[key] = (f"VTK's reader {_death(status)} on it", b"")
            break
        pos, n_text = end + 1, int(sizes[0])
        error = first_error(out[pos : pos + n_text])
        data = out[pos + n_text : pos + n_text + int(sizes[1])]
        pos += n_text + len(data)
        results[key] = (f"VTK: {error}", b"") if error else (None, data)
    return results


@dataclass
class _Child:
    """A child reading files; its output goes to a temporary file, so it never waits."""

    process: subprocess.Popen
    output: IO[bytes]
    keys: list[Key]
    started: float

    def finish(self) -> dict[Key, Read]:
        """Wait for the child (up to :data:`PROBE_TIMEOUT` from its start) and parse what it
        wrote; the clean files are kept for later reads."""
        try:
            self.process.wait(timeout=max(0.0, PROBE_TIMEOUT - (time.monotonic() - self.started)))
            status = self.process.returncode
        except subprocess.TimeoutExpired:
            self.stop()
            status = None
        self.output.seek(0)
        results = _parse(self.output.read(), self.keys, status)
        self.output.close()
        _keep(results)
        return results

    def stop(self) -> None:
        self.process.kill()
        self.process.wait()


_PENDING: list[_Child] = []  # children started by prefetch, not asked for yet


def _keep(results: dict[Key, Read]) -> None:
    """Keep the clean files' data for later reads of the same content."""
    for key, (problem, data) in results.items():
        if problem is None and len(data) <= _KEPT_BYTES:
            _READ[key] = data
            while len(_READ) > _READ_KEPT:
                _READ.popitem(last=False)


class _Server:
    """One child that reads file after file for a process that reads many (a batch worker:
    one start, not one a case), in the order they were asked for; a file it dies or stalls
    on is named as a one-file child's would be, and the child is not used again."""

    def __init__(self, python: str) -> None:
        self.process = subprocess.Popen(
            [python, "-c", _CHILD_CODE, "0", json.dumps(sys.path), "--serve"],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
        )
        self.pending: list[Key] = []
        self.buffer = b""
        self.dead = False

    def ask(self, path: Path) -> Key:
        """Ask for ``path`` (once while it is pending); its key."""
        key = _key(path)
        if key not in self.pending:
            extra = PROBE_MEMORY + 64 * path.stat().st_size
            try:
                self.process.stdin.write(f"{extra}\t{path}\n".encode())
                self.process.stdin.flush()
            except OSError:  # the child is gone: the next read starts another
                self.dead = True
                return key
            self.pending.append(key)
        return key

    def take(self, key: Key) -> Read | None:
        """The result of ``key`` (asked for), those asked before it kept on the way; None
        where the child died before it got to it."""
        import select

        while self.pending and not self.dead:
            first = self.pending[0]
            deadline = time.monotonic() + PROBE_TIMEOUT
            while not self._whole():
                left = deadline - time.monotonic()
                ready = select.select([self.process.stdout], [], [], max(left, 0.0))[0]
                chunk = os.read(self.process.stdout.fileno(), 1 << 20) if ready else None
                if not chunk:  # stalled (None) or died (b"")
                    if chunk is None:
                        self.process.kill()
                    status = None if chunk is None else self.process.wait()
                    self.dead = True
                    found = _parse(self.buffer, [first], status).get(first)
                    return found if first == key else None
                self.buffer += chunk
            size = self._whole()
            results = _parse(self.buffer[:size], [first], 0)
            self.buffer = self.buffer[size:]
            self.pending.pop(0)
            _keep(results)
            if first == key:
                return results.get(key)
        return None

    def _whole(self) -> int:
        """The length of the first whole record in the buffer, 0 if there is none yet."""
        if not self.buffer.startswith(_MARKER):
            return 0
        end = self.buffer.find(b"\n", len(_MARKER))
        sizes = self.buffer[len(_MARKER) : end].split() if end >= 0 else []
        whole = end + 1 + sum(map(int, sizes)) if len(sizes) == 2 else 0
        return whole if whole and whole <= len(self.buffer) else 0

    def stop(self) -> None:
        self.process.kill()
        self.process.wait()


_SERVER: list[_Server] = []  # the serving child of a process that asked for one (serve)


def serve() -> None:
    """Read this process's VTK files by one long-lived child from now on (a batch worker's
    cases: the child's start, about 0.2 s, once a worker instead of once a case). POSIX only
    (the replies are waited for with ``select``); elsewhere a child a run stays."""
    if os.name == "posix" and not _SERVER and not os.environ.get("PINN_MESH_NO_CHILD"):
        python = _child_python()
        if python is not None:
            try:
                _SERVER.append(_Server(python))
            except OSError as exc:  # no child could start: a child a run, as before
                log.debug("no serving child: %s", exc)


def _server() -> _Server | None:
    """The serving child, a new one where the last died; None where this process does not
    serve (:func:`serve`)."""
    if _SERVER and _SERVER[0].dead:
        _SERVER.pop().stop()
        serve()
    return _SERVER[0] if _SERVER else None


def _start(paths: list[Path]) -> _Child | None:
    """A child reading ``paths``; None where none can start (no Python to start)."""
    python = _child_python()
    if python is None or not paths:
        return None
    keys = [_key(path) for path in paths]
    memory = PROBE_MEMORY + 64 * sum(path.stat().st_size for path in paths)
    command = [python, "-c", _CHILD_CODE, str(memory), json.dumps(sys.path)]
    output = tempfile.TemporaryFile()
    try:
        process = subprocess.Popen(
            [*command, *map(str, paths)],
            stdin=subprocess.DEVNULL,
            stdout=output,
            stderr=subprocess.DEVNULL,
            creationflags=getattr(subprocess, "CREATE_NO_WINDOW", 0),  # no console (Windows)
        )
    except OSError as exc:  # the child could not start
        output.close()
        log.debug("%s read in this process: %s", paths, exc)
        return None
    return _Child(process, output, keys, time.monotonic())


def _readable(path: str | os.PathLike) -> Path | None:
    """``path`` where it names a VTK file that a read would get to (else None)."""
    try:
        path = Path(path)
        size = path.stat().st_size if path.suffix.lower() in VTK_FORMATS else 0
        return path if path.is_file() and 0 < size <= MAX_FILE_BYTES else None
    except (OSError, ValueError, TypeError):
        return None


def prefetch(paths: Iterable[str | os.PathLike | None]) -> None:
    """Start one child reading the VTK files among ``paths`` that were not read yet; each is
    then taken from it by :func:`read`. Others (missing, not VTK) are left to the reader."""
    if os.environ.get("PINN_MESH_NO_CHILD"):
        return
    files = [path for path in map(_readable, filter(None, paths)) if path is not None]
    server = _server()
    if server is not None:  # asked of the serving child, which reads them in order
        for path in files:
            if _key(path) not in _READ:
                server.ask(path)
        return
    try:
        child = _start([path for path in files if _key(path) not in _READ])
    except OSError:  # changed under us: the reads report it
        return
    if child is not None:
        _PENDING.append(child)


def read(path: Path) -> Read | None:
    """Read the VTK file ``path`` in a child process (one :func:`prefetch` started, else a
    new one): (what is wrong with it, None if nothing; the polydata as a binary legacy VTK
    string). None where no child could read it (no Python to start, no VTK there,
    ``PINN_MESH_NO_CHILD=1``): then this process reads the file itself. A file of the same
    content is read once per process."""
    if os.environ.get("PINN_MESH_NO_CHILD"):
        return None
    key = _key(path)
    for child in [c for c in _PENDING if key in c.keys]:
        _PENDING.remove(child)
        found = child.finish().get(key)
        if found is not None:
            return found
    if key in _READ:
        _READ.move_to_end(key)
        return None, _READ[key]
    server = _server()
    if server is not None:
        found = server.take(server.ask(path))
        if found is not None or not server.dead:
            return found
    child = _start([path])
    return None if child is None else child.finish().get(key)


def stop_pending() -> None:
    """End the children that :func:`prefetch` started and no read asked for (a run refused
    before it read its files): a later run in this process reads afresh."""
    while _PENDING:
        child = _PENDING.pop()
        child.stop()
        child.output.close()


@atexit.register
def _stop_children() -> None:
    """The unread and the serving children end with this process."""
    stop_pending()
    while _SERVER:
        _SERVER.pop().stop()
