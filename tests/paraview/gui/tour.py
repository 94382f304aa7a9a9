"""Runs inside the ParaView GUI (``paraview --script=...``) for tests/paraview/gui/tour.sh.

Opens example_data/hexa_bend.stl and fig2.vtp (both shown), turns on auto-apply, makes new
PINN Structured Mesh filters default to Method elliptic (a quick grid; the hexahedral one's
grid small), writes what each update of a PINN filter gave (points, error, summary, the
inputs' visibility, the display's colouring) to PINN_GUI_RESULT.NAME.json (NAME: the
filter's registration name; PINN_GUI_RESULT.NAME.created as soon as it exists), and writes
PINN_GUI_READY when the GUI may be driven;
PINN_GUI_RESULT.help.json: the help files the plugin registered with the GUI's help engine
and their pages.
"""

import json
import os
import sqlite3
import traceback

import paraview.simple as simple
from paraview import servermanager

from pinn_engine.routes import help_engine

RESULT = os.environ["PINN_GUI_RESULT"]
DATA = os.path.join(os.environ["PINN_GUI_REPO"], "example_data")
MESH_FILTERS = (
    "PINNStructuredMesh",
    "PINNStructuredMeshMultiBlock",
    "PINNStructuredMeshHexahedral",
)
watched = {}


def state(key, proxy, alg):
    """What the filter's last update gave and how the view shows it and its inputs."""
    view = simple.GetActiveView()
    display = simple.GetDisplayProperties(proxy, view)
    prop = proxy.SMProxy.GetProperty("Input")
    inputs = [prop.GetProxy(k) for k in range(prop.GetNumberOfProxies())]
    shown = {
        name: int(simple.GetDisplayProperties(src, view).Visibility)
        for (name, _), src in simple.GetSources().items()
        if src.SMProxy in inputs
    }
    return {
        "name": key[0],
        "points": alg.GetOutputDataObject(0).GetNumberOfPoints(),
        "error": alg.GetLastError(),
        "summary": alg.GetLastSummary(),
        "inputs_visible": shown,
        "representation": str(display.Representation).strip("'"),
        "colour": [str(c) for c in display.ColorArrayName],
    }


def on_timer(obj, event):
    """Writes each watched filter's state once its update has ended (RESULT.NAME.json)."""
    for key, (proxy, alg, ended) in list(watched.items()):
        if not ended:
            continue
        try:
            result = state(key, proxy, alg)
        except Exception:
            result = {"exception": traceback.format_exc()}
        path = f"{RESULT}.{key[0]}.json"
        with open(path + ".tmp", "w") as f:
            json.dump(result, f)
        os.replace(path + ".tmp", path)
        watched[key] = (proxy, alg, False)


def on_register(obj, event):
    for key, proxy in simple.GetSources().items():
        if proxy.GetXMLName() in MESH_FILTERS and key not in watched:
            alg = proxy.GetClientSideObject()
            watched[key] = (proxy, alg, False)

            def ended(o, e, k=key, p=proxy, a=alg):
                watched[k] = (p, a, True)  # written by the timer, after the display exists

            alg.AddObserver("EndEvent", ended)
            open(f"{RESULT}.{key[0]}.created", "w").close()  # tour.sh: the quick-launch acted


def write_help_state():
    """The .qch files the plugin registered (one) and the pages each holds."""
    pages = {}
    for path in help_engine.registered():
        with sqlite3.connect(path) as db:
            pages[str(path)] = [r[0] for r in db.execute("SELECT Name FROM FileNameTable")]
    with open(f"{RESULT}.help.json", "w") as f:
        json.dump(pages, f)


def main():
    write_help_state()
    view = simple.GetActiveViewOrCreate("RenderView")
    view.OrientationAxesVisibility = 0
    stl = simple.STLReader(
        registrationName="hexa_bend.stl", FileNames=[os.path.join(DATA, "hexa_bend.stl")]
    )
    simple.Show(stl, view)
    curve = simple.XMLPolyDataReader(
        registrationName="fig2.vtp", FileName=[os.path.join(DATA, "fig2.vtp")]
    )
    simple.Show(curve, view)
    simple.ResetCamera()
    simple.Render()
    simple.GetSettingsProxy("GeneralSettings").AutoApply = 1
    settings = servermanager.vtkSMSettings.GetInstance()
    settings.SetSetting("filters.PINNStructuredMeshHexahedral.Method", 2)  # elliptic: quick
    for axis, nodes in enumerate((13, 11, 9)):
        settings.SetSetting("filters.PINNStructuredMeshHexahedral.GridSize", axis, nodes)
    servermanager.ProxyManager().SMProxyManager.AddObserver("RegisterEvent", on_register)
    interactor = view.GetRenderWindow().GetInteractor()
    interactor.AddObserver("TimerEvent", on_timer)
    interactor.CreateRepeatingTimer(300)


try:
    main()
    status = "ready\n"
except Exception:
    status = "error\n" + traceback.format_exc()
with open(os.environ["PINN_GUI_READY"], "w") as f:
    f.write(status)
