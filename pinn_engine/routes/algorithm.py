"""pinn-mesh as a VTK algorithm: boundary (+ auxiliary lines) in, structured grid out.

``PinnMeshAlgorithm`` is a plain ``VTKPythonAlgorithmBase`` subclass: it works in any VTK
pipeline (pip ``vtk``, pyvista, ParaView's own VTK 9.2), and the ParaView plugin in
``plugin/`` only decorates it. It imports ``vtkmodules`` and the engine; torch is imported
only when a network is trained.

>>> alg = PinnMeshAlgorithm()
>>> alg.SetInputConnection(0, boundary_reader.GetOutputPort())
>>> alg.AddInputConnection(1, aux_reader.GetOutputPort())    # optional, repeatable
>>> alg.SetGridSize(41, 21)
>>> alg.Update()                                              # trains once
>>> alg.SetGridSize(81, 41); alg.Update()                     # re-evaluates, no training

Ports: input 0 the boundary (``vtkPolyData``, one closed polyline or polygon); input 1 the
auxiliary lines (``vtkPolyData``, optional, any number of connections, each may hold several
polylines); output 0 a ``vtkStructuredGrid`` as in SPEC 3, plus field data ``Trained``
(1 when this update trained a network, 0 when it re-used one), ``TrainingCount``, and for a
network ``NetworkResult`` (``network``: its grid was kept; ``start``: the guard kept the
start) and ``LargestNodeMove`` (from start to result, of the diagonal).

Errors (bad boundary, bad auxiliary line, failed or cancelled training, bad settings) are
reported as one line ``PINN Structured Mesh: <message>`` through ``vtkOutputWindow`` (the
Output Messages window in ParaView) and as an ``ErrorEvent`` on the algorithm; the output
is then an empty grid and ``GetLastError()`` returns the message.

A grid with folded cells (or lines leaving an orthogonal side more than 2 degrees off 90)
is still produced, with one warning line ``PINN Structured Mesh: warning: N of M cells are
folded ...`` (a hint in the words of the ParaView panel) through
``vtkOutputWindow`` (ParaView's Output Messages) and as a ``WarningEvent``;
``GetLastWarning()`` returns it.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np
from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase
from vtkmodules.vtkCommonCore import vtkIntArray
from vtkmodules.vtkCommonDataModel import vtkPolyData, vtkStructuredGrid
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline

from pinn_engine.errors import STOP, InputError, SettingsError, grid_warnings, unknown_name
from pinn_engine.routes.filters import (
    FamilyInput,
    FieldInput,
    LastOutcome,
    LineInputs,
    Stoppable,
    choice,
    patch_setting,
)
from pinn_engine.routes.reporting import message_of
from pinn_engine.routes.summary_lines import grid_lines
from pinn_engine.settings import (
    KIND_SETTINGS,
    METHODS,
    NEURAL,
    OBJECTIVES,
    PRESETS,
    SIDE_NAMES,
    TOPOLOGIES,
    Settings,
    grid_size_problem,
    make_settings,
    parse_sides,
    parse_spacing,
    setting_names,
)

if TYPE_CHECKING:
    from pinn_engine.job import MeshCache

LABEL = "PINN Structured Mesh"
AUTO_TOPOLOGY = "auto"  # the topology picked from the input (job.topology_of), the default
PREPARE_SHARE = 0.3  # of the progress bar for a body's stages before training (elliptic grid)


def _warning(report: dict) -> str | None:
    """The update's warning: a stopped training, folded cells and wall angles off an
    orthogonal side, in the panel's words, joined; None when none applies."""
    return "; ".join(text for text, _ in grid_warnings(report, "paraview")) or None


class PinnMeshAlgorithm(
    LastOutcome, Stoppable, FamilyInput, FieldInput, LineInputs, VTKPythonAlgorithmBase
):
    """Structured quadrilateral grid of a four-sided boundary (pinn, mgnet, tfi, elliptic).

    Settings (each setter calls ``Modified()`` when the value changes):

    * ``SetMethod("pinn"|"mgnet"|"tfi"|"elliptic")`` (or its index 0..3), default ``pinn``
    * ``SetGridSize(ni, nj)``: nodes along xi and eta, default 41 x 21
    * ``SetPreset("default"|"paper")`` (or 0/1): the base settings; ``paper`` is the paper's
      section 4 (penalty boundary term, decision-tree boundary fit, 1000 elliptic sweeps)
    * ``SetAdamEpochs``, ``SetLBFGSIterations``, ``SetHiddenLayers``, ``SetNeurons``,
      ``SetLambda2``, ``SetSeed``: override the preset (``None`` restores the preset value)
    * ``SetSpacing(bottom, right, top, left)``: first-edge lengths (0: none), and
      ``SetOrthogonal(b, r, t, l)``: 0/1 per side (SPEC 7; also names or a dict)
    * ``SetCorners(i0, i1, i2, i3)``: the four corner point indices of the boundary;
      ``SetCorners(None)`` or any negative index: automatic detection
    * ``SetObjective("best"|"winslow"|"quality")`` (or 0/1/2): the pinn's objective (SPEC 7)
    * ``SetPresetSetting(preset, name, value)``: a value used only under that preset
    * ``SetSetting(name, value)``: any other field of ``pinn_engine.settings.Settings``
      (e.g. ``"device"``, ``"boundary_mode"``, ``"elliptic_iterations"``)
    * ``SetPatchNames(names)``: boundary patch names (four names bottom right top left, or
      ``SIDE=NAME`` items, as a string, sequence or mapping); field data ``PatchNames``
    * input port 2 (optional), a Field: any dataset (a solver's result); the grid is then
      adapted to its array ``SetAdaptArray(name)`` (default: its first point array) with
      ``SetAdaptStrength(beta)`` (SPEC 14); point array ``Monitor``
    * ``SetModel(path)``: a family model (SPEC 16: ``pinn-mesh fit``'s file, or a fitted
      model) that meshes the boundary as a member of its family (field data
      ``NetworkResult`` and ``FamilyModel`` say what was kept); "": none
    """

    FIELD_PORT = 2

    LABEL = LABEL

    def __init__(
        self,
        route: str = "paraview",
        cache: MeshCache | None = None,
        progress: Callable[[dict], bool | None] | None = None,
    ) -> None:
        """``route``: whose words errors are in ("paraview"; "pyvista" keeps them off VTK's
        output window, for the caller to raise ``GetLastException()``); ``cache``: fitted
        networks to share (default: this algorithm's own); ``progress``: the caller's
        training callback, as the pyvista route's (returning True cancels)."""
        super().__init__(nInputPorts=3, nOutputPorts=1, outputType="vtkStructuredGrid")
        self.SetProgressText(LABEL)  # also what the executive's own progress events show
        self._route, self._user_progress = route, progress
        self._exception: Exception | None = None
        self._method = "pinn"
        self._preset = "default"
        self._size = (41, 21)
        self._overrides: dict[str, object] = {}
        self._preset_values: dict[tuple[str, str], object] = {}  # (preset, setting): value
        self._corners: tuple[int, int, int, int] | None = None
        self._patches = ""  # as given; checked at the update (default names when empty)
        self._wall_spacing = 0.0  # first-layer height off a body's wall; 0: the default
        self._auto_topology = False  # topology from the input (AUTO_TOPOLOGY)
        if cache is None:
            from pinn_engine.job import MeshCache  # the job's modules: at the first filter

            cache = MeshCache()
        self._cache = cache
        self._last_error = ""
        self._last_warning = ""
        self._trained = False
        self._failed: tuple | None = None  # stamp of the inputs/settings of a failed update
        self._stop_signal: int | None = None  # a stop signal received during training

    # ---- settings ----------------------------------------------------------------------
    def _set_override(self, name: str, value) -> None:
        current = self._overrides.get(name)
        if value is None:
            if name in self._overrides:
                del self._overrides[name]
                self.Modified()
        elif current != value:
            self._overrides[name] = value
            self.Modified()

    def SetMethod(self, method) -> None:
        self._set("_method", choice(method, METHODS, "method"))

    def GetMethod(self) -> str:
        return self._method

    def SetPreset(self, preset) -> None:
        self._set("_preset", choice(preset, PRESETS, "preset"))

    def GetPreset(self) -> str:
        return self._preset

    def SetGridSize(self, ni, nj=None) -> None:
        """Nodes along xi and eta (checked at the next update: at least 2 x 2)."""
        if nj is None:  # a (ni, nj) pair
            ni, nj = ni
        self._set("_size", (int(ni), int(nj)))

    def GetGridSize(self) -> tuple[int, int]:
        return self._size

    def SetAdamEpochs(self, n) -> None:
        self._set_override("adam_epochs", None if n is None else int(n))

    def SetLBFGSIterations(self, n) -> None:
        self._set_override("lbfgs_iterations", None if n is None else int(n))

    def SetHiddenLayers(self, n) -> None:
        self._set_override("hidden_layers", None if n is None else int(n))

    def SetNeurons(self, n) -> None:
        self._set_override("neurons", None if n is None else int(n))

    def SetLambda2(self, value) -> None:
        self._set_override("lambda2", None if value is None else float(value))

    def SetSeed(self, n) -> None:
        self._set_override("seed", None if n is None else int(n))

    def SetSpacing(self, *values) -> None:
        """First-edge length per side (SPEC 7): four numbers for bottom, right, top, left
        (0: that side keeps today's distribution), a dict ``{"bottom": 1e-3}`` or a string
        ``"bottom=1e-3,top=0.01"``; ``None`` or all zeros: no spacing."""
        value = values[0] if len(values) == 1 else values
        if (
            isinstance(value, (list, tuple))
            and len(value) == 4
            and all(isinstance(v, (int, float, np.number)) for v in value)
        ):
            value = {side: float(h) for side, h in zip(SIDE_NAMES, value) if h}
        spacing = parse_spacing(value)
        self._set_override("spacing", spacing or None)

    def GetSpacing(self) -> tuple:
        return self._overrides.get("spacing", ())

    def SetOrthogonal(self, *values) -> None:
        """Sides that grid lines leave at 90 degrees (SPEC 7): four 0/1 flags for bottom,
        right, top, left, a list of names or ``"bottom,left"``; ``None``: none."""
        value = values[0] if len(values) == 1 else values
        if (
            isinstance(value, (list, tuple))
            and len(value) == 4
            and all(isinstance(v, (int, bool, np.integer)) for v in value)
        ):
            value = [side for side, on in zip(SIDE_NAMES, value) if on]
        self._set_override("orthogonal", parse_sides(value) or None)

    def GetOrthogonal(self) -> tuple:
        return self._overrides.get("orthogonal", ())

    def SetObjective(self, objective) -> None:
        """The pinn's objective: best, winslow or quality (or its index); None: the
        preset's."""
        self._set_override(
            "objective", None if objective is None else choice(objective, OBJECTIVES, "objective")
        )

    def SetPanelSetting(self, name: str, value) -> None:
        """A value from the ParaView panel: one equal to the default preset's is no override,
        so that a panel left at its defaults follows the chosen preset (with Preset paper,
        the paper's 5000 Adam epochs rather than the default's 0)."""
        self.SetSetting(
            name, None if value == getattr(KIND_SETTINGS["four_sided"](), name) else value
        )

    def SetPresetSetting(self, preset, name: str, value) -> None:
        """A value used only while ``preset`` is chosen (the panel's per-preset fields, such as
        Adam Epochs and Paper Adam Epochs, so that the panel shows what runs); one equal to
        the preset's own value, or None, is no override."""
        preset = choice(preset, PRESETS, "preset")
        if name not in setting_names():
            raise unknown_name(name, setting_names(), "setting")
        if value is not None and value == getattr(make_settings("pinn", preset), name):
            value = None
        key = (preset, name)
        if value is None:
            if key in self._preset_values:
                del self._preset_values[key]
                self.Modified()
        elif self._preset_values.get(key) != value:
            self._preset_values[key] = value
            self.Modified()

    def SetSetting(self, name: str, value) -> None:
        """Override any ``Settings`` field (``None`` restores the preset's value)."""
        if name in ("method", "preset"):
            getattr(self, f"Set{name.capitalize()}")(value)
            return
        if name not in setting_names():
            raise unknown_name(name, setting_names(), "setting")
        self._set_override(name, value)

    def SetCorners(self, *indices) -> None:
        if len(indices) == 1:
            indices = indices[0]
        if indices is None or len(indices) == 0:
            corners = None
        else:
            if len(indices) != 4:
                raise SettingsError("corners: give four point indices (or None for automatic)")
            corners = tuple(int(i) for i in indices)
            if min(corners) < 0:
                corners = None
        self._set("_corners", corners)

    def GetCorners(self) -> tuple[int, int, int, int] | None:
        return self._corners

    def SetPatchNames(self, names) -> None:
        self._set("_patches", patch_setting(names))

    def SetTopology(self, topology) -> None:
        """ "none" (a four-sided domain, the default), "o" (O-grid), "c" (C-grid) or
        "auto" (a four-sided domain, or an O-grid where the input is none but a body: the
        Airfoil source's curve or two closed polylines; the ParaView panel's default), or
        0, 1, 2, 3."""
        kind = choice(topology, (*TOPOLOGIES, AUTO_TOPOLOGY), "topology")
        self._set("_auto_topology", kind == AUTO_TOPOLOGY)
        self._set_override("topology", None if kind in ("none", AUTO_TOPOLOGY) else kind)

    def GetTopology(self) -> str:
        fallback = AUTO_TOPOLOGY if self._auto_topology else "none"
        return self._overrides.get("topology", fallback)

    def SetFarFieldRadius(self, radius) -> None:
        """Far-field circle radius in chords about mid-chord (one body curve)."""
        self._set_override("farfield", float(radius))

    def SetWallSpacing(self, h) -> None:
        """First-layer height off the body wall (0: the default, half the mean spacing
        along the wall); with Topology O or C it is the spacing of the wall, side bottom."""
        self._set("_wall_spacing", float(h))

    def GetPatchNames(self) -> tuple[str, ...]:
        """The four patch names (bottom, right, top, left) the next update uses."""
        from pinn_engine.io.export.patches import body_patch_names as body_patches
        from pinn_engine.io.export.patches import patch_specs

        topology = self.GetTopology()
        default = body_patches(topology) if topology in ("o", "c") else SIDE_NAMES
        return patch_specs(self._panel_patches(), default)[0]

    def GetSettings(self, topology: str | None = None) -> Settings:
        """The ``Settings`` the next update uses (raises ``ValueError`` if invalid);
        ``topology``: the one picked from the input under topology auto."""
        overrides = {
            name: value
            for (preset, name), value in self._preset_values.items()
            if preset == self._preset
        }
        overrides.update(self._overrides)
        if topology in ("o", "c") and "topology" not in overrides:
            overrides["topology"] = topology
        if self._method != "pinn":  # the panel hides Objective for the other methods
            overrides.pop("objective", None)
        if overrides.get("topology", "none") == "none":
            overrides.pop("farfield", None)  # the panel always sets it; a body's setting
        elif self._wall_spacing:
            overrides["spacing"] = (("bottom", self._wall_spacing),)  # the body's wall
        lattice = tuple(max(n, 2) for n in self._size)
        return make_settings(
            self._method, self._preset, **{"lattice": lattice, "size": self._size, **overrides}
        )

    # ---- results -----------------------------------------------------------------------
    def GetOutput(self) -> vtkStructuredGrid:
        """The output grid (after ``Update()``); empty when the last update failed."""
        return self.GetOutputDataObject(0)

    def GetTrainingCount(self) -> int:
        """How many networks this algorithm has trained (grid-size changes do not train)."""
        return self._cache.trainings

    def GetTrained(self) -> bool:
        """Whether the last update trained a network (False: re-used or classical method)."""
        return self._trained

    # ---- pipeline ----------------------------------------------------------------------
    def RequestInformation(self, request, inInfo, outInfo):
        ni, nj = (max(n, 1) for n in self._size)
        info = outInfo.GetInformationObject(0)
        info.Set(vtkStreamingDemandDrivenPipeline.WHOLE_EXTENT(), 0, ni - 1, 0, nj - 1, 0, 0)
        return 1

    def RequestData(self, request, inInfo, outInfo):
        output = vtkStructuredGrid.GetData(outInfo, 0)
        if self.GetAbortExecute():
            self.SetAbortExecute(0)  # an abort request is for the run it came in, not this one
        if self._failed is not None and self._failed == self._stamp(inInfo):
            # Nothing changed since the failure; the executive asks again only because the
            # empty output does not cover the whole extent. Do not repeat the error (or a
            # failed training) on every render.
            output.Initialize()
            return 1
        self._failed = None
        self._last_error, self._last_warning, self._trained = "", "", False
        self._last_summary = ""
        self._exception = None
        try:
            grid, warning = self._execute(inInfo)
        except Exception as exc:
            self._exception = exc
            message = self._message(exc)
        else:
            output.ShallowCopy(grid)
            self._keep_grid()
            if warning:
                self._report(warning, warning=True)
            self._progress(1.0, "done")
            self.SetProgressText(LABEL)
            return 1
        output.Initialize()
        if self.GetAbortExecute():
            self.SetAbortExecute(0)
        self._failed = self._stamp(inInfo)
        self._report(message)
        return 1

    def _message(self, exc: Exception) -> str:
        """The one-line message of a failed update, in the route's words."""
        return message_of(exc, self._route)

    def _stamp(self, inInfo) -> tuple:
        """What a re-execution depends on: the settings and the inputs' modification times.

        (Not this algorithm's MTime: VTK modifies it for abort bookkeeping between runs.)
        """
        times: list = [
            self._method,
            self._preset,
            self._size,
            self._corners,
            tuple(sorted(self._overrides.items(), key=repr)),
            tuple(sorted(self._preset_values.items(), key=repr)),
            repr(self._patches),
            self._wall_spacing,
            self._auto_topology,
            self._model if isinstance(self._model, str) else id(self._model),
            self._adapt_array,
            self._adapt_strength,
        ]
        for port in inInfo:
            for k in range(port.GetNumberOfInformationObjects()):
                data = port.GetInformationObject(k).Get(vtkPolyData.DATA_OBJECT())
                times.append(data.GetMTime() if data is not None else -1)
        return tuple(times)

    def _execute(self, inInfo) -> tuple[vtkStructuredGrid, str | None]:
        """The grid and its warning (folded cells, wall angles; None when neither)."""
        from pinn_engine import job

        ni, nj = self._size
        problem = grid_size_problem(ni, nj)
        if problem:
            raise SettingsError(f"Grid Size {ni} {nj}: {problem}")
        inputs = [
            vtkPolyData.GetData(inInfo[0], k)
            for k in range(inInfo[0].GetNumberOfInformationObjects())
        ]
        aux = [
            vtkPolyData.GetData(port, k)
            for port in inInfo[1 : self.FIELD_PORT]
            for k in range(port.GetNumberOfInformationObjects())
        ]
        field = self._field(inInfo)
        settings, picked = self._adapting(self.GetSettings()), []
        try:
            geometry = job.geometry_from_polydata(
                settings, inputs, aux, self._corners, patches=self._panel_patches()
            )
        except InputError:  # no four-sided domain: under Automatic, a body is one too
            if self.GetTopology() != AUTO_TOPOLOGY or job.topology_of(inputs) != "o":
                raise
            settings = self._adapting(self.GetSettings("o"))
            geometry = job.geometry_from_polydata(
                settings, inputs, aux, patches=self._panel_patches()
            )
            picked = ["Topology Automatic: the input is a body, meshed as an O-grid"]
        neural = settings.method in NEURAL
        # "training" only once a step has run: a process's first training first imports torch
        # and builds the start grid (seconds), and the abort button is answered at each step
        self._progress(0.0, "preparing to train" if neural else "meshing")
        began = time.perf_counter()
        outcome = self._run_job(
            settings,
            geometry,
            self._training_progress(settings),
            self._cache,
            family=self._model,
            field=field,
        )
        self._trained = outcome.trained
        seconds = time.perf_counter() - began
        self._tell([*picked, *grid_lines(outcome.report, settings, *self._size, seconds)])
        self._progress(0.95, "meshing")
        fd = outcome.data.GetFieldData()
        for name, value in (
            ("Trained", int(self._trained)),
            ("TrainingCount", self._cache.trainings),
        ):
            arr = vtkIntArray()
            arr.SetName(name)
            arr.InsertNextValue(value)
            fd.AddArray(arr)
        return outcome.data, _warning(outcome.report)

    def _panel_patches(self):
        """The patch names as given, None for the panel's default text (so that a body grid
        gets its own default names)."""
        text = self._patches
        if isinstance(text, str) and text.split() in ([], list(SIDE_NAMES)):
            return None
        return text

    def _training_progress(self, settings: Settings) -> Callable[[dict], bool | str]:
        """The engine's progress callback: the bar (a body's stages before training up to
        ``PREPARE_SHARE``, training up to 0.9) and the answer: ``STOP`` after the stop signal
        (or the caller's ``STOP``), True to cancel (the caller's True, an abort request)."""
        adam, lbfgs = settings.adam_epochs, settings.lbfgs_iterations
        total = max(adam + lbfgs, 1)

        def progress(info: dict) -> bool | str:
            if info["phase"] == "prepare":
                fraction = PREPARE_SHARE * info["step"] / max(info["total"], 1)
                self._progress(fraction, info["stage"])
            else:
                done = info["step"] if info["phase"] == "adam" else adam + min(info["step"], lbfgs)
                phase = "Adam" if info["phase"] == "adam" else "L-BFGS"
                fraction = PREPARE_SHARE + (0.9 - PREPARE_SHARE) * min(done / total, 1.0)
                self._progress(fraction, f"training ({phase})")
            answer = self._user_progress(info) if self._user_progress is not None else None
            if isinstance(answer, str) and answer == STOP:
                return STOP
            return bool(answer) or self._stop_answer()

        return progress
