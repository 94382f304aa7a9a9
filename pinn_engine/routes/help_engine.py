"""Registering a Qt compressed help file (.qch) with the help engine of the ParaView GUI
this Python runs in, so that the panel's "?" and the help's search find a Python plugin's
pages.

ParaView 5.11 registers its own .qch and those a compiled plugin carries
(``vtkPVPlugin::GetBinaryResources``, read by ``pqPluginDocumentationBehavior``); a Python
plugin carries none, and Qt is not wrapped in ParaView's Python. So this calls, with ctypes,
what ``pqPluginDocumentationBehavior`` calls: ``pqApplicationCore::registerDocumentation``,
then the help engine's ``setupData`` and its search engine's ``reindexDocumentation`` (without
which 5.11's help search finds nothing at all: nothing else builds its index). The symbols
are those of the GUI's own libraries (libpqCore, libQt5Help, libQt5Core); where one is
absent (pvpython, pvbatch, a server, a build without Qt help or on another Qt) nothing is
done."""

from __future__ import annotations

import atexit
import contextlib
import ctypes
import os
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path

_P = ctypes.c_void_p
# name: (Itanium C++ ABI symbol, argument types, result type); a method's first argument is
# its object
_FUNCTIONS = {
    "core": ("_ZN17pqApplicationCore8instanceEv", (), _P),
    "register": ("_ZN17pqApplicationCore21registerDocumentationERK7QString", (_P, _P), None),
    "engine": ("_ZN17pqApplicationCore10helpEngineEv", (_P,), _P),
    "setup": ("_ZN15QHelpEngineCore9setupDataEv", (_P,), ctypes.c_bool),
    "search": ("_ZN11QHelpEngine12searchEngineEv", (_P,), _P),
    "reindex": ("_ZN17QHelpSearchEngine20reindexDocumentationEv", (_P,), None),
    # QString(const QChar *unicode, int size): a constructor, its object first
    "qstring": ("_ZN7QStringC1EPK5QChari", (_P, ctypes.c_char_p, ctypes.c_int), None),
}
_PREFIX = "pinn-mesh-help-"  # a GUI's help file: PREFIX<its process id>.qch, in the temp folder
_REGISTERED = []  # the .qch registered with this process's help engine
_KEPT = []  # what lives as long as the GUI: the file name's QString, the session observer


def _function(name: str):
    symbol, arguments, result = _FUNCTIONS[name]
    function = getattr(ctypes.CDLL(None), symbol)
    function.argtypes, function.restype = arguments, result
    return function


def in_gui() -> bool:
    """Whether this process is a ParaView GUI with Qt help whose functions are the ones
    called here (ParaView 5.11's, Qt 5's): all their symbols are loaded."""
    process = ctypes.CDLL(None)
    return all(hasattr(process, symbol) for symbol, _, _ in _FUNCTIONS.values())


def _qstring(text: str):
    """A QString made by the GUI's Qt, kept for the session (the help engine's copy shares
    its data)."""
    utf16 = text.encode("utf-16-le")
    qstring = ctypes.create_string_buffer(ctypes.sizeof(_P))  # a QString is one d-pointer
    _function("qstring")(qstring, utf16, len(utf16) // 2)
    _KEPT.append(qstring)
    return qstring


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)  # no signal: only whether the process exists
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's
        return True
    return True


def _remove_ended(folder: Path) -> None:
    """Remove the help files of GUIs that have ended: a GUI that is killed leaves its own."""
    for old in folder.glob(f"{_PREFIX}*.qch"):
        pid = old.stem.removeprefix(_PREFIX)
        if pid.isdigit() and not _alive(int(pid)):
            with contextlib.suppress(OSError):  # (another user's, in a shared folder)
                old.unlink()


def _register_now(write: Callable[[Path], None]) -> bool:
    """Write the .qch with ``write`` and register it, if the application core exists and it
    is not registered yet; whether it is registered."""
    core = _function("core")()
    if _REGISTERED or not core:
        return bool(_REGISTERED)
    folder = Path(tempfile.gettempdir())
    _remove_ended(folder)
    path = folder / f"{_PREFIX}{os.getpid()}.qch"
    try:
        write(path)
        atexit.register(path.unlink, missing_ok=True)  # as ParaView removes its own copies
    except OSError as exc:  # the filters work on without their help pages
        print(
            f"PINN Mesh plugin: its help pages were not written ({exc}); set TMPDIR to a "
            "writable folder",
            file=sys.stderr,
        )
        return False
    _function("register")(core, _qstring(str(path)))
    engine = _function("engine")(core)
    if engine:  # (none where ParaView was built without Qt help)
        _function("setup")(engine)
        _function("reindex")(_function("search")(engine))
    _REGISTERED.append(path)
    return True


def register(write: Callable[[Path], None]) -> None:
    """Register the .qch that ``write`` writes (to the path it is given) with this GUI's help
    engine: now, or when the GUI's first session starts (a plugin on PV_PLUGIN_PATH is loaded
    before ParaView's application core exists). Nothing where this is no GUI."""
    if not in_gui() or _register_now(write):
        return
    from paraview.modules.vtkRemotingServerManager import vtkSMProxyManager

    def on_session(manager, event):
        _register_now(write)

    _KEPT.append(on_session)  # VTK's own reference to a Python observer is not enough
    manager = vtkSMProxyManager.GetProxyManager()
    manager.AddObserver(vtkSMProxyManager.ActiveSessionChanged, on_session)


def registered() -> list[Path]:
    """The .qch registered with this GUI's help engine (one, once registered)."""
    return list(_REGISTERED)
