"""pvpython check of the PINN Structured Mesh plugin (run by tests/paraview/test_paraview.py).

    scripts/pvenv.sh pvpython tests/paraview/scripts/check_filter.py EXAMPLE_DIR

Expects the plugin to be loaded already through PV_PLUGIN_PATH (scripts/pvenv.sh sets it).
Prints one ``RESULT {json}`` line; any failed check raises (exit status 1).
"""

import json
import os
import sys
import time

import paraview.simple as simple
from paraview import servermanager
from paraview.simple import PolyLineSource, XMLPolyDataReader
from pvcommon import captured_errors
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

EXAMPLES = sys.argv[1]
SHORT = {"AdamEpochs": 60, "LBFGSIterations": 5}
result = {
    "pinn_engine_on_pythonpath": any(
        os.path.isdir(os.path.join(p, "pinn_engine"))
        for p in os.environ.get("PYTHONPATH", "").split(os.pathsep)
        if p
    )
}


def field(grid, name):
    arr = grid.GetFieldData().GetArray(name)
    return None if arr is None else arr.GetValue(0)


def summary(grid):
    return {
        "class": grid.GetClassName(),
        "extent": list(grid.GetExtent()),
        "points": grid.GetNumberOfPoints(),
        "cell_arrays": [
            grid.GetCellData().GetArrayName(i)
            for i in range(grid.GetCellData().GetNumberOfArrays())
        ],
        "method": grid.GetFieldData().GetAbstractArray("Method").GetValue(0)
        if grid.GetFieldData().GetAbstractArray("Method")
        else None,
        "trained": field(grid, "Trained"),
        "training_count": field(grid, "TrainingCount"),
    }


# 1. the plugin came in through PV_PLUGIN_PATH (no LoadPlugin), pinn_engine via the plugin
assert hasattr(simple, "PINNStructuredMesh"), "PINN Structured Mesh filter not loaded"
result["torch_after_load"] = "torch" in sys.modules
proto = servermanager.ProxyManager().GetPrototypeProxy("filters", "PINNStructuredMesh")
result["label"] = proto.GetXMLLabel()
hints = proto.GetHints()
menu = hints.FindNestedElementByName("ShowInMenu") if hints else None
result["menu_category"] = menu.GetAttribute("category") if menu else None
import pinn_engine  # noqa: E402  (already imported by the plugin)

result["pinn_engine_file"] = pinn_engine.__file__

boundary = XMLPolyDataReader(FileName=[os.path.join(EXAMPLES, "fig2.vtp")])
aux = XMLPolyDataReader(FileName=[os.path.join(EXAMPLES, "fig2_aux.vtp")])

# 2. boundary + auxiliary lines, short training; progress events reach the algorithm
mesh = simple.PINNStructuredMesh(Input=boundary, AuxiliaryLines=[aux], GridSize=[41, 21], **SHORT)
progress = []
alg = mesh.GetClientSideObject()
alg.AddObserver("ProgressEvent", lambda obj, event: progress.append(obj.GetProgress()))
start = time.perf_counter()
grid = servermanager.Fetch(mesh)
result["first"] = summary(grid)
result["first_seconds"] = time.perf_counter() - start
result["whole_extent"] = list(mesh.GetDataInformation().GetExtent())
result["progress"] = [min(progress), max(progress), len(progress)] if progress else []
first_points = vtk_to_numpy(grid.GetPoints().GetData()).copy()

# 3. a new grid size trains anew (the default starts from the elliptic grid of that size);
#    back at the first size, the first network is re-used, not retrained
mesh.GridSize = [61, 31]
result["resized"] = summary(servermanager.Fetch(mesh))
mesh.GridSize = [41, 21]
start = time.perf_counter()
back = servermanager.Fetch(mesh)
result["back"] = summary(back)
result["back_seconds"] = time.perf_counter() - start
result["back_max_diff"] = float(abs(vtk_to_numpy(back.GetPoints().GetData()) - first_points).max())

# 4. the two auxiliary polylines as two inputs (PolyLineSource) on a new filter instance
reader = vtkXMLPolyDataReader()
reader.SetFileName(os.path.join(EXAMPLES, "fig2_aux.vtp"))
reader.Update()
lines = reader.GetOutput()
sources = []
for k in range(lines.GetNumberOfCells()):
    ids = lines.GetCell(k).GetPointIds()
    pts = [c for i in range(ids.GetNumberOfIds()) for c in lines.GetPoint(ids.GetId(i))]
    sources.append(PolyLineSource(Points=pts))
two = simple.PINNStructuredMesh(Input=boundary, AuxiliaryLines=sources, GridSize=[41, 21], **SHORT)
grid_two = servermanager.Fetch(two)
result["two_inputs"] = summary(grid_two)
result["two_inputs_max_diff"] = float(
    abs(vtk_to_numpy(grid_two.GetPoints().GetData()) - first_points).max()
)

# 4b. boundary and auxiliary lines both on Input, as the GUI connects two selected sources
both = simple.PINNStructuredMesh(Input=[aux, boundary], GridSize=[41, 21], **SHORT)
grid_both = servermanager.Fetch(both)
result["both_on_input"] = summary(grid_both)
result["both_on_input_max_diff"] = float(
    abs(vtk_to_numpy(grid_both.GetPoints().GetData()) - first_points).max()
)

# 5. a bad boundary (the auxiliary file: two open polylines): empty output, one error line
bad = simple.PINNStructuredMesh(Input=aux, **SHORT)
with captured_errors() as err:
    bad_grid = servermanager.Fetch(bad)
result["bad"] = {"points": bad_grid.GetNumberOfPoints(), "class": bad_grid.GetClassName()}
result["bad_vtk_text"] = err["vtk"]
result["bad_stderr"] = err["stderr"]

# 6. ParaView goes on: fix the input of the failed filter and update again
bad.Input = boundary
bad.AuxiliaryLines = [aux]
result["recovered"] = summary(servermanager.Fetch(bad))

# 7. boundary-layer settings (SPEC 7): first-edge spacing and orthogonal sides on the panel
layer = simple.PINNStructuredMesh(
    Input=boundary,
    Method=3,
    GridSize=[41, 21],
    FirstEdgeSpacing=[0.01, 0, 0, 0],
    OrthogonalSides=[1, 0, 0, 0],
)
fd = servermanager.Fetch(layer).GetFieldData()
result["layer"] = {
    "first_edge": [fd.GetArray("FirstEdge_bottom").GetValue(k) for k in range(3)],
    "angle": fd.GetArray("WallAngleDeviation_bottom").GetValue(0),
    "properties": list(layer.ListProperties()),
}
result["torch_at_end"] = "torch" in sys.modules
print("RESULT " + json.dumps(result))
