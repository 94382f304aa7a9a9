"""Runs inside the ParaView GUI (``paraview --script=...``) for scripts/paraview_screenshot.sh.

Loads example_data/fig2.vtp and fig2_aux.vtp, applies PINN Structured Mesh (the plugin comes
in through PV_PLUGIN_PATH) with a short training, colours the grid by MaxIncludedAngle, keeps
the filter selected so the Properties panel shows its settings, then writes the marker file
named by PINN_SHOT_READY.
"""

import os
import traceback

import paraview.simple as simple
from paraview.simple import (
    ColorBy,
    GetActiveViewOrCreate,
    GetColorTransferFunction,
    Render,
    SetActiveSource,
    Show,
    XMLPolyDataReader,
)


def main():
    repo = os.environ["PINN_SHOT_REPO"]
    data = os.path.join(repo, "example_data")

    boundary = XMLPolyDataReader(
        registrationName="fig2.vtp", FileName=[os.path.join(data, "fig2.vtp")]
    )
    aux = XMLPolyDataReader(
        registrationName="fig2_aux.vtp", FileName=[os.path.join(data, "fig2_aux.vtp")]
    )
    mesh = simple.PINNStructuredMesh(
        registrationName="PINNStructuredMesh1",
        Input=boundary,
        AuxiliaryLines=[aux],
        GridSize=[41, 21],
    )

    view = GetActiveViewOrCreate("RenderView")
    view.OrientationAxesVisibility = 0
    display = Show(mesh, view)
    display.SetRepresentationType("Surface With Edges")
    ColorBy(display, ("CELLS", "MaxIncludedAngle"))
    display.RescaleTransferFunctionToDataRange(True, False)
    display.SetScalarBarVisibility(view, True)
    GetColorTransferFunction("MaxIncludedAngle").ApplyPreset("Viridis (matplotlib)", True)
    for source, colour in ((boundary, [0.9, 0.1, 0.1]), (aux, [1.0, 0.6, 0.0])):
        lines = Show(source, view)
        lines.ColorArrayName = ["POINTS", ""]
        lines.AmbientColor = lines.DiffuseColor = colour
        lines.LineWidth = 3.0
        lines.Position = [0.0, 0.0, 0.01]  # in front of the grid (the camera looks down -z)
    view.InteractionMode = "2D"
    view.ResetCamera()
    view.CameraPosition = [*view.CameraFocalPoint[:2], view.CameraFocalPoint[2] + 10]
    view.CameraViewUp = [0, 1, 0]
    view.ResetCamera()
    SetActiveSource(mesh)
    Render()


try:
    main()
    status = "ready\n"
except Exception:  # report to the shell script instead of leaving the GUI waiting
    status = "error\n" + traceback.format_exc()
with open(os.environ["PINN_SHOT_READY"], "w") as marker:
    marker.write(status)
