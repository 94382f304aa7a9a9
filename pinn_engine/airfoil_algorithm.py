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

from .errors import InputError


def body_polydata(surface: np.ndarray, sharp: bool) -> vtkPolyData:
    """The body curve as a polyline (closed when ``sharp``)."""
    pts = surface[:-1] if sharp else surface
    poly = vtkPolyData()
    points = vtkPoints()
    xyz = np.column_stack([pts, np.zeros(len(pts))])
    points.SetData(numpy_to_vtk(np.ascontiguousarray(xyz, dtype=float), deep=True))
    poly.SetPoints(points)
    line = vtkPolyLine()
    ids = list(range(len(pts))) + ([0] if sharp else [])
    line.GetPointIds().SetNumberOfIds(len(ids))
    for k, i in enumerate(ids):
        line.GetPointIds().SetId(k, i)
    cells = vtkCellArray()
    cells.InsertNextCell(line)
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
        from .airfoil import load_body

        if not self._filename:
            raise InputError("no file name set")
        return load_body(self._filename)


class AirfoilSource(_AirfoilBase):
    """A NACA 4-digit section of chord 1 (``SetNACA("2412")``; ``SetSharpTrailingEdge``:
    closed trailing edge, for the C-grid, or the classical blunt one, for the O-grid)."""

    LABEL = "Airfoil source"

    def __init__(self) -> None:
        super().__init__()
        self._code, self._sharp = "0012", True

    def SetNACA(self, code) -> None:
        if str(code) != self._code:
            self._code = str(code).strip()
            self.Modified()

    def SetSharpTrailingEdge(self, sharp) -> None:
        if bool(sharp) != self._sharp:
            self._sharp = bool(sharp)
            self.Modified()

    def _body(self):
        from .airfoil import load_body

        return load_body(naca=self._code, te="sharp" if self._sharp else "blunt")


def body_and_farfield_of(poly: vtkPolyData, radius: float, source: str = "boundary input"):
    """The body (and far field) of a filter's input: one polyline is the body (closed:
    sharp trailing edge; open: blunt), with a far-field circle of ``radius`` chords; two
    closed polylines are the body inside the far field."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    from .airfoil import body_from_points, circle, polyline_farfield
    from .fileio import polylines_of

    if poly is None or poly.GetNumberOfPoints() == 0:
        raise InputError("is empty; connect an airfoil (the Airfoil source or a .dat file)", source)
    xyz = vtk_to_numpy(poly.GetPoints().GetData()).astype(float)
    curves = []
    for ids, closed in polylines_of(poly, source):
        pts = xyz[ids, :2]
        if closed and not np.array_equal(pts[0], pts[-1]):
            pts = np.concatenate([pts, pts[:1]])
        curves.append(pts)
    if len(curves) == 1:
        body = body_from_points(curves[0], source)
        return body, circle(body, radius)
    if len(curves) == 2:
        size = [float(np.ptp(c, axis=0).max()) for c in curves]
        inner, outer = (curves[0], curves[1]) if size[0] < size[1] else (curves[1], curves[0])
        body = body_from_points(inner, source)
        return body, polyline_farfield(outer, body, source)
    raise InputError(
        f"holds {len(curves)} polylines; connect one airfoil curve (with Far "
        "Field Radius) or two closed polylines (body inside far field)",
        source,
    )


__all__ = ["AirfoilReader", "AirfoilSource", "body_and_farfield_of", "body_polydata"]
