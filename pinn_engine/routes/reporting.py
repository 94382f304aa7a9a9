"""How pinn-mesh's VTK algorithms report a failed or doubtful update: one line, in the words
of the route that runs them (ParaView's panel, pyvista's keywords)."""

from __future__ import annotations

import sys

from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase
from vtkmodules.vtkCommonCore import vtkCommand, vtkOutputWindow

from pinn_engine.errors import InputError, PinnMeshError, SettingsError, TrainingCancelled


def message_of(exc: Exception, route: str) -> str:
    """The one-line message of an update that raised ``exc``, in ``route``'s words."""
    if isinstance(exc, TrainingCancelled):
        return f"{exc}; no grid produced"
    if isinstance(exc, SettingsError):
        return f"invalid settings: {exc.for_route(route)}"
    if isinstance(exc, InputError):
        return str(exc.for_route(route))
    if isinstance(exc, PinnMeshError):
        return str(exc)
    if isinstance(exc, ValueError):  # invalid settings
        return f"invalid settings: {exc}"
    if isinstance(exc, ImportError):
        return (
            f"cannot import {exc.name or exc} in this Python ({sys.executable}); "
            "pinn-mesh needs numpy, scipy, shapely, pyamg and (to train) torch there"
        )
    return f"unexpected {type(exc).__name__}: {exc}"  # never reaches ParaView's executive


def announce(algorithm: VTKPythonAlgorithmBase, line: str, warning: bool = False) -> None:
    """``line`` in VTK's output window (ParaView's Output Messages) and as the algorithm's
    ``ErrorEvent`` (``WarningEvent`` when ``warning``), the line its call data."""
    window = vtkOutputWindow.GetInstance()
    if warning:
        window.DisplayWarningText(line + "\n")
        algorithm.InvokeEvent(vtkCommand.WarningEvent, line)
    else:
        window.DisplayErrorText(line + "\n")
        algorithm.InvokeEvent(vtkCommand.ErrorEvent, line)
