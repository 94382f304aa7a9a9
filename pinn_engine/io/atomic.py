"""Files written atomically: complete or absent, never half-written (``atomic_path``), and
a place checked writable before any meshing. Standard library only, so that a writer needs
none of the readers' VTK (``io.fileio`` re-exports these)."""

from __future__ import annotations

import contextlib
import os
import signal
import tempfile
from pathlib import Path

from pinn_engine.errors import InputError


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


def umask() -> int:
    """The process's file mode mask (read by setting it and setting it back)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def check_writable(path: str | os.PathLike) -> None:
    """Refuse (one line, before any meshing) a ``path`` that cannot be written: the nearest
    existing folder above it must take a new file."""
    place = Path(path).absolute().parent
    while not place.exists() and place != place.parent:
        place = place.parent
    if not place.is_dir():
        raise InputError(f"cannot be written: {str(place)!r} is not a folder", str(path))
    try:  # a file made and removed at once: what os.access cannot tell (root, /proc)
        with tempfile.TemporaryFile(dir=place):
            pass
    except OSError as exc:
        raise InputError(
            f"cannot be written: the folder {str(place)!r} takes no new file "
            f"({exc.strerror or exc})",
            str(path),
        ) from None


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike, suffix: str = ".part"):
    """Yield a temporary name next to ``path``; on success it replaces ``path`` atomically.

    The one way this package writes a file: the caller writes the temporary file (in this
    process), which is flushed to disk (``fsync``) and renamed over ``path``. On any failure
    or interruption the temporary file is removed and ``path`` is untouched, so the file is
    complete or absent, never half-written; if the process is killed, ``path`` is untouched
    and the temporary file stays. Concurrent writers of the same ``path`` each use their own
    temporary name; the last to finish wins.
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
        with open(tmp, "rb+") as f:  # on disk before it takes the target's name
            os.fsync(f.fileno())
        os.chmod(tmp, 0o666 & ~umask())  # mkstemp makes 0600; give the usual permissions
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
