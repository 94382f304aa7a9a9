"""Runs inside the ParaView GUI (``paraview --script=...``) for tests/paraview/gui/drive.sh.

Opens example_data/fig2.vtp and fig2_aux.vtp, turns on auto-apply and, for every PINN
Structured Mesh filter the GUI creates, writes what its update gave (points, auxiliary lines,
inputs, error) to the JSON file named by PINN_GUI_RESULT, and creates PINN_GUI_RESULT.training
once its progress says it trains. PINN_GUI_LONG=1 makes new filters
default to a long training (Preset paper, 200000 Adam epochs) for the stop tests, with the
Time Limit PINN_GUI_TIME_LIMIT when set. Writes the file named by PINN_GUI_READY when the GUI
may be driven. A timer answers drive.sh's requests (``on_timer``): change the filter's input,
write the display's state.
"""

import json
import os
import traceback

import paraview.simple as simple
from paraview import servermanager

RESULT = os.environ["PINN_GUI_RESULT"]
DATA = os.path.join(os.environ["PINN_GUI_REPO"], "example_data")
watched = {}


def write(proxy, alg):
    try:
        grid = alg.GetOutput()
        report = grid.GetFieldData().GetAbstractArray("Report")
        report = json.loads(report.GetValue(0)) if report is not None else {}
        prop = proxy.SMProxy.GetProperty("Input")
        connected = [prop.GetProxy(k) for k in range(prop.GetNumberOfProxies())]
        result = {
            "points": grid.GetNumberOfPoints(),
            "aux_lines": report.get("aux_lines"),
            "inputs": sorted(
                name for (name, _), src in simple.GetSources().items() if src.SMProxy in connected
            ),
            "error": alg.GetLastError(),
            "warning": alg.GetLastWarning(),
        }
    except Exception:
        result = {"exception": traceback.format_exc()}
    with open(RESULT + ".tmp", "w") as f:
        json.dump(result, f)
    os.replace(RESULT + ".tmp", RESULT)


def training(alg):
    """Marks (file PINN_GUI_RESULT.training) that the filter's training is under way."""
    marker = RESULT + ".training"
    if alg.GetProgressText().startswith("PINN Structured Mesh: training") and not os.path.exists(
        marker
    ):
        open(marker, "w").close()


def on_register(obj, event):
    for key, proxy in simple.GetSources().items():
        if proxy.GetXMLName() == "PINNStructuredMesh" and key not in watched:
            alg = proxy.GetClientSideObject()
            alg.AddObserver("ProgressEvent", lambda o, e, a=alg: training(a))
            watched[key] = alg.AddObserver("EndEvent", lambda o, e, p=proxy, a=alg: write(p, a))


def display_state():
    """The filter's display in the active view: representation, colour array, points, and
    the selected source's proxy name."""
    view = simple.GetActiveView()
    for proxy in simple.GetSources().values():
        if proxy.GetXMLName() == "PINNStructuredMesh":
            display = simple.GetDisplayProperties(proxy, view)
            alg = proxy.GetClientSideObject()
            return {
                "representation": str(display.Representation).strip("'"),
                "colour": [str(c) for c in display.ColorArrayName],
                "points": alg.GetOutput().GetNumberOfPoints(),
                "error": alg.GetLastError(),
                "selected": simple.GetActiveSource().GetXMLName(),
            }
    return {}


def on_timer(obj, event):
    """Requests from drive.sh as files: RESULT.fix connects the filter to both sources (the
    user's Change Input), RESULT.probe NAME writes display_state() to NAME."""
    try:
        if os.path.exists(RESULT + ".fix"):
            os.remove(RESULT + ".fix")
            sources = simple.GetSources()
            mesh = next(p for p in sources.values() if p.GetXMLName() == "PINNStructuredMesh")
            mesh.Input = [simple.FindSource("fig2.vtp"), simple.FindSource("fig2_aux.vtp")]
        if os.path.exists(RESULT + ".probe"):
            with open(RESULT + ".probe") as f:
                name = f.read().strip()
            os.remove(RESULT + ".probe")
            with open(name + ".tmp", "w") as f:
                json.dump(display_state(), f)
            os.replace(name + ".tmp", name)
    except Exception:
        with open(RESULT + ".timer_error", "a") as f:
            f.write(traceback.format_exc())


def main():
    view = simple.GetActiveViewOrCreate("RenderView")
    view.OrientationAxesVisibility = 0
    for name in ("fig2.vtp", "fig2_aux.vtp"):
        reader = simple.XMLPolyDataReader(
            registrationName=name, FileName=[os.path.join(DATA, name)]
        )
        simple.Show(reader, view)
    simple.ResetCamera()
    simple.Render()
    simple.GetSettingsProxy("GeneralSettings").AutoApply = 1
    if os.environ.get("PINN_GUI_LONG") == "1":
        settings = servermanager.vtkSMSettings.GetInstance()
        settings.SetSetting("filters.PINNStructuredMesh.Preset", 1)
        settings.SetSetting("filters.PINNStructuredMesh.PaperAdamEpochs", 200000)
        if os.environ.get("PINN_GUI_TIME_LIMIT"):
            limit = float(os.environ["PINN_GUI_TIME_LIMIT"])
            settings.SetSetting("filters.PINNStructuredMesh.TimeLimit", limit)
    servermanager.ProxyManager().SMProxyManager.AddObserver("RegisterEvent", on_register)
    interactor = view.GetRenderWindow().GetInteractor()  # Qt's timer: polls drive.sh's files
    interactor.AddObserver("TimerEvent", on_timer)
    interactor.CreateRepeatingTimer(300)


try:
    main()
    status = "ready\n"
except Exception:
    status = "error\n" + traceback.format_exc()
with open(os.environ["PINN_GUI_READY"], "w") as f:
    f.write(status)
