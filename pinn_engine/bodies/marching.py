"""The body grid's march off the wall in C++ (``march.cpp``): :func:`bodygrid.march`'s loop
over the rows, the same operations in the same order, so that every reference grid is
bit-identical to the NumPy loop's (``tests/bodies``), in about a tenth of its time.

The install compiles it beside its source (``setup.py``'s build step, as the jet kernels),
named by a hash of the source and the flags: one built from another source is never loaded.
Where none was built (no compiler at the install, a source changed since), or with
``PINN_MESH_NATIVE=0``, :func:`library` is None and the march runs as NumPy operations:
slower, the same grid. The flags are the compiler's default target's (no ``-march``): the
loop is short rows of scalar work, and ``-ffp-contract=off`` keeps every multiply and add a
rounded operation of its own, as NumPy's are (no fused multiply-add).

Standard library only at import: ``setup.py`` loads this file by its path to build the
library, where the build environment has setuptools alone.
"""

from __future__ import annotations

import ctypes
import functools
import hashlib
import os
from pathlib import Path

SOURCE = Path(__file__).with_name("march.cpp")
FLAGS = ["-O2", "-ffp-contract=off", "-shared", "-fPIC", "-std=c++17"]
STEM = "march"  # the library's file name: march-<hash>.so


def packaged_library(folder: Path = SOURCE.parent) -> Path:
    """The library built from this source with :data:`FLAGS`, in ``folder``."""
    digest = hashlib.sha256(SOURCE.read_bytes() + b"\0" + " ".join(FLAGS).encode())
    return folder / f"{STEM}-{digest.hexdigest()[:16]}.so"


def build_packaged(folder: Path, compiler: str | None, compile_library) -> Path | None:
    """Compile the library into ``folder`` (the install step) by ``compile_library(compiler,
    folder, target, flags, source)`` (the jet kernels' ``native._compile``), the libraries of
    older sources there removed; None, with a one-line message, where there is no compiler
    or the build fails: the march then runs as NumPy operations."""
    if compiler is None:
        print("pinn-mesh: no C++ compiler found; the body grids' march runs as NumPy operations")
        return None
    target = packaged_library(folder)
    try:
        compile_library(compiler, folder, target, FLAGS, SOURCE)
    except (OSError, RuntimeError) as exc:  # native.NativeBuildError: the install goes on
        print(f"pinn-mesh: the body grids' march was not compiled ({exc}); NumPy runs it")
        return None
    for old in folder.glob(f"{STEM}-*.so"):
        if old != target:
            old.unlink()
    return target


@functools.cache
def library() -> ctypes.CDLL | None:
    """The compiled march, or None where it was not built for this source (or
    ``PINN_MESH_NATIVE=0``)."""
    path = packaged_library()
    if os.environ.get("PINN_MESH_NATIVE", "1") == "0" or not path.is_file():
        return None
    return load(path)


def load(path: Path) -> ctypes.CDLL | None:
    """The library at ``path`` with its function's argument types; None where it does not
    load."""
    try:
        lib = ctypes.CDLL(str(path))
    except OSError:
        return None
    p, n, i, d = ctypes.c_void_p, ctypes.c_long, ctypes.c_int, ctypes.c_double
    lib.march_rows.argtypes = [n, n, p, d, i, i, d, n, p, p, p, p, p, p, p, p]
    lib.march_rows.restype = i
    return lib
