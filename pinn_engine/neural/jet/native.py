"""The networks' jet in C++ (``kernels.cpp``), compiled with the system compiler.

Installing the package compiles it into the package (``setup.py``'s ``build_jet`` step:
:func:`build_packaged`), named by a hash of the source, the flags and the CPU
(``-march=native`` code runs only on the CPU it was built for): :func:`kernels` loads that
library when it was built for this source and CPU. Otherwise (a wheel built on another
machine, a source changed since the install) the library is built once, with a one-line
warning, into a per-user cache (``$PINN_MESH_CACHE``, else ``$XDG_CACHE_HOME/pinn-mesh`` or
``~/.cache/pinn-mesh``), keyed as well by the compiler (its path and version). Either is
loaded with ctypes: no Python or torch headers. Without a C++ compiler, with
``PINN_MESH_NATIVE=0``, or when the build fails (:class:`NativeBuildError`), :func:`kernels`
returns None and the networks use the same formulas as torch operations (slower, same
results); a missing compiler and a failed build each say so in a one-line
``errors.JetKernelsWarning`` (Python's warnings filters reach it). ``PINN_MESH_PORTABLE=1``
at the install builds the library for any CPU of the platform (a wheel for other machines,
docs/install.md), loaded where no library for this CPU is.

Nothing is loaded from a folder that another user could write to. The cache folder is
created with mode 0700; before a library is loaded, the folder and the file must belong to
this user and be writable by nobody else (POSIX; on Windows the user's profile and
temporary folders are private already). Where the cache folder fails that, the per-user
folder in the temporary directory is tried, then a fresh private folder for this process
alone, each time with a warning. The package's own library is trusted as its Python code is.
"""

from __future__ import annotations

import ctypes
import functools
import hashlib
import logging
import os
import platform
import shutil
import stat
import subprocess
import tempfile
import warnings
from pathlib import Path

from pinn_engine.errors import JetKernelsWarning

log = logging.getLogger(__name__)
SOURCE = Path(__file__).with_name("kernels.cpp")
PACKAGED_DIR = SOURCE.parent  # where the install step puts the library (build_packaged)
FLAGS = ["-O3", "-march=native", "-fno-trapping-math", "-shared", "-fPIC", "-std=c++17", "-pthread"]
# a wheel for other machines (PINN_MESH_PORTABLE=1 at its build): the compiler's default
# target instead of this CPU's, so that it runs on any CPU of the platform
PORTABLE_FLAGS = [f for f in FLAGS if f != "-march=native"]
PORTABLE = "portable"  # the library's CPU key when built so
CPUINFO = Path("/proc/cpuinfo")
# seconds a build may take: 50 s on 2 idle cores, over 120 s on busy ones, where a finished
# build still beats the torch fallback's 2x slower training on every later run
COMPILE_TIMEOUT = 600.0
# what training without the kernels costs (docs/install.md: fig2's default training)
NO_COMPILER_COST = "slower"
# said where the kernels are compiled (the install, or a run the install did not build for):
# 93 s measured on 2 busy cores (docs/install.md)
COMPILING = (
    "pinn-mesh: compiling the network's C++ jet kernels into %s, once per source and CPU "
    "(a minute or two)"
)
# /proc/cpuinfo fields (first processor) that name the CPU and what it can run: x86 and ARM
_CPU_FIELDS = (
    "vendor_id",
    "cpu family",
    "model",
    "model name",
    "cpu model",
    "hardware",
    "cpu implementer",
    "cpu architecture",
    "cpu variant",
    "cpu part",
    "isa",
    "flags",
    "features",
)


class NativeBuildError(RuntimeError):
    """The C++ kernels could not be built; the message names the compiler command and
    ends with the end of its error output."""


class NotPrivateError(OSError):
    """A cache folder or library that another user could have written."""


def _cache_dir() -> Path:
    if os.environ.get("PINN_MESH_CACHE"):
        return Path(os.environ["PINN_MESH_CACHE"])
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "pinn-mesh"


def _temporary_cache_dir() -> Path:
    """The per-user folder in the temporary directory (the fallback for an unusable cache)."""
    user = os.getuid() if hasattr(os, "getuid") else os.environ.get("USERNAME", "user")
    return Path(tempfile.gettempdir()) / f"pinn-mesh-{user}"


def _output(command: list[str]) -> str:
    """The standard output of ``command``, stripped; "" where it cannot run or fails."""
    try:
        done = subprocess.run(command, capture_output=True, text=True, timeout=10)
    except (OSError, subprocess.SubprocessError):
        return ""
    return done.stdout.strip() if done.returncode == 0 else ""


def _linux_cpu() -> str:
    """The first processor's identifying fields of ``/proc/cpuinfo`` (model, flags)."""
    try:
        text = CPUINFO.read_text(errors="replace")
    except OSError:
        return ""
    found = {}
    for line in text.split("\n\n", 1)[0].splitlines():
        key, sep, value = line.partition(":")
        key = key.strip().lower()
        if sep and key in _CPU_FIELDS and key not in found:
            found[key] = " ".join(value.split())
    return "; ".join(f"{k}={found[k]}" for k in _CPU_FIELDS if found.get(k))


def _cpu_id() -> str:
    """What identifies this CPU for ``-march=native`` code; never empty.

    The machine (``platform.machine()``) and the CPU's model: ``/proc/cpuinfo`` on Linux
    (model name and flags), ``sysctl -n machdep.cpu.brand_string`` (and the feature list
    where there is one) on macOS, ``platform.processor()`` on Windows. Where none of these
    says anything, the host's name: the build is then kept per machine.
    """
    system = platform.system()
    if system == "Linux":
        model = _linux_cpu()
    elif system == "Darwin":
        model = " ".join(
            _output(["sysctl", "-n", name])
            for name in ("machdep.cpu.brand_string", "machdep.cpu.features")
        ).strip()
    else:
        model = platform.processor()
    if not model:
        model = f"unidentified CPU of host {platform.node() or 'unknown'}"
    return f"{platform.machine() or 'unknown machine'} {system} {model}"


def _hash(parts: list[bytes]) -> str:
    return hashlib.sha256(b"\0".join(parts)).hexdigest()[:16]


def build_key(compiler: str) -> str:
    """The cached library's key: a hash of the source, the compiler's path and version, the
    flags and the CPU (:func:`_cpu_id`); 16 hex digits."""
    version = _output([compiler, "--version"]).splitlines()[:1] or ["unknown version"]
    compiler_path = str(shutil.which(compiler) or compiler)
    return _hash([SOURCE.read_bytes(), compiler_path.encode(), version[0].encode()] + _target())


def _target(portable: bool = False) -> list[bytes]:
    """What the library's code depends on beside its source: the flags and the CPU (none
    for a portable build)."""
    if portable:
        return [" ".join(PORTABLE_FLAGS).encode(), PORTABLE.encode()]
    return [" ".join(FLAGS).encode(), _cpu_id().encode()]


def packaged_library(folder: Path, portable: bool = False) -> Path:
    """The install step's library in ``folder``: named by a hash of the source, the flags
    and the CPU, so that one built for another CPU or an older source is never loaded (a
    portable one, by the source and its flags alone)."""
    return folder / f"jet_kernels-{_hash([SOURCE.read_bytes(), *_target(portable)])}.so"


def _portable_build() -> bool:
    """Whether this build is for other machines: ``PINN_MESH_PORTABLE=1`` (docs/install.md)."""
    return os.environ.get("PINN_MESH_PORTABLE", "0") == "1"


def build_packaged(folder: Path) -> Path | None:
    """Compile the library into the package folder ``folder`` (the install step); the
    libraries of older sources there are removed. None, with a one-line message on stderr,
    where there is no compiler or the build fails: the engine then builds it at first use."""
    compiler = _compiler()
    if compiler is None:
        print("pinn-mesh: no C++ compiler found; the jet kernels are built at first use")
        return None
    portable = _portable_build()
    target = packaged_library(folder, portable)
    kept = _kept_build(target.name)
    if kept is not None:  # an earlier install's (the core, then each extra): no compiling
        print(f"pinn-mesh: the jet kernels for this source and CPU, built before: {kept}")
        shutil.copyfile(kept, target)
    else:
        print(COMPILING % folder)
        try:
            _compile(compiler, folder, target, PORTABLE_FLAGS if portable else FLAGS)
        except NativeBuildError as exc:
            print(f"pinn-mesh: {_one_line(str(exc))}; the jet kernels are built at first use")
            return None
        _keep_build(target)
    for old in folder.glob("jet_kernels-*.so"):
        if old != target:
            old.unlink()
    return target


def _kept_build(name: str) -> Path | None:
    """The library ``name`` an earlier install kept in the user's cache, if it is private."""
    try:
        folder = _private_dir(_cache_dir())
    except OSError:
        return None
    kept = folder / name
    return kept if kept.is_file() and _not_private(kept, folder=False) is None else None


def _keep_build(library: Path) -> None:
    """A copy of an install's library in the user's cache, for the next install (pip builds
    anew for each extra); nothing where the cache cannot take it."""
    try:
        folder = _private_dir(_cache_dir())
        fd, tmp = tempfile.mkstemp(suffix=".so.part", dir=folder)
        os.close(fd)
        shutil.copyfile(library, tmp)
        os.chmod(tmp, 0o700)
        os.replace(tmp, folder / library.name)
    except OSError:
        pass


def _not_private(path: Path, folder: bool) -> str | None:
    """Why ``path`` (a folder or a library file) may hold what another user wrote; None if
    it is this user's alone: owned by this user, writable by no one else, and no link
    (``os.lstat``). Not checked on Windows (no POSIX owners and modes)."""
    if os.name == "nt":
        return None
    info = os.lstat(path)
    if stat.S_ISLNK(info.st_mode):
        return "is a symbolic link"
    if folder and not stat.S_ISDIR(info.st_mode):
        return "is not a folder"
    if not folder and not stat.S_ISREG(info.st_mode):
        return "is not a regular file"
    if info.st_uid != os.getuid():
        return f"belongs to user {info.st_uid}, not to this user ({os.getuid()})"
    if info.st_mode & (stat.S_IWGRP | stat.S_IWOTH):
        return f"is writable by others (mode {stat.S_IMODE(info.st_mode):o})"
    return None


def _private_dir(path: Path) -> Path:
    """``path``, created with mode 0700 if missing; raises ``NotPrivateError`` where it is
    not this user's alone (:func:`_not_private`), ``OSError`` where it cannot be made."""
    path.mkdir(mode=0o700, parents=True, exist_ok=True)
    why = _not_private(path, folder=True)
    if why:
        raise NotPrivateError(f"cache folder {path} {why}")
    return path


def _compile(
    compiler: str, folder: Path, target: Path, flags: list[str] = FLAGS, source: Path = SOURCE
) -> Path:
    """Build the library of ``source`` (the jet kernels') into ``target`` in ``folder`` with
    ``flags``: complete or absent, even if two processes build at once; readable and
    writable by this user alone."""
    fd, tmp = tempfile.mkstemp(suffix=".so.part", dir=folder)
    os.close(fd)
    command = [compiler, *flags, "-o", tmp, str(source)]
    shown = " ".join(command)
    try:
        try:
            done = subprocess.run(command, capture_output=True, text=True, timeout=COMPILE_TIMEOUT)
        except subprocess.TimeoutExpired:
            raise NativeBuildError(f"`{shown}` did not finish in {COMPILE_TIMEOUT:g} s") from None
        except OSError as exc:  # the compiler cannot be run at all
            raise NativeBuildError(f"`{shown}` could not run: {exc}") from None
        if done.returncode != 0:
            tail = (done.stderr or done.stdout or "no output").strip()[-800:]
            raise NativeBuildError(f"`{shown}` failed (exit status {done.returncode}): {tail}")
        os.chmod(tmp, 0o700)  # the compiler's own mode follows the umask (0775 under 002)
        os.replace(tmp, target)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return target


def _built(compiler: str) -> tuple[Path, Path | None]:
    """The library for this source, compiler and CPU: (its path, the fresh folder to remove
    after loading it or None). Found or built in the first private folder of: the cache,
    the per-user folder in the temporary directory, a fresh private folder."""
    name = f"jet_kernels-{build_key(compiler)}.so"
    for candidate in (_cache_dir(), _temporary_cache_dir()):
        try:
            folder = _private_dir(candidate)
            target = folder / name
            if os.path.lexists(target):
                why = _not_private(target, folder=False)
                if why is None:
                    return target, None
                log.warning("not loading %s: it %s; building it again", target, why)
            log.warning(COMPILING, folder)
            return _compile(compiler, folder, target), None
        except NotPrivateError as exc:
            log.warning("%s; not using it for the jet kernels", exc)
        except OSError as exc:  # e.g. a read-only home: try the next folder
            log.info("cannot use %s for the jet kernels (%s)", candidate, exc)
    fresh = Path(tempfile.mkdtemp(prefix="pinn-mesh-"))  # 0700, this user's
    log.warning("jet kernels built in a fresh private folder %s for this process", fresh)
    try:
        return _compile(compiler, fresh, fresh / name), fresh
    except BaseException:
        shutil.rmtree(fresh, ignore_errors=True)
        raise


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


def _compiler() -> str | None:
    return os.environ.get("CXX") or shutil.which("c++") or shutil.which("g++")


def _one_line(text: str, limit: int = 1000) -> str:
    """``text`` as one line of at most ``limit`` characters (its end: where errors are)."""
    return " ".join(text.split())[-limit:]


@functools.cache
def kernels() -> ctypes.CDLL | None:
    """The loaded kernel library, or None where it cannot be built (then torch is used)."""
    if os.environ.get("PINN_MESH_NATIVE", "1") == "0":
        return None
    for portable in (False, True):  # this CPU's build, else a portable wheel's
        packaged = packaged_library(PACKAGED_DIR, portable)
        if packaged.exists():
            try:
                return _bind(ctypes.CDLL(str(packaged)))
            except (OSError, AttributeError) as exc:
                log.warning("not loading %s (%s)", packaged, _one_line(str(exc)))
    compiler = _compiler()
    if not compiler:
        warnings.warn(
            "pinn-mesh: no C++ compiler found (install g++ or set CXX): the network's jets "
            f"run as torch operations, {NO_COMPILER_COST}",
            JetKernelsWarning,
            stacklevel=2,
        )
        return None
    try:
        path, fresh = _built(compiler)
        try:
            return _bind(ctypes.CDLL(str(path)))
        finally:
            if fresh is not None:  # loaded: the file can go (POSIX; Windows keeps it)
                shutil.rmtree(fresh, ignore_errors=True)
    except (OSError, NativeBuildError, AttributeError) as exc:
        warnings.warn(
            f"pinn-mesh: could not build the fused jet kernels ({_one_line(str(exc))}); "
            "using torch operations",
            JetKernelsWarning,
            stacklevel=2,
        )
        return None
