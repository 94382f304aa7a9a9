"""pinn-mesh's multi-block route as a VTK algorithm (SPEC 10): boundary and block edges in,
one structured grid a block out.

``PinnMultiBlockAlgorithm`` is a plain ``VTKPythonAlgorithmBase`` subclass (pip ``vtk``,
pyvista, ParaView's own VTK 9.2); ``plugin/`` decorates it as the filter PINN Multi-Block
Mesh, and the pyvista accessor's ``blocks=`` runs it.

>>> alg = PinnMultiBlockAlgorithm()
>>> alg.SetInputConnection(0, boundary_reader.GetOutputPort())  # outer boundary and holes
>>> alg.AddInputConnection(1, edges_reader.GetOutputPort())     # block edges, repeatable
>>> alg.AddInputConnection(2, aux_reader.GetOutputPort())       # auxiliary lines, optional
>>> alg.SetCellSize(0.1)
>>> alg.Update()
>>> blocks = alg.GetOutput()                                     # vtkMultiBlockDataSet
>>> edges = alg.GetBlockEdges()                                  # the edges meshed

``SetBlocking("automatic")`` proposes the block edges from the boundary and its holes alone
(SPEC 13; input 1 left empty, open polylines on input 0 refused).

Ports: input 0 ``vtkPolyData``, repeatable: its closed polylines (or polygons) are the outer
boundary and the holes, its open polylines block edges (ParaView's GUI connects every
selected source there); input 1 more block edges (optional, repeatable); input 2 auxiliary
lines inside blocks (optional, repeatable: open polylines, each from a side of one block to
the opposite side, fitted by pinn). Output 0 the
``vtkMultiBlockDataSet`` of the command line's ``.vtm``: ``vtkStructuredGrid`` blocks named
``block0``, ``block1``, ... with the cell arrays of SPEC 3 and the run's report; output 1
the block edges meshed (``vtkPolyData`` of open polylines: the proposal under Automatic,
which a user can copy, edit and connect as block edges).

A failed update leaves the output empty and reports one line ``PINN Structured Mesh (Multi-Block):
<message>`` (the ParaView route: in Output Messages and as an ``ErrorEvent``; other routes
read ``GetLastError()`` and raise ``GetLastException()``). Folded cells give one warning line
the same way (``GetLastWarning()``).
"""

from __future__ import annotations

import time

import numpy as np
from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase
from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkMultiBlockDataSet, vtkPolyData

from pinn_engine.errors import unknown_name
from pinn_engine.io.export.edges import edges_polydata
from pinn_engine.routes.filters import (
    FamilyInput,
    FieldInput,
    LastOutcome,
    LineInputs,
    PatchWalls,
    Stoppable,
    choice,
    place_items,
    update_warning,
)
from pinn_engine.routes.reporting import message_of
from pinn_engine.routes.summary_lines import blocks_lines
from pinn_engine.settings import (
    BLOCKS_METHOD,
    MULTIBLOCK_METHODS,
    NO_TIME_LIMIT,
    Settings,
    make_settings,
    option_constraints,
    setting_names,
)

LABEL = "PINN Structured Mesh (Multi-Block)"
INTERFACES = option_constraints()["interfaces"].values  # free, fixed (SPEC 10)
BLOCKING = ("manual", "automatic")  # block edges drawn, or proposed (SPEC 13)
# the fix a folded elliptic or pinn multi-block grid is pointed to
# the settings with a setter of their own (``SetSetting`` takes the multi-block kind's others)
OWN_SETTERS = frozenset({"method", "cell_size", "interfaces", "time_limit", "spacing"})
OWN_SETTERS |= {"orthogonal", "adapt_strength"}
MOVE_EDGES = "moving the block edges near them (the cell array Folded marks them)"


class PinnMultiBlockAlgorithm(
    LastOutcome, Stoppable, FamilyInput, FieldInput, LineInputs, PatchWalls, VTKPythonAlgorithmBase
):
    """Multi-block structured grid (SPEC 10) of a boundary, its holes and block edges.

    Settings (each setter calls ``Modified()`` when the value changes; values are checked at
    the next update against the kinds' tables (``settings.option_constraints``)):

    * ``SetBlocking("manual"|"automatic")`` (or 0/1), default manual: the block edges are
      the open polylines of inputs 0 and 1 (in ParaView proposed as by automatic where
      there are none), or proposed from the boundary alone (SPEC 13)
    * ``SetMethod("tfi"|"elliptic"|"pinn")`` (or its index in ``MULTIBLOCK_METHODS``),
      default pinn: each block's PINN on the elliptic grid (Winslow on all blocks at once)
    * ``SetCellSize(h)``: cell length in the boundary's units; 0 (default): the diagonal / 40
    * ``SetInterfaces("free"|"fixed")`` (or 0/1): interface nodes solved like interior nodes,
      or kept on the drawn edges
    * ``SetPatchNames(items)``: ``X,Y=NAME[:TYPE]`` items naming the boundary piece nearest
      (X, Y), ``hole1=NAME[:TYPE]`` or ``boundary=NAME[:TYPE]`` every piece of that ring (a
      string of items separated by spaces, a sequence of them, or a mapping ``{(x, y):
      "NAME[:TYPE]"}`` or ``{"hole1": "NAME[:TYPE]"}``); default names ``boundary``,
      ``hole1``, ...
    * ``SetCells(items)``: ``X,Y=N`` items, N cells along the chain through the block side
      nearest (X, Y) (a string, a sequence or a mapping ``{(x, y): N}``)
    * ``SetGradings(items)``: ``X,Y=R`` items, cells growing geometrically along the chain
      through the block side nearest (X, Y), the last R times the first (blockMesh's
      expansion ratio), the first at that side's end nearest the point (a string, a
      sequence or a mapping ``{(x, y): R}``)
    * ``SetSpacing(items)``: ``NAME=H`` items, the first grid edge leaving that patch, and
      ``X,Y=H`` items, the cells on both sides of the block side nearest (X, Y) H across
      it, growing along the chain (``"cylinder=0.005 0.3,0.2=0.01"``, a sequence of items
      or a mapping ``{"cylinder": 0.005, (0.3, 0.2): 0.01}``)
    * ``SetOrthogonal(names)``: patches that grid lines leave along the normal
      (``"cylinder,walls"`` or a sequence of names)
    * ``SetTimeLimit(seconds)``: pinn's training (all blocks together) ends after this many
      seconds with its best grids so far (0: no limit, the default); so does an abort
      request or SIGUSR1
    * ``SetModel(path)``: a multi-block family model (SPEC 16: ``pinn-mesh fit``'s file, or
      a fitted model) whose nodes start the solve (the report's ``family`` and the blocks'
      field data ``NetworkResult`` and ``FamilyModel`` say what was kept); "": none
    * ``SetSetting(name, value)``: any other setting of the multi-block kind by its name (its
      blocks' training: ``adam_epochs``, ``lbfgs_iterations``, ``hidden_layers``, ``preset``
      ...); None: the default

    Patch items, spacings and names are checked at the next update (one line naming the
    item, as the command line's ``--patch``, ``--spacing`` and ``--orthogonal``).
    """

    LABEL = LABEL
    FIELD_PORT = 3  # a Field input (optional): the grid adapted to its array (SPEC 14)

    def __init__(self, route: str = "paraview") -> None:
        """``route``: whose words messages are in ("paraview"; "pyvista" keeps them off VTK's
        output window, for the caller to raise ``GetLastException()``)."""
        super().__init__(nInputPorts=4, nOutputPorts=2, outputType="vtkMultiBlockDataSet")
        self.SetProgressText(LABEL)
        self._route = route
        self._blocking = BLOCKING[0]
        self._method = BLOCKS_METHOD
        self._cell_size = 0.0
        self._time_limit = NO_TIME_LIMIT
        self._interfaces = INTERFACES[0]
        self._patches: tuple[str, ...] = ()  # X,Y=NAME[:TYPE] items, checked at the update
        self._cells: tuple[str, ...] = ()  # X,Y=N items, checked at the update
        self._gradings: tuple[str, ...] = ()  # X,Y=R items, checked at the update
        self._settings: dict = {}  # SetSetting's, checked at the update
        self._last_error = self._last_warning = ""
        self._exception: Exception | None = None

    def FillOutputPortInformation(self, port, info):
        """Output 0 the blocks, output 1 the block edges meshed."""
        kind = "vtkMultiBlockDataSet" if port == 0 else "vtkPolyData"
        info.Set(vtkDataObject.DATA_TYPE_NAME(), kind)
        return 1

    # ---- settings ----------------------------------------------------------------------
    def SetBlocking(self, blocking) -> None:
        self._set("_blocking", choice(blocking, BLOCKING, "blocking"))

    def GetBlocking(self) -> str:
        return self._blocking

    def SetMethod(self, method) -> None:
        self._set("_method", choice(method, MULTIBLOCK_METHODS, "method"))

    def GetMethod(self) -> str:
        return self._method

    def SetCellSize(self, h) -> None:
        self._set("_cell_size", float(h))

    def GetCellSize(self) -> float:
        return self._cell_size

    def SetTimeLimit(self, seconds) -> None:
        self._set("_time_limit", float(seconds))

    def GetTimeLimit(self) -> float:
        return self._time_limit

    def SetInterfaces(self, interfaces) -> None:
        self._set("_interfaces", choice(interfaces, INTERFACES, "interfaces"))

    def GetInterfaces(self) -> str:
        return self._interfaces

    def SetPatchNames(self, items) -> None:
        self._set("_patches", place_items(items))

    def GetPatchNames(self) -> tuple[str, ...]:
        return self._patches

    def SetCells(self, items) -> None:
        if hasattr(items, "items"):
            items = {key: int(n) for key, n in items.items()}
        self._set("_cells", place_items(items))

    def GetCells(self) -> tuple[str, ...]:
        return self._cells

    def SetGradings(self, items) -> None:
        if hasattr(items, "items"):
            items = {key: float(r) for key, r in items.items()}
        self._set("_gradings", place_items(items))

    def GetGradings(self) -> tuple[str, ...]:
        return self._gradings

    def SetSetting(self, name: str, value) -> None:
        """A setting of the multi-block kind (``job.OPTIONS``) that no other setter sets: its
        blocks' training (``adam_epochs=...``) or ``preset``; None restores the default."""
        from pinn_engine.job import OPTIONS

        names = OPTIONS["blocks"] & setting_names() - OWN_SETTERS
        if name not in names:
            raise unknown_name(name, sorted(names), "setting")
        settings = {k: v for k, v in {**self._settings, name: value}.items() if v is not None}
        self._set("_settings", settings)

    def GetSettings(self) -> Settings:
        """The ``Settings`` the next update uses (raises ``ValueError`` if invalid)."""
        settings = dict(self._settings)
        return make_settings(
            self._method,
            settings.pop("preset", "default"),
            kind="blocks",
            cell_size=self._cell_size,
            interfaces=self._interfaces,
            time_limit=self._time_limit,
            **settings,
        )

    # ---- results -----------------------------------------------------------------------
    def GetOutput(self) -> vtkMultiBlockDataSet:
        """The blocks (after ``Update()``); empty when the last update failed."""
        return self.GetOutputDataObject(0)

    def GetBlockEdges(self) -> vtkPolyData:
        """The block edges meshed (after ``Update()``): the proposal under Automatic."""
        return self.GetOutputDataObject(1)

    # ---- pipeline ----------------------------------------------------------------------
    def RequestData(self, request, inInfo, outInfo):
        output = vtkMultiBlockDataSet.GetData(outInfo, 0)
        edges_out = vtkPolyData.GetData(outInfo, 1)
        self._last_error = self._last_warning = self._last_summary = ""
        self._exception = None
        self._progress(0.0, "meshing")
        try:
            dataset, report, edges = self._execute(inInfo)
        except Exception as exc:
            self._exception = exc
            output.Initialize()
            edges_out.Initialize()
            self._report(message_of(exc, self._route), warning=False)
        else:
            output.ShallowCopy(dataset)
            self._keep_grid()
            edges_out.ShallowCopy(edges_polydata(edges))
            warning = update_warning(report, self._route, MOVE_EDGES)
            if warning:
                self._report(warning, warning=True)
        self._progress(1.0, "done")
        self.SetProgressText(LABEL)
        return 1

    def _execute(self, inInfo) -> tuple[vtkMultiBlockDataSet, dict, list[np.ndarray]]:
        """The blocks of the connected inputs under the settings, the run's report and the
        block edges meshed."""
        from pinn_engine import job

        settings = self._adapting(self.GetSettings())
        ports = [
            [vtkPolyData.GetData(port, k) for k in range(port.GetNumberOfInformationObjects())]
            for port in inInfo[: self.FIELD_PORT]
        ]
        field = self._field(inInfo)
        geometry = job.blocks_from_polydata(
            *ports,
            automatic=self._automatic(),
            patches=self._patches,
            spacing=self._spacing,
            orthogonal=self._orthogonal,
            cells=self._cells,
            gradings=self._gradings,
            cell_size=settings.cell_size,
        )
        began = time.perf_counter()
        outcome = self._run_job(settings, geometry, self._block, family=self._model, field=field)
        self._tell(blocks_lines(settings.method, outcome.report, time.perf_counter() - began))
        return outcome.data, outcome.report, outcome.edges

    def _automatic(self) -> bool | None:
        """Whether the block edges are proposed: under Blocking Automatic, and in ParaView
        under Manual where none are connected (None: the panel's first Apply meshes); the
        other routes asked for blocks= or --blocks and are told when none came."""
        if self._blocking == "automatic":
            return True
        return None if self._route == "paraview" else False

    def _block(self, info: dict) -> str | None:
        """The pinn's progress block by block (``kinds.blocks.problem``) on the bar, the
        elliptic grid before it at 0; answers ``errors.STOP`` on an abort request or the
        stop signal (the Time Limit is the job's: ``settings.time_limit``, all blocks
        together)."""
        if info["phase"] == "prepare":
            self._progress(info["step"] / info["total"], info["stage"])
        return self._stop_answer()


__all__ = ["BLOCKING", "MOVE_EDGES", "PinnMultiBlockAlgorithm"]
