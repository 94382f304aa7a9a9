"""What the VTK filters (four-sided/body, multi-block, hexahedral) share: their input ports,
their setters and how they read a setting's forms (a ParaView enumeration's index, the
panel's text fields), their last update's outcome and summary, how a training is stopped
(abort request, SIGUSR1) and the folded-cells warning."""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Callable
from dataclasses import replace

import numpy as np
from vtkmodules.vtkCommonCore import vtkOutputWindow

from pinn_engine.errors import (
    ROUTE_WORDS,
    STOP,
    SettingsError,
    family_fallback_warning,
    stopped_training_warning,
)
from pinn_engine.routes.reporting import announce
from pinn_engine.routes.responsive import run_polled
from pinn_engine.settings import setting_problem


def choice(value, options: tuple[str, ...], what: str) -> str:
    """Accept a name or an index into ``options`` (ParaView enumerations send indices)."""
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        if 0 <= int(value) < len(options):
            return options[int(value)]
        raise SettingsError(f"{what} index {value} out of range 0..{len(options) - 1}")
    name = str(value).strip().lower()
    if name not in options:
        raise SettingsError(f"unknown {what} {value!r}; use one of {', '.join(options)}")
    return name


def setting_items(value, separators: str) -> tuple[str, ...]:
    """Items of a setting given as one string (split at whitespace and ``separators``: the
    panel's text field) or as a sequence of strings; None or "" is none."""
    if value is None:
        return ()
    if isinstance(value, str):
        for sep in separators:
            value = value.replace(sep, " ")
        return tuple(value.split())
    return tuple(str(v).strip() for v in value if str(v).strip())


def place_items(value) -> tuple[str, ...]:
    """``KEY=VALUE`` items of a setting whose keys may be names or points (``X,Y``): a
    string of items (separated by whitespace, ``;`` or, between items that each hold a
    ``=``, commas), a sequence of them, or a mapping ``{NAME: VALUE}`` or ``{(x, y):
    VALUE}``."""
    if hasattr(value, "items"):
        return tuple(
            f"{float(key[0])!r},{float(key[1])!r}={v}" if isinstance(key, tuple) else f"{key}={v}"
            for key, v in value.items()
        )
    out: list[str] = []
    for item in setting_items(value, ";"):
        parts = [part for part in item.split(",") if part]
        out += parts if all("=" in part for part in parts) else [item]
    return tuple(out)


def spacing_items(value) -> tuple[str, ...]:
    """``NAME=H`` or ``X,Y=H`` items of a first-edge spacing setting (:func:`place_items`,
    the lengths as floats)."""
    if hasattr(value, "items"):
        value = {key: repr(float(h)) for key, h in value.items()}
    return place_items(value)


def patch_setting(names) -> str | dict:
    """Patch names as a filter keeps them until its update checks them
    (``io.export.patches.patch_specs`` reads every form): the panel's string, a mapping,
    or a sequence joined by spaces; None is ""."""
    if not isinstance(names, str) and names is not None:
        names = dict(names) if hasattr(names, "items") else " ".join(map(str, names))
    return names or ""


class ModifiedOnChange:
    """Mixed into a ``VTKPythonAlgorithmBase``: settings change the algorithm's modified time
    only when they change, so an unchanged Apply does not run it again."""

    def _set(self, attr: str, value) -> None:
        if getattr(self, attr) != value:
            setattr(self, attr, value)
            self.Modified()


class PatchWalls(ModifiedOnChange):
    """Mixed into a filter whose patches are named (multi-block, hexahedral): first-edge
    spacing (``NAME=H`` items) and orthogonal patches, kept as items until its update checks
    them (the command line's ``--spacing`` and ``--orthogonal``)."""

    _spacing: tuple[str, ...] = ()  # NAME=H items
    _orthogonal: tuple[str, ...] = ()  # patch names

    def SetSpacing(self, items) -> None:
        self._set("_spacing", spacing_items(items))

    def GetSpacing(self) -> tuple[str, ...]:
        return self._spacing

    def SetOrthogonal(self, names) -> None:
        self._set("_orthogonal", setting_items(names, ",;"))

    def GetOrthogonal(self) -> tuple[str, ...]:
        return self._orthogonal


class FamilyInput(ModifiedOnChange):
    """Mixed into the 2D filters: a family model (SPEC 16) that meshes the input as a member
    of its family (``job.run``'s ``family``)."""

    _model = None  # the model's file, or a fitted model; None: the input's own run

    def SetModel(self, model) -> None:
        """A family model (SPEC 16: ``pinn-mesh fit``'s file, or a fitted model) that meshes
        the input as a member of its family; ``None`` or "": none."""
        self._set("_model", model or None)

    def GetModel(self):
        return self._model


class LastOutcome:
    """Mixed into a ``VTKPythonAlgorithmBase`` whose class names its ``LABEL``: progress and
    messages under that name, and what the last update left (``RequestData`` sets
    ``_last_error``, ``_last_warning`` and ``_exception``), for scripts and pyvista."""

    LABEL = ""  # the filter's name in ParaView's menu, progress bar and Output Messages

    def GetLastError(self) -> str:
        """The line of the last failed update ("" after a successful one)."""
        return self._last_error

    def GetLastWarning(self) -> str:
        """The warning line of the last update ("" when it had none)."""
        return self._last_warning

    def GetLastException(self) -> Exception | None:
        """The exception of the last failed update (None after a successful one)."""
        return self._exception

    def GetLastSummary(self) -> str:
        """The command line's summary line(s) of the last successful update ("" after a
        failed one)."""
        return getattr(self, "_last_summary", "")

    def _tell(self, lines: list[str]) -> None:
        """Keep the summary ``lines`` and in ParaView show them in Output Messages, one line
        each under the filter's name (plain text: the window does not pop up for it)."""
        self._last_summary = "\n".join(lines)
        if self._route == "paraview":
            for line in lines:
                vtkOutputWindow.GetInstance().DisplayText(f"{self.LABEL}: {line}\n")

    def _progress(self, fraction: float, phase: str) -> None:
        """Progress with the filter's name and the phase as its text: ParaView's progress bar
        shows it instead of the class name ("PythonAlgorithm")."""
        self.SetProgressText(f"{self.LABEL}: {phase}")
        self.UpdateProgress(fraction)

    def _report(self, message: str, warning: bool = False) -> None:
        """Keep ``message`` as the last error (or warning) line, and in ParaView announce it
        in Output Messages; the other routes raise or warn in their own words."""
        line = f"{self.LABEL}: {'warning: ' if warning else ''}{' '.join(str(message).split())}"
        if warning:
            self._last_warning = line
        else:
            self._last_error = line
        if self._route == "paraview":
            announce(self, line, warning)


class Stoppable:
    """Mixed into a ``VTKPythonAlgorithmBase`` that trains: a training ends early, with its
    best grid so far, on an abort request (``GetAbortExecute()``, checked each time progress
    is reported) or on SIGUSR1 (``pkill -USR1 -x paraview``: ParaView 5.11 delivers no click
    while a filter runs)."""

    _stop_signal: int | None = None  # a stop signal received during training
    _abort_seen = False  # an abort request came during this training

    _abort_pressed = False  # the GUI's abort button was pressed during this run

    def _abort_requested(self) -> bool:
        if self._abort_pressed:
            return True
        check = getattr(self, "CheckAbort", None)  # VTK 9.4+
        if check is not None and check():
            return True
        return bool(self.GetAbortExecute())

    @contextlib.contextmanager
    def _stop_on_signal(self):
        """While training, SIGUSR1 (``pkill -USR1 -x paraview``) stops the training with the
        best grid so far (and a warning) instead of ending the host process: ParaView 5.11
        handles no GUI event while a filter runs, so its abort button cannot. Only where
        SIGUSR1 has its default action or a Python handler, which is put back afterwards (the
        host is left as it was); main thread only."""
        self._stop_signal, self._abort_seen, self._abort_pressed = None, False, False
        usr1 = getattr(signal, "SIGUSR1", None)
        previous = signal.getsignal(usr1) if usr1 is not None else None
        if previous is None or threading.current_thread() is not threading.main_thread():
            yield  # a handler installed outside Python, or no main thread: leave it alone
            return

        def stop(signum, frame):  # noqa: ARG001
            self._stop_signal = signum

        signal.signal(usr1, stop)
        try:
            yield
        finally:
            signal.signal(usr1, previous)

    def _run_job(self, settings, geometry, progress: Callable[[dict], object], *more, **named):
        """``job.run(settings, geometry, progress, *more, **named)`` with the stop signal
        taken; in ParaView in a worker thread polled by this one
        (``responsive.run_polled``), so that the GUI stays alive and its abort button is
        honoured."""
        from pinn_engine import job

        with self._stop_on_signal():
            if self._route != "paraview":
                return job.run(settings, geometry, progress, *more, **named)
            return run_polled(
                lambda report: job.run(settings, geometry, report, *more, **named),
                progress,
                self._press_abort,
            )

    def _press_abort(self) -> None:
        """The abort button, as an abort request (not ``SetAbortExecute``, whose
        ``Modified()`` would have the pipeline run the filter again afterwards)."""
        self._abort_pressed = True

    def _keep_grid(self) -> None:
        """Clear an abort request taken during the run (and VTK 9.3+'s AbortOutput, which
        would empty the output): the grid is whole and is handed over."""
        self.SetAbortExecute(0)
        if hasattr(self, "SetAbortOutput"):
            self.SetAbortOutput(0)

    def _stop_answer(self) -> str | None:
        """The trainer's answer (``errors.STOP``: end with the best grid) after an abort
        request or the stop signal, else None. The request is taken and cleared, so that the
        executive keeps the grid the run then hands over."""
        if self._abort_requested():
            self.SetAbortExecute(0)
            self._abort_seen = True
        return STOP if self._stop_signal or self._abort_seen else None


class LineInputs(ModifiedOnChange):
    """Mixed into a ``VTKPythonAlgorithmBase``: port 0 takes every selected polydata (the
    boundary and the lines selected with it: ParaView's GUI connects them all there), the
    other ports more lines (optional)."""

    def FillInputPortInformation(self, port, info):
        info.Set(self.INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData")
        info.Set(self.INPUT_IS_REPEATABLE(), 1)
        if port >= 1:
            info.Set(self.INPUT_IS_OPTIONAL(), 1)
        return 1


class FieldInput(ModifiedOnChange):
    """Mixed into the 2D filters before ``LineInputs``: the optional Field port
    ``FIELD_PORT`` (any dataset: a solver's result, the OpenFOAM reader's output) whose
    array the grid is adapted to (SPEC 14), that array's name and the monitor's strength."""

    FIELD_PORT = -1  # set by each filter: its last input port
    _adapt_array = ""  # the array's name; "": the Field input's first point (else cell) array
    _adapt_strength: float | None = None  # None: the settings' default

    def FillInputPortInformation(self, port, info):
        if port != self.FIELD_PORT:
            return super().FillInputPortInformation(port, info)
        info.Set(self.INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject")
        info.Set(self.INPUT_IS_OPTIONAL(), 1)
        return 1

    def RequestUpdateExtent(self, request, inInfo, outInfo):
        """The whole Field input, one piece (the executive would ask a structured field
        for the grid's own extent)."""
        from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline as sddp

        port = inInfo[self.FIELD_PORT]
        for k in range(port.GetNumberOfInformationObjects()):
            info = port.GetInformationObject(k)
            if info.Has(sddp.WHOLE_EXTENT()):
                info.Set(sddp.UPDATE_EXTENT(), info.Get(sddp.WHOLE_EXTENT()), 6)
            info.Set(sddp.UPDATE_PIECE_NUMBER(), 0)
            info.Set(sddp.UPDATE_NUMBER_OF_PIECES(), 1)
        return 1

    def SetAdaptArray(self, *name) -> None:
        """The array to adapt to by name (ParaView's array selection passes five values,
        the name last)."""
        self._set("_adapt_array", str(name[-1]) if name and name[-1] is not None else "")

    def GetAdaptArray(self) -> str:
        return self._adapt_array

    def SetAdaptStrength(self, beta) -> None:
        problem = None if beta is None else setting_problem("adapt_strength", beta)
        if problem:
            raise SettingsError(f"Adapt Strength {beta}: {problem}")
        self._set("_adapt_strength", None if beta is None else float(beta))

    def _adapting(self, settings):
        """``settings`` with the strength set here, if any."""
        if self._adapt_strength is None:
            return settings
        return replace(settings, adapt_strength=self._adapt_strength)

    def _field(self, inInfo):
        """The Field input's array as a ``job.Field``, or None without a Field input."""
        from vtkmodules.vtkCommonDataModel import vtkDataObject

        from pinn_engine.job import Field

        port = inInfo[self.FIELD_PORT]
        data = (
            port.GetInformationObject(0).Get(vtkDataObject.DATA_OBJECT())
            if (port.GetNumberOfInformationObjects())
            else None
        )
        if data is None:
            return None
        return Field(data, self._adapt_array or None, "field input")


def folded_warning(report: dict, route: str, otherwise: str) -> str | None:
    """The warning of a grid with folded cells in ``route``'s words, or None: ``report``
    holds ``method``, ``cells`` and ``quality.folded_cells``; a tfi grid is pointed to the
    elliptic method, any other to ``otherwise`` (the fix of the filter's kind of input)."""
    folded = int(report["quality"]["folded_cells"])
    if not folded:
        return None
    if report["method"] == "tfi":
        fix = ROUTE_WORDS[route]["method"].format("elliptic")
    else:
        fix = otherwise
    verb = "is" if folded == 1 else "are"
    return f"{folded} of {report['cells']} cells {verb} folded; try {fix}"


def update_warning(report: dict, route: str, otherwise: str) -> str | None:
    """The warning line of a multi-block or hexahedral update: a training stopped early
    (time limit, abort, SIGUSR1), folded cells (:func:`folded_warning`) and a family model's
    grid not kept, joined; None when none applies."""
    found = (
        stopped_training_warning(report, route),
        folded_warning(report, route, otherwise),
        family_fallback_warning(report, route),
    )
    return "; ".join(w for w in found if w) or None
