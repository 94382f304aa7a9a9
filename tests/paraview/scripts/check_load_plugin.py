"""pvpython check: load the plugin file with LoadPlugin (as Tools > Manage Plugins > Load New
does) and run a classical method, which must not import torch.

    scripts/pvenv.sh pvpython tests/paraview/scripts/check_load_plugin.py PLUGIN_FILE EXAMPLE_DIR

Run with PV_PLUGIN_PATH pointing elsewhere. Prints one ``RESULT {json}`` line.
"""

import json
import os
import sys

import paraview.simple as simple
from paraview import servermanager
from paraview.simple import LoadPlugin, XMLPolyDataReader

PLUGIN, EXAMPLES = sys.argv[1], sys.argv[2]
result = {"before_load": hasattr(simple, "PINNStructuredMesh")}
LoadPlugin(PLUGIN, remote=False, ns=globals())
result["after_load"] = "PINNStructuredMesh" in globals()
result["old_names_after_load"] = [
    n in globals() for n in ("PINNMultiBlockMesh", "PINNHexahedralMesh")
]
result["torch_after_load"] = "torch" in sys.modules

proto = servermanager.ProxyManager().GetPrototypeProxy("filters", "PINNStructuredMesh")
it = servermanager.vtkSMOrderedPropertyIterator()
it.SetProxy(proto)
it.Begin()
order = []
while not it.IsAtEnd():
    order.append(it.GetKey())
    it.Next()
result["property_order"] = order
method = proto.GetProperty("Method").FindDomain("vtkSMEnumerationDomain")
result["methods"] = [method.GetEntryText(i) for i in range(method.GetNumberOfEntries())]
result["advanced"] = sorted(
    key for key in order if proto.GetProperty(key).GetPanelVisibility() == "advanced"
)
airfoil = servermanager.ProxyManager().GetPrototypeProxy("sources", "PINNAirfoilSource")
result["naca_label"] = airfoil.GetProperty("NACA").GetXMLLabel()
pxm = servermanager.ProxyManager()
result["help"] = {  # the panel's "?": every proxy of the plugin documented
    name: [
        pxm.GetPrototypeProxy(group, name).GetDocumentation().GetShortHelp() or "",
        pxm.GetPrototypeProxy(group, name).GetDocumentation().GetLongHelp() or "",
    ]
    for group, name in [
        ("filters", "PINNStructuredMesh"),
        ("sources", "PINNAirfoilSource"),
        ("sources", "PINNAirfoilReader"),
        ("writers", "PINNMeshCGNSWriter"),
        ("writers", "PINNMeshOpenFOAMWriter"),
    ]
}
# the help pages the GUI is given (routes/paraview_help.py): one per proxy, named by a
# (group, proxy name) ParaView knows; pvpython has no help engine to register them with

from pinn_engine.routes import help_engine, paraview_help  # noqa: E402

pages = paraview_help.help_pages(sys.modules["pinn_mesh_plugin"].help_xmls())[0]
result["help_pages"] = [page.name for page in pages]
result["help_pages_unknown"] = [
    page.name for page in pages[1:] if not pxm.GetPrototypeProxy(*page.name.split(".")[:2])
]
result["help_registered"] = [str(path) for path in help_engine.registered()]
shown = proto.GetHints().FindNestedElementByName("RepresentationType")
result["representation"] = shown.GetAttribute("type") if shown else None
aux_hints = proto.GetProperty("AuxiliaryLines").GetHints()
result["aux_optional"] = bool(aux_hints and aux_hints.FindNestedElementByName("Optional"))

boundary = XMLPolyDataReader(FileName=[os.path.join(EXAMPLES, "wavy.vtp")])
mesh = PINNStructuredMesh(Input=boundary, Method="elliptic", GridSize=[31, 16])  # noqa: F821
grid = servermanager.Fetch(mesh)
result["grid"] = {
    "class": grid.GetClassName(),
    "extent": list(grid.GetExtent()),
    "max_angle": grid.GetCellData().GetArray("MaxIncludedAngle") is not None,
    "method": grid.GetFieldData().GetAbstractArray("Method").GetValue(0),
}
# a field per preset for the settings the presets differ in; the chosen
# preset's is used (and shown), the other's is not
presets = PINNStructuredMesh(Input=boundary, Preset="paper", AdamEpochs=7)  # noqa: F821
presets.UpdateVTKObjects()
alg = presets.GetClientSideObject()
first = alg.GetSettings()
presets.PaperLBFGSIterations = 90
presets.UpdateVTKObjects()
second = alg.GetSettings()
presets.Preset = "default"
presets.UpdateVTKObjects()
third = alg.GetSettings()
result["presets"] = [[s.adam_epochs, s.lbfgs_iterations, s.lambda2] for s in (first, second, third)]


def decorated_by(element):
    """The (property, value) pairs of the widget decorators under an XML element."""
    found = []
    for k in range(element.GetNumberOfNestedElements()):
        child = element.GetNestedElement(k)
        if child.GetAttribute("property"):
            found.append((child.GetAttribute("property"), child.GetAttribute("value") or ""))
        found += decorated_by(child)
    return found


result["preset_decorators"] = {
    key: decorated_by(proto.GetProperty(key).GetHints())
    for key in ("AdamEpochs", "PaperAdamEpochs", "Lambda2", "PaperLambda2")
}
result["torch_at_end"] = "torch" in sys.modules
print("RESULT " + json.dumps(result))
