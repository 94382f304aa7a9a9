"""pinn-mesh's six-faced 3D route as a VTK algorithm (SPEC 11): a surface with six tagged
faces in, its hexahedral grid out.

``PinnHexaAlgorithm`` is a plain ``VTKPythonAlgorithmBase`` subclass (pip ``vtk``, pyvista,
ParaView's own VTK 9.2, which has no pyvista: the engine's hexa route is plain VTK);
``plugin/`` decorates it as the filter PINN Structured Mesh (Hexahedral), and the pyvista accessor's
``size=(ni, nj, nk)`` on a surface with ``FaceId`` runs it.

>>> alg = PinnHexaAlgorithm()
>>> alg.SetInputConnection(0, surface_reader.GetOutputPort())   # closed, FaceId 0..5
>>> alg.SetGridSize(21, 21, 21)
>>> alg.SetSpacing("kmin=0.002")                                 # as --spacing kmin=0.002
>>> alg.Update()
>>> grid = alg.GetOutput()                                       # vtkStructuredGrid

Port: input 0 a ``vtkPolyData``, a closed triangulated (or polygonal) surface with a cell
array ``FaceId`` of six values. Output 0 the ``vtkStructuredGrid`` ``(ni, nj, nk)`` of the
command line's ``.vts``: cell arrays ``MaxIncludedAngle``, ``MinIncludedAngle``,
``ScaledJacobian``, ``Folded``; field data ``Method``, ``PatchNames``, ``PatchTypes``,
``Report`` (JSON) and the quality figures (``kinds.hexa.mesh.hexa_grid``).

A failed update leaves the output empty and reports one line ``PINN Structured Mesh (Hexahedral):
<message>`` (the ParaView route: in Output Messages and as an ``ErrorEvent``; other routes
read ``GetLastError()`` and raise ``GetLastException()``). Folded cells give one warning line
the same way (``GetLastWarning()``).
"""

from __future__ import annotations

from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase
from vtkmodules.vtkCommonDataModel import vtkPolyData, vtkStructuredGrid
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline

from pinn_engine.errors import ROUTE_WORDS, InputError, SettingsError
from pinn_engine.io.export.patches import named_patches
from pinn_engine.routes.filters import (
    LastOutcome,
    PatchWalls,
    Stoppable,
    choice,
    patch_setting,
    update_warning,
)
from pinn_engine.routes.reporting import message_of
from pinn_engine.routes.summary_lines import hexa_lines
from pinn_engine.settings import (
    FACE_ANGLE,
    HEXA_METHOD,
    HEXA_METHODS,
    HEXA_SIZE,
    NO_TIME_LIMIT,
    hexa_size_problem,
    make_settings,
)

LABEL = "PINN Structured Mesh (Hexahedral)"
TRAINING_SHARE = (0.2, 0.9)  # the progress bar's span of pinn's training (face grids before)
# what a curve given to the hexahedral filter is pointed to, in each route's words
CURVE_FIX = {
    "paraview": "a 2D curve is meshed by PINN Structured Mesh (four-sided, or a body with "
    "Topology O-grid or C-grid) or by PINN Structured Mesh (Multi-Block); this filter takes a "
    "closed surface",
    "pyvista": "a 2D curve is meshed with size=(ni, nj) or blocks=; size=(ni, nj, nk) takes "
    "a closed surface",
}


def refold_hint(route: str) -> str:
    """The fix a folded elliptic (or pinn) hexahedral grid is pointed to, in ``route``'s
    words: the folds come from the face grids, where the surface bends sharply."""
    return (
        f"another {ROUTE_WORDS[route]['size']} or a finer triangulation where the surface "
        "bends sharply (the cell array Folded marks the cells)"
    )


class PinnHexaAlgorithm(LastOutcome, Stoppable, PatchWalls, VTKPythonAlgorithmBase):
    """Hexahedral structured grid (SPEC 11) of a closed surface with six tagged faces.

    Settings (each setter calls ``Modified()`` when the value changes; values are checked at
    the next update):

    * ``SetMethod(name)`` (or its index in ``settings.HEXA_METHODS``), default
      ``settings.HEXA_METHOD``
    * ``SetGridSize(ni, nj, nk)``: nodes along i, j and k, default 21 21 21
    * ``SetPatchNames(names)``: the patch names of the six faces, each optionally
      ``NAME:TYPE`` (six names imin imax jmin jmax kmin kmax, or ``SIDE=NAME`` items, SIDE
      one of those or ``faceN``, the input face whose FaceId is N, as a string, sequence or
      mapping; the command line's ``--patch``); field data
      ``PatchNames`` and ``PatchTypes``
    * ``SetSpacing(items)``: ``PATCH=H`` items, the first grid edge leaving that face
      (``"kmin=0.002"``, a sequence of items or a mapping ``{"kmin": 0.002}``; ``--spacing``)
    * ``SetOrthogonal(names)``: faces that grid lines leave along the normal (``"kmin,kmax"``
      or a sequence of names; ``--orthogonal``; elliptic and pinn)
    * ``SetFaceAngle(degrees)``: a surface without ``FaceId`` (an STL) is split into faces
      where neighbouring triangles' normals differ by more than this, default 40 (SPEC 11)
    * ``SetTimeLimit(seconds)``: pinn's training ends after this many seconds with its best
      grid so far (0: no limit, the default); so does an abort request or SIGUSR1

    Patch names, spacings and orthogonal faces are checked at the next update, before
    meshing (one line naming the item, as the command line's).
    """

    LABEL = LABEL

    def __init__(self, route: str = "paraview") -> None:
        """``route``: whose words messages are in ("paraview"; "pyvista" keeps them off VTK's
        output window, for the caller to raise ``GetLastException()``)."""
        super().__init__(
            nInputPorts=1, inputType="vtkPolyData", nOutputPorts=1, outputType="vtkStructuredGrid"
        )
        self.SetProgressText(LABEL)
        self._route = route
        self._method = HEXA_METHOD
        self._size = HEXA_SIZE
        self._patches: str | dict = ""  # as given; checked at the update (imin ... kmax)
        self._faces: dict[str, int] = {}  # side -> the input's FaceId, as last found
        self._face_angle = FACE_ANGLE
        self._time_limit = NO_TIME_LIMIT
        self._last_error = self._last_warning = ""
        self._exception: Exception | None = None
        self._failed: tuple | None = None  # what the last failed update ran on

    # ---- settings ----------------------------------------------------------------------
    def SetMethod(self, method) -> None:
        self._set("_method", choice(method, HEXA_METHODS, "method"))

    def GetMethod(self) -> str:
        return self._method

    def SetGridSize(self, ni, nj, nk) -> None:
        self._set("_size", (int(ni), int(nj), int(nk)))

    def GetGridSize(self) -> tuple[int, int, int]:
        return self._size

    def SetPatchNames(self, names) -> None:
        self._set("_patches", patch_setting(names))

    def GetPatchNames(self) -> tuple[str, ...]:
        """The six patch names (imin ... kmax) the next update uses (``faceN`` items as the
        last update found the input's faces)."""
        return named_patches(self._patches, self._faces)[0]

    def SetFaceAngle(self, degrees) -> None:
        self._set("_face_angle", float(degrees))

    def GetFaceAngle(self) -> float:
        return self._face_angle

    def SetTimeLimit(self, seconds) -> None:
        self._set("_time_limit", float(seconds))

    def GetTimeLimit(self) -> float:
        return self._time_limit

    # ---- results -----------------------------------------------------------------------
    def GetOutput(self) -> vtkStructuredGrid:
        """The grid (after ``Update()``); empty when the last update failed."""
        return self.GetOutputDataObject(0)

    # ---- pipeline ----------------------------------------------------------------------
    def RequestInformation(self, request, inInfo, outInfo):
        extent = [v for n in self._size for v in (0, max(n, 1) - 1)]
        outInfo.GetInformationObject(0).Set(
            vtkStreamingDemandDrivenPipeline.WHOLE_EXTENT(), *extent
        )
        return 1

    def RequestData(self, request, inInfo, outInfo):
        output = vtkStructuredGrid.GetData(outInfo, 0)
        surface = vtkPolyData.GetData(inInfo[0], 0)
        settings = (
            self._method,
            self._size,
            self._patches,
            self._spacing,
            self._orthogonal,
            self._face_angle,
            self._time_limit,
        )
        stamp = (*settings, surface.GetMTime() if surface else -1)
        if stamp == self._failed:
            # Nothing changed since the failure; the executive asks again only because the
            # empty output does not cover the whole extent: say it once.
            output.Initialize()
            return 1
        self._failed = None
        self._last_error = self._last_warning = self._last_summary = ""
        self._exception = None
        try:
            grid, report = self._execute(surface)
        except Exception as exc:
            self._exception = exc
            self._failed = stamp
            output.Initialize()
            self._report(message_of(exc, self._route), warning=False)
        else:
            output.ShallowCopy(grid)
            self._keep_grid()
            warning = update_warning(report, self._route, refold_hint(self._route))
            if warning:
                self._report(warning, warning=True)
        self._progress(1.0, "done")
        self.SetProgressText(LABEL)
        return 1

    def _execute(self, surface: vtkPolyData) -> tuple[vtkStructuredGrid, dict]:
        """The grid of the connected surface under the settings, and the run's report; the
        summary line told (``_tell``)."""
        from pinn_engine import job

        problem = hexa_size_problem(self._size)
        if problem:
            size = " ".join(map(str, self._size))
            raise SettingsError(f"{ROUTE_WORDS[self._route]['size']} {size}: {problem}")
        settings = make_settings(
            self._method,
            kind="hexa",
            size=self._size,
            spacing=list(self._spacing),
            orthogonal=",".join(self._orthogonal),
            face_angle=self._face_angle,
            time_limit=self._time_limit,
        )
        if surface is None or surface.GetNumberOfPolys() + surface.GetNumberOfStrips() == 0:
            raise InputError(f"holds no surface triangles: {CURVE_FIX[self._route]}", "input")
        geometry = job.hexa_from_polydata(surface, "input", self._patches)
        outcome = self._run_job(settings, geometry, self._hexa_progress)
        self._faces = outcome.report["faces"]
        self._tell(hexa_lines(outcome.report))
        return outcome.data, outcome.report

    def _hexa_progress(self, info: dict) -> str | None:
        """The run's stages on the bar, and its training (:meth:`_training`)."""
        if info["phase"] == "prepare":
            self._progress(info["step"] / info["total"], info["stage"])
            return None
        return self._training(info)

    def _training(self, info: dict) -> str | None:
        """The trainer's progress on the bar (training from 0.2 to 0.9), answering
        ``errors.STOP`` to an abort request or the stop signal."""
        low, high = TRAINING_SHARE
        done = info["step"] / max(info["total"], 1)
        self._progress(low + (high - low) * min(done, 1.0), f"training ({info['phase']})")
        return self._stop_answer()


__all__ = ["LABEL", "PinnHexaAlgorithm", "refold_hint"]
