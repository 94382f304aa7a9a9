"""A blockMeshDict read and meshed as a VTK algorithm (SPEC 15): the file in, its blocks out.

``PinnBlockMeshDictReader`` is a plain ``VTKPythonAlgorithmBase`` subclass with no input
port; ``plugin/`` decorates it as ParaView's reader of ``blockMeshDict`` files and
``pinn_engine.read_blockmeshdict`` runs it for pyvista.

>>> alg = PinnBlockMeshDictReader()
>>> alg.SetFileName("system/blockMeshDict")
>>> alg.SetMethod("elliptic")                  # pinn (default), elliptic or tfi
>>> alg.Update()
>>> blocks = alg.GetOutputDataObject(0)        # vtkMultiBlockDataSet: block0, block1, ...

Output 0 the ``vtkMultiBlockDataSet`` of the command line's ``.vtm``: a
``vtkStructuredGrid`` a block with cell arrays ``MaxIncludedAngle``, ``MinIncludedAngle``,
``ScaledJacobian``, ``Folded`` and field data ``Method``, ``Report`` (JSON) and checkMesh's
figures. A failed update leaves the output empty and reports one line (``GetLastError()``,
``GetLastException()``; in ParaView in Output Messages).
"""

from __future__ import annotations

from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase
from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet

from pinn_engine.errors import InputError
from pinn_engine.routes.filters import LastOutcome, choice
from pinn_engine.routes.reporting import message_of
from pinn_engine.routes.summary_lines import dictionary_line
from pinn_engine.settings import DICTIONARY_METHODS, KIND_SETTINGS

LABEL = "PINN blockMeshDict Reader"
INTERFACES = KIND_SETTINGS["blocks3d"].CONSTRAINTS["interfaces"].values  # free, fixed
DEFAULT = KIND_SETTINGS["blocks3d"]()  # its method and interfaces at first


class PinnBlockMeshDictReader(LastOutcome, VTKPythonAlgorithmBase):
    """The blocks of an OpenFOAM blockMeshDict, meshed (SPEC 15).

    * ``SetFileName(path)``: the dictionary
    * ``SetMethod(name)`` (or its index in ``settings.DICTIONARY_METHODS``): ``pinn``
      (default: the better of the Winslow grid and blockMesh's placement), ``elliptic`` or
      ``tfi``
    * ``SetInterfaces(name)``: ``free`` (default: interfaces solved) or ``fixed``
      (blockMesh's placement of the block faces kept)
    """

    LABEL = LABEL

    def __init__(self, route: str = "paraview") -> None:
        super().__init__(nInputPorts=0, nOutputPorts=1, outputType="vtkMultiBlockDataSet")
        self._route = route
        self._filename, self._method, self._interfaces = (
            "",
            DICTIONARY_METHODS[0],
            DEFAULT.interfaces,
        )
        self._last_error = self._last_warning = ""
        self._exception: Exception | None = None

    def _set(self, name: str, value) -> None:
        if getattr(self, name) != value:
            setattr(self, name, value)
            self.Modified()

    def SetFileName(self, name) -> None:
        self._set("_filename", str(name or ""))

    def GetFileName(self) -> str:
        return self._filename

    def SetMethod(self, method) -> None:
        self._set("_method", choice(method, DICTIONARY_METHODS, "method"))

    def GetMethod(self) -> str:
        return self._method

    def SetInterfaces(self, interfaces) -> None:
        self._set("_interfaces", choice(interfaces, INTERFACES, "interfaces"))

    def GetInterfaces(self) -> str:
        return self._interfaces

    def RequestData(self, request, inInfo, outInfo):
        from pinn_engine import job
        from pinn_engine.settings import make_settings

        output = vtkMultiBlockDataSet.GetData(outInfo, 0)
        self._last_error = self._last_warning = self._last_summary = ""
        self._exception = None
        try:
            if not self._filename:
                raise InputError("no file name set")
            settings = make_settings(self._method, kind="blocks3d", interfaces=self._interfaces)
            geometry = job.dictionary_from_file(self._filename)
            outcome = job.run(settings, geometry, self._stage)
        except Exception as exc:
            self._exception = exc
            output.Initialize()
            self._report(message_of(exc, self._route), warning=False)
            return 1
        output.ShallowCopy(outcome.data)
        self._tell([dictionary_line(outcome.report)])
        return 1

    def _stage(self, info: dict) -> None:
        self._progress(info["step"] / info["total"], info["stage"])
