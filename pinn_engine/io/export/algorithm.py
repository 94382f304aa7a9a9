"""The writers as a VTK sink (``GridWriter``): what ParaView's File > Save Data runs.

The ParaView plugin decorates one subclass per format (``plugin/pinn_mesh_plugin.py``);
the algorithm itself is plain VTK, so it also works in any VTK pipeline::

    w = GridWriter("cgns")
    w.SetInputConnection(mesh_algorithm.GetOutputPort())
    w.SetFileName("out/grid.cgns")
    w.Write()

Its input is a grid of the structured filters (``vtkStructuredGrid``) or the multi-block
filter's blocks (``vtkMultiBlockDataSet``, written by ``export.write_blocks``). Patch
names come from the grid's ``PatchNames`` (the filter's Patch Names field). Errors
are one line ``PINN Mesh writer: <message>`` through ``vtkOutputWindow`` (ParaView's
Output Messages) and ``GetLastError()``; nothing is written then.
"""

from __future__ import annotations

from pathlib import Path

from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase
from vtkmodules.vtkCommonCore import vtkCommand, vtkOutputWindow
from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet, vtkStructuredGrid

from pinn_engine.errors import InputError, MissingExtraError, PinnMeshError
from pinn_engine.io.export import FORMATS, is_box, write, write_blocks

LABEL = "PINN Mesh writer"
# formats offered in ParaView (its own writers cover .vts and .vtk), as each registers
# itself: key -> (extension, writer proxy name, pvpython:
# ``servermanager.writers.PINNMeshCGNSWriter(Input=..., ...)``; file type in Save Data's
# list, short so that the list shows it whole)
PARAVIEW_FORMATS = {key: f.paraview for key, f in FORMATS.items() if f.paraview}


class GridWriter(VTKPythonAlgorithmBase):
    """Writes its input ``vtkStructuredGrid`` in one of ``export.FORMATS``.

    ``SetFileName(path)``; for OpenFOAM a ``NAME.foam`` path writes the case folder
    ``NAME/`` beside it (with ``NAME/NAME.foam`` inside, which ParaView opens).
    ``SetExtrudeThickness(t)``: one cell of thickness t in z (0: 2D; OpenFOAM: the mean
    edge length).
    """

    FORMAT = "vts"

    def __init__(self, fmt: str | None = None) -> None:
        super().__init__(nInputPorts=1, nOutputPorts=0, inputType="vtkDataObject")
        self._format = fmt or self.FORMAT
        self._file_name = ""
        self._extrude = 0.0
        self._last_error = self._last_message = ""

    def SetFileName(self, name) -> None:
        if name != self._file_name:
            self._file_name = name or ""
            self.Modified()

    def GetFileName(self) -> str:
        return self._file_name

    def SetExtrudeThickness(self, value) -> None:
        value = float(value or 0.0)
        if value != self._extrude:
            self._extrude = value
            self.Modified()

    def GetLastError(self) -> str:
        return self._last_error

    def GetIsThreeD(self) -> int:
        """1 when the connected input is a hexahedral grid (nothing to extrude), else 0:
        what the Save Data panel's Extrude Thickness is hidden by."""
        grid = self.GetInputDataObject(0, 0) if self.GetNumberOfInputConnections(0) else None
        return int(
            isinstance(grid, vtkStructuredGrid) and grid.GetNumberOfPoints() > 0 and is_box(grid)
        )

    def GetLastMessage(self) -> str:
        """What the last write told Output Messages besides errors: the file written (or
        where an OpenFOAM case went)."""
        return self._last_message

    def Write(self) -> int:
        self.Modified()
        self.Update()
        return 0 if self._last_error else 1

    def RequestData(self, request, inInfo, outInfo):
        self._last_error = self._last_message = ""
        try:
            if not self._file_name:
                raise InputError("no file name given")
            path = Path(self._file_name)
            if self._format == "openfoam":
                path = path.with_suffix("") if path.suffix.lower() == ".foam" else path
            data = inInfo[0].GetInformationObject(0).Get(vtkMultiBlockDataSet.DATA_OBJECT())
            extrude = self._extrude if self._extrude > 0 else None
            if isinstance(data, vtkMultiBlockDataSet):
                written = write_blocks(data, path, self._format, extrude=extrude)
            elif isinstance(data, vtkStructuredGrid):
                written = write(data, path, self._format, extrude=extrude)
            else:
                kind = "nothing" if data is None else f"a {data.GetClassName()}"
                raise InputError(f"writes the grids of the PINN filters, not {kind}")
            if self._format == "openfoam":  # a folder appears: say where
                self._last_message = (
                    f"{LABEL}: wrote the OpenFOAM case {written} "
                    f"(mesh in {written / 'constant' / 'polyMesh'}; open {written.name}.foam)"
                )
            else:
                self._last_message = f"{LABEL}: wrote {written} ({FORMATS[self._format].name})"
            vtkOutputWindow.GetInstance().DisplayText(self._last_message + "\n")
        except (InputError, MissingExtraError) as exc:
            self._report(str(exc.for_route("paraview")))
        except PinnMeshError as exc:
            self._report(str(exc))
        except OSError as exc:
            where = f"{exc.filename}: " if getattr(exc, "filename", None) else ""
            self._report(f"{where}{exc.strerror or exc}")
        except Exception as exc:  # never let an exception reach ParaView's executive
            self._report(f"unexpected {type(exc).__name__}: {exc}")
        return 1

    def _report(self, message: str) -> None:
        line = f"{LABEL}: {' '.join(str(message).split())}"
        self._last_error = line
        vtkOutputWindow.GetInstance().DisplayErrorText(line + "\n")
        self.InvokeEvent(vtkCommand.ErrorEvent, line)
