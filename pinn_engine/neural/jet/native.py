"""The networks' jet in C++ (``kernels.cpp``), compiled once with the system compiler.

The library is built on first use into a per-user cache (``$PINN_MESH_CACHE``, else
``$XDG_CACHE_HOME/pinn-mesh`` or ``~/.cache/pinn-mesh``), keyed by the source, the compiler
flags and the CPU, and loaded with ctypes: no Python or torch headers, a few seconds to build.
Without a C++ compiler, or with ``PINN_MESH_NATIVE=0``, :func:`kernels` returns None and the
networks use the same formulas as torch operations (slower, same results).
"""

from __future__ import annotations

import ctypes
import functools
import hashlib
import logging
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

log = logging.getLogger(__name__)
SOURCE = Path(__file__).with_name("kernels.cpp")
FLAGS = ["-O3", "-march=native", "-fno-trapping-math", "-shared", "-fPIC", "-std=c++17", "-pthread"]


def _cache_dir() -> Path:
    if os.environ.get("PINN_MESH_CACHE"):
        return Path(os.environ["PINN_MESH_CACHE"])
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "pinn-mesh"


def _cpu_flags() -> str:
    try:
        with open("/proc/cpuinfo") as f:
            return next((line for line in f if line.startswith("flags")), "")
    except OSError:
        return ""


def _build(compiler: str, cache: Path) -> Path:
    source = SOURCE.read_bytes()
    key = hashlib.sha256(
        b"\0".join([source, " ".join([compiler, *FLAGS]).encode(), _cpu_flags().encode()])
    ).hexdigest()[:16]
    target = cache / f"jet_kernels-{key}.so"
    if target.exists():
        return target
    cache.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(suffix=".so.part", dir=cache)  # complete or absent, even if
    os.close(fd)  # two processes build at once
    try:
        subprocess.run(
            [compiler, *FLAGS, "-o", tmp, str(SOURCE)],
            check=True,
            capture_output=True,
            text=True,
            timeout=120,
        )
        os.replace(tmp, target)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return target


def _bind(lib: ctypes.CDLL) -> ctypes.CDLL:
    p, n, i = ctypes.c_void_p, ctypes.c_ssize_t, ctypes.c_int
    lib.net_workspace.argtypes, lib.net_workspace.restype = [n, n, n, n, i], n
    for suffix in ("f32", "f64"):
        fwd, bwd = getattr(lib, f"net_forward_{suffix}"), getattr(lib, f"net_backward_{suffix}")
        fwd.argtypes, fwd.restype = [i, i, i] + [n] * 5 + [p] * 6, i
        bwd.argtypes, bwd.restype = [i, i, i] + [n] * 5 + [p] * 7, i
        loss = getattr(lib, f"net_loss_{suffix}")
        loss.argtypes, loss.restype = [i, i] + [n] * 5 + [p] * 4 + [n, p, p, i, p, p], i
    return lib


def threads() -> int:
    """Threads for the two sub-networks' jets: ``PINN_MESH_JET_THREADS``, default 1 (two
    measured no faster on the shared 2-core machine this was written on, with other work on
    both cores)."""
    return max(1, int(os.environ.get("PINN_MESH_JET_THREADS") or 1))


@functools.cache
def kernels() -> ctypes.CDLL | None:
    """The loaded kernel library, or None where it cannot be built (then torch is used)."""
    if os.environ.get("PINN_MESH_NATIVE", "1") == "0":
        return None
    compiler = os.environ.get("CXX") or shutil.which("c++") or shutil.which("g++")
    if not compiler:
        log.info("no C++ compiler found: jet layers run as torch operations")
        return None
    try:
        try:
            path = _build(compiler, _cache_dir())
        except OSError:  # e.g. a read-only home: use the temporary directory
            path = _build(compiler, Path(tempfile.gettempdir()) / f"pinn-mesh-{os.getuid()}")
        return _bind(ctypes.CDLL(str(path)))
    except (OSError, subprocess.SubprocessError, AttributeError) as exc:
        detail = getattr(exc, "stderr", "") or exc
        log.warning(
            "could not build the fused jet kernels (%s); using torch operations",
            str(detail).strip()[:500],
        )
        return None
