"""What the multi-block and hexahedral filters tell and how they stop in the ParaView
GUI: the command line's summary line after an update, an untagged surface's faces found at
Face Angle, a 2D curve pointed to the 2D filters, and a training stopped by an abort
request or the Time Limit with its best grid kept and one warning line."""

from __future__ import annotations

import json

import pytest
import pyvista as pv
from helpers import EXAMPLES, OutputMessages

from pinn_engine.routes.hexa_algorithm import PinnHexaAlgorithm
from pinn_engine.routes.multiblock_algorithm import PinnMultiBlockAlgorithm

SIZE = (7, 6, 5)  # the bend at a small size: a quick pinn


def _hexa(surface, method: str = "tfi") -> PinnHexaAlgorithm:
    alg = PinnHexaAlgorithm()
    alg.SetInputDataObject(0, surface)
    alg.SetMethod(method)
    alg.SetGridSize(*SIZE)
    return alg


def test_the_hexahedral_filter_tells_the_command_lines_summary_line():
    alg = _hexa(pv.read(EXAMPLES / "hexa_bend.vtp"))
    with OutputMessages(alg, "ErrorEvent") as said:
        alg.Update()
    assert said.lines == [] and len(said.told) == 3  # short lines: the panel cuts long ones
    assert said.told[0].startswith(
        "PINN Structured Mesh (Hexahedral): tfi 7x6x5 hexahedral grid, 120 cells"
    )
    assert said.told[1].startswith("PINN Structured Mesh (Hexahedral): min ScaledJacobian")
    assert said.told[2] == (
        "PINN Structured Mesh (Hexahedral): "
        "faces face0=jmin face1=jmax face2=imax face3=imin face4=kmin face5=kmax"
    )
    assert all(len(line) < 130 for line in said.told)
    assert said.told[0] in said.window.GetOutput()  # what Output Messages shows
    alg.SetInputDataObject(0, pv.Sphere())
    alg.Update()
    assert alg.GetLastSummary() == "" and alg.GetLastError()


def test_an_stl_surface_is_split_at_face_angle_and_a_curve_is_pointed_to_the_2d_filters():
    alg = _hexa(pv.read(EXAMPLES / "hexa_bend.stl"))  # no FaceId: faces at 40 degrees
    alg.SetPatchNames("face0=inner:wall")
    alg.Update()
    assert alg.GetLastError() == "" and alg.GetOutput().GetNumberOfPoints() == 7 * 6 * 5
    assert alg.GetPatchNames()[2] == "inner"  # face 0, the inner wall, is jmin
    alg.SetFaceAngle(95.0)  # the bend's edges turn by 90 degrees: one face
    alg.Update()
    assert alg.GetLastError() == (
        "PINN Structured Mesh (Hexahedral): input: found 1 faces at edges sharper than 95 degrees; "
        "a six-faced domain needs 6 (try another Face Angle or a FaceId cell array)"
    )
    alg = _hexa(pv.read(EXAMPLES / "fig2.vtp"))
    alg.Update()
    assert alg.GetLastError() == (
        "PINN Structured Mesh (Hexahedral): input: holds no surface triangles: a 2D curve is "
        "meshed by PINN Structured Mesh (four-sided, or a body with Topology O-grid or C-grid) "
        "or by PINN Structured Mesh (Multi-Block); this filter takes a closed surface"
    )


@pytest.mark.slow
def test_an_abort_request_stops_the_hexahedral_training_with_its_best_grid():
    alg = _hexa(pv.read(EXAMPLES / "hexa_bend.vtp"), "pinn")
    alg.SetOrthogonal("kmin")  # a term the Winslow start leaves to win: the network trains

    asked = []

    def abort_when_training(obj, event):
        if "training" in obj.GetProgressText() and not asked:
            asked.append(obj.GetProgress())
            obj.SetAbortExecute(1)  # what the progress bar's abort button asks, once

    alg.AddObserver("ProgressEvent", abort_when_training)
    alg.Update()
    assert alg.GetLastError() == "" and alg.GetOutput().GetNumberOfPoints() == 7 * 6 * 5
    report = json.loads(alg.GetOutput().GetFieldData().GetAbstractArray("Report").GetValue(0))
    assert report["training"]["stopped"]["reason"] == "request"
    assert "a stop was asked" in alg.GetLastWarning()
    assert not alg.GetAbortExecute()


def test_the_multiblock_time_limit_ends_the_training_with_its_best_grids():
    alg = PinnMultiBlockAlgorithm()
    alg.SetInputDataObject(0, pv.read(EXAMPLES / "lshape.vtp"))
    alg.AddInputDataObject(0, pv.read(EXAMPLES / "lshape_blocks.vtp"))
    alg.SetInputDataObject(2, pv.read(EXAMPLES / "lshape_aux.vtp"))  # a line to follow: trains
    alg.SetMethod("pinn")
    alg.SetCellSize(0.25)
    alg.SetTimeLimit(0.01)  # spent before the first block trains
    alg.Update()
    assert alg.GetLastError() == "" and alg.GetOutput().GetNumberOfBlocks() > 1
    assert "its time limit of 0.01 s ran out" in alg.GetLastWarning()
    assert "a larger Time Limit (0: none)" in alg.GetLastWarning()
    assert alg.GetLastSummary().startswith("pinn ")
