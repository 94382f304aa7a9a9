"""A filter's long work run so that the ParaView GUI stays alive: the work in a worker
thread, the thread that called ``RequestData`` polling it, relaying its progress and the
abort answer, and (in the GUI) letting Qt handle its events meanwhile.

ParaView 5.11 handles no GUI event while a filter runs: its progress manager does not
process events (``pqProgressManager::setProgress``), so the window does not repaint, the
abort button cannot be pressed, and the clicks made meanwhile wait in the queue and fire
afterwards. Its progress manager's event filter, active while progress is shown, drops
key and mouse presses on every widget but the progress bar and its abort button; so
processing Qt's events here (``QCoreApplication::processEvents``, with ctypes: Qt is not
wrapped in ParaView's Python) repaints the window, delivers the abort button's click and
drops the other clicks, which are then never replayed. 5.11 also connects the progress
manager's ``abort()`` signal to nothing: :class:`AbortButton` connects it to a QTimer of its
own, whose state says whether it was pressed. Outside the GUI (pvpython, pyvista, a VTK
pipeline) the polling runs all the same and no event is processed.
"""

from __future__ import annotations

import ctypes
import queue
import threading
import time
from collections.abc import Callable
from typing import Any

POLL_SECONDS = 0.05  # between two polls: the GUI's repaint and abort latency
EVENT_MS = 20  # the longest Qt may spend on events at one poll
PARKED_MS = 1 << 30  # the abort timer's interval: it is started, never left to fire
_P = ctypes.c_void_p
# name: (Itanium C++ ABI symbol, argument types, result type); a method's object first
_QT = {
    "app": ("_ZN16QCoreApplication4selfE", None, None),  # data: the application
    "process": (
        "_ZN16QCoreApplication13processEventsE6QFlagsIN10QEventLoop17ProcessEventsFlagEEi",
        (ctypes.c_int, ctypes.c_int),
        None,
    ),
    "core": ("_ZN17pqApplicationCore8instanceEv", (), _P),
    # the progress manager: pqApplicationCore's child (its getter is inline, no symbol)
    "find": (
        "_Z20qt_qFindChild_helperPK7QObjectRK7QStringRK11QMetaObject6QFlagsIN2Qt15FindChildOptionEE",
        (_P, _P, _P, ctypes.c_int),
        _P,
    ),
    "meta": ("_ZN17pqProgressManager16staticMetaObjectE", None, None),  # data: its address
    "qstring": ("_ZN7QStringC1EPK5QChari", (_P, ctypes.c_char_p, ctypes.c_int), None),
    "enable_abort": ("_ZN17pqProgressManager14setEnableAbortEb", (_P, ctypes.c_bool), None),
    "unblock": ("_ZN17pqProgressManager13unblockEventsEb", (_P, ctypes.c_bool), ctypes.c_bool),
    "cursor": ("_ZN7QCursor3posEv", (), ctypes.c_uint64),  # a QPoint (x, y) in one register
    "widget_at": ("_ZN12QApplication8widgetAtERK6QPoint", (_P,), _P),
    "cast": ("_ZNK11QMetaObject4castEP7QObject", (_P, _P), _P),
    "bar_meta": ("_ZN16pqProgressWidget16staticMetaObjectE", None, None),  # data
    "timer": ("_ZN6QTimerC1EP7QObject", (_P, _P), None),
    "interval": ("_ZN6QTimer11setIntervalEi", (_P, ctypes.c_int), None),
    "stop": ("_ZN6QTimer4stopEv", (_P,), None),
    # QObject::connect(sender, SIGNAL, receiver, SLOT, type): QMetaObject::Connection
    # returned through a hidden first argument
    "connect": (
        "_ZN7QObject7connectEPKS_PKcS1_S3_N2Qt14ConnectionTypeE",
        (_P, _P, ctypes.c_char_p, _P, ctypes.c_char_p, ctypes.c_int),
        None,
    ),
}
RECURSIVELY = 1  # Qt::FindChildrenRecursively
# Qt 5's object layout, as its headers fix it: a QObject is its vtable and d_ptr (a
# QObjectData: vtable, q_ptr, parent, ...)
QOBJECT_BYTES, QOBJECT_D_PTR, QOBJECTDATA_PARENT = 16, 8, 16
BAR_DEPTH = 3  # the abort button, the progress widget's inner frame, the progress widget
QTIMER_BYTES = 256  # room for a QTimer (40 bytes in Qt 5), which this module constructs
_KEPT: list = []  # the abort timer's memory: it lives as long as the GUI


def _function(name: str):
    """The Qt or ParaView function ``name``, called with the GIL held (``PyDLL``): the Python
    observers Qt's events run expect it, as in any call from ParaView."""
    symbol, arguments, result = _QT[name]
    function = getattr(ctypes.PyDLL(None), symbol)
    function.argtypes, function.restype = arguments, result
    return function


def in_gui() -> bool:
    """Whether this is the main thread of a process running Qt's application with
    ParaView's progress manager (the GUI; not pvpython, pvbatch or a plain Python)."""
    if threading.current_thread() is not threading.main_thread():
        return False
    process = ctypes.CDLL(None)
    if not all(hasattr(process, symbol) for symbol, _, _ in _QT.values()):
        return False
    app = ctypes.c_void_p.in_dll(process, _QT["app"][0])
    return bool(app.value) and bool(_function("core")())


def _data(name: str) -> int:
    """The address of the data symbol ``name`` of ``_QT``."""
    return ctypes.addressof(ctypes.c_char.in_dll(ctypes.PyDLL(None), _QT[name][0]))


def _parent(obj: int) -> int:
    """A QObject's parent: ``d_ptr->parent`` (Qt 5's QObjectData: vptr, q_ptr, parent)."""
    data = ctypes.c_void_p.from_address(obj + QOBJECT_D_PTR).value
    return ctypes.c_void_p.from_address(data + QOBJECTDATA_PARENT).value or 0


def _progress_manager() -> int:
    """The GUI's pqProgressManager: the child of that class of pqApplicationCore."""
    meta = _data("meta")
    anyname = ctypes.create_string_buffer(ctypes.sizeof(_P))  # an empty QString
    _function("qstring")(anyname, b"", 0)
    return _function("find")(_function("core")(), anyname, meta, RECURSIVELY)


class AbortButton:
    """The progress bar's abort button of ParaView 5.11, enabled while the work runs, and
    the GUI's events processed so that it can be pressed. A QTimer of this module, parked,
    is started by the progress manager's ``abort()`` signal, so that :meth:`pressed` can
    tell (5.11 connects that signal to nothing)."""

    def __init__(self) -> None:
        self._manager = _progress_manager()
        if not _KEPT:
            timer = ctypes.create_string_buffer(QTIMER_BYTES)
            _function("timer")(timer, None)
            _function("interval")(timer, PARKED_MS)
            connection = ctypes.create_string_buffer(ctypes.sizeof(_P))
            _function("connect")(
                connection, self._manager, b"2abort()", ctypes.addressof(timer), b"1start()", 0
            )
            _KEPT.append(timer)
        self._timer = _KEPT[0]
        _function("stop")(self._timer)
        _function("enable_abort")(self._manager, True)

    def _over_bar(self) -> bool:
        """Whether the mouse is over the progress bar (its abort button is a child)."""
        point = ctypes.c_uint64(_function("cursor")())
        widget = _function("widget_at")(ctypes.addressof(point)) or 0
        for _ in range(BAR_DEPTH):
            if not widget:
                return False
            if _function("cast")(_data("bar_meta"), widget):
                return True
            widget = _parent(widget)
        return False

    def process_events(self) -> None:
        """Let Qt handle the events waiting, for ``EVENT_MS`` at most. ParaView's progress
        manager drops every key and mouse press meanwhile (they are never replayed), even
        the abort button's, which reaches its window first; so its presses are let through
        while the mouse is over the progress bar."""
        unblock = self._over_bar()
        if unblock:
            _function("unblock")(self._manager, True)
        try:
            _function("process")(0, EVENT_MS)  # QEventLoop::AllEvents
        finally:
            if unblock:
                _function("unblock")(self._manager, False)

    def pressed(self) -> bool:
        """Whether the abort button was pressed since this object was made."""
        # QTimer's timer id (an int after the QObject's 16 bytes) is >= 0 while it runs
        return ctypes.c_int.from_buffer(self._timer, QOBJECT_BYTES).value >= 0

    def close(self) -> None:
        _function("stop")(self._timer)
        _function("enable_abort")(self._manager, False)


def run_polled(
    work: Callable[[Callable[[dict], Any]], Any],
    progress: Callable[[dict], Any],
    abort: Callable[[], None],
) -> Any:
    """``work(report)`` in a worker thread while this thread serves it: each ``report(info)``
    of the worker waits until this thread has called ``progress(info)`` (which may update
    VTK's progress and read the abort request: only this thread may) and returns its answer,
    as a direct call would. In the GUI, Qt's events are processed at least every
    ``POLL_SECONDS`` meanwhile, and a press of the abort button calls ``abort()`` (as
    ParaView's own abort sets the algorithm's AbortExecute). Returns what ``work`` returns,
    or raises what it raised; an exception here (Ctrl-C) cancels the work at its next
    report and waits for it to end."""
    requests: queue.Queue = queue.Queue()
    done = object()  # the worker's last request: it has ended
    cancelled = threading.Event()

    def report(info: dict) -> Any:
        if cancelled.is_set():
            return True
        reply: queue.Queue = queue.Queue(maxsize=1)
        requests.put((info, reply))
        return reply.get()

    def target() -> None:
        try:
            outcome = (work(report), None)
        except BaseException as exc:  # handed to the caller's thread
            outcome = (None, exc)
        requests.put((done, outcome))

    button = AbortButton() if in_gui() else None
    threading.Thread(target=target, name="pinn-mesh work", daemon=True).start()
    pumped = time.monotonic()
    try:
        while True:
            try:
                info, reply = requests.get(timeout=POLL_SECONDS)
            except queue.Empty:
                info = reply = None
            if info is done:
                result, error = reply
                break
            if button is not None and time.monotonic() - pumped >= POLL_SECONDS:
                button.process_events()
                pumped = time.monotonic()
                if button.pressed():
                    abort()
            if info is not None:
                reply.put(progress(info))
    except BaseException:
        cancelled.set()
        while True:  # answer the worker until it has ended
            info, reply = requests.get()
            if info is done:
                break
            reply.put(True)
        raise
    finally:
        if button is not None:
            button.close()
    if error is not None:
        raise error
    return result
