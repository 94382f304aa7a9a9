"""VTK algorithms that make an airfoil curve (SPEC 9): a ``.dat`` reader and a NACA source.

Both output a ``vtkPolyData`` with the body as one polyline in Selig order (counter-
clockwise from the trailing edge): closed for a sharp trailing edge, open (its two ends the
corners of the base) for a blunt one, so that the mesher sees which it is. The PINN mesh
filter meshes it with Topology O-grid or C-grid. ``plugin/`` only decorates these classes.
"""

from __future__ import annotations

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase
from vtkmodules.vtkCommonCore import vtkCommand, vtkOutputWindow, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData, vtkPolyLine

from pinn_engine.errors import InputError


def body_polydata(surface: np.ndarray, sharp: bool, far: np.ndarray | None = None) -> vtkPolyData:
    """The body curve as a polyline (closed when ``sharp``), and the far-field curve ``far``
    (closed) as a second one when given."""
    pts = surface[:-1] if sharp else surface
    curves = [(pts, sharp)]
    if far is not None:
        ring = far[:-1] if np.array_equal(far[0], far[-1]) else far
        curves.append((ring, True))
    poly, points, cells, at = vtkPolyData(), vtkPoints(), vtkCellArray(), 0
    xyz = np.concatenate([np.column_stack([c, np.zeros(len(c))]) for c, _ in curves])
    points.SetData(numpy_to_vtk(np.ascontiguousarray(xyz, dtype=float), deep=True))
    poly.SetPoints(points)
    for curve, closed in curves:
        line = vtkPolyLine()
        ids = [at + k for k in range(len(curve))] + ([at] if closed else [])
        line.GetPointIds().SetNumberOfIds(len(ids))
        for k, i in enumerate(ids):
            line.GetPointIds().SetId(k, i)
        cells.InsertNextCell(line)
        at += len(curve)
    poly.SetLines(cells)
    return poly


class _AirfoilBase(VTKPythonAlgorithmBase):
    LABEL = "Airfoil"

    def __init__(self) -> None:
        super().__init__(nInputPorts=0, nOutputPorts=1, outputType="vtkPolyData")
        self._last_error = ""

    def GetLastError(self) -> str:
        return self._last_error

    def _body(self):  # pragma: no cover - overridden
        raise NotImplementedError

    def RequestData(self, request, inInfo, outInfo):
        output = vtkPolyData.GetData(outInfo, 0)
        self._last_error = ""
        try:
            body = self._body()
        except InputError as exc:
            line = f"{self.LABEL}: {exc.for_route('paraview')}"
            self._last_error = line
            vtkOutputWindow.GetInstance().DisplayErrorText(line + "\n")
            self.InvokeEvent(vtkCommand.ErrorEvent, line)
            output.Initialize()
            return 1
        output.ShallowCopy(body_polydata(body.surface, body.sharp))
        return 1


class AirfoilReader(_AirfoilBase):
    """Reads a Selig or Lednicer ``.dat`` file (``SetFileName``)."""

    LABEL = "Airfoil (.dat) reader"

    def __init__(self) -> None:
        super().__init__()
        self._filename = ""

    def SetFileName(self, name) -> None:
        if name != self._filename:
            self._filename = name or ""
            self.Modified()

    def GetFileName(self) -> str:
        return self._filename

    def _body(self):
        from pinn_engine.bodies.airfoil import load_body

        if not self._filename:
            raise InputError("no file name set")
        return load_body(self._filename)


NACA, SHARP = "0012", True  # the source's section at first: NACA 0012, a sharp trailing edge


class AirfoilSource(_AirfoilBase):
    """A NACA 4-digit section of chord 1 (``SetNACA("2412")``; ``SetSharpTrailingEdge``:
    closed trailing edge, for the C-grid, or the classical blunt one, for the O-grid)."""

    LABEL = "Airfoil source"

    def __init__(self) -> None:
        super().__init__()
        self._code, self._sharp = NACA, SHARP

    def SetNACA(self, code) -> None:
        if str(code) != self._code:
            self._code = str(code).strip()
            self.Modified()

    def SetSharpTrailingEdge(self, sharp) -> None:
        if bool(sharp) != self._sharp:
            self._sharp = bool(sharp)
            self.Modified()

    def _body(self):
        from pinn_engine.bodies.airfoil import load_body

        return load_body(naca=self._code, te="sharp" if self._sharp else "blunt")


__all__ = ["AirfoilReader", "AirfoilSource", "body_polydata"]
