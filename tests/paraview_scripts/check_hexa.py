"""pvpython check of the PINN Hexahedral Mesh filter (run by tests/test_paraview.py).

    scripts/pvenv.sh pvpython tests/paraview_scripts/check_hexa.py EXAMPLE_DIR

The 90-degree bend of example_data by tfi, elliptic and pinn (the default), by tfi with
Patch Names and First Edge Spacing, with Orthogonal Patches (refused for tfi), then a sphere
(no FaceId) and the bend again on the same filter. Prints one ``RESULT {json}`` line; any failed
check raises (exit status 1).
"""

import json
import os
import sys

import paraview.simple as simple
from paraview import servermanager
from paraview.simple import XMLPolyDataReader
from pvcommon import captured_errors
from vtkmodules.util.numpy_support import vtk_to_numpy

EXAMPLES = sys.argv[1]
SIZE = [11, 9, 7]  # unequal: a swapped direction shows in the extent
result = {}


def grid_of(grid):
    """The grid's class, extent, points (nk, nj, ni, 3) as lists, cell arrays and figures."""
    ext = grid.GetExtent()
    cd, fd = grid.GetCellData(), grid.GetFieldData()
    shape = (ext[5] + 1, ext[3] + 1, ext[1] + 1, 3)
    return {
        "class": grid.GetClassName(),
        "extent": list(ext),
        "points": vtk_to_numpy(grid.GetPoints().GetData()).reshape(shape).tolist(),
        "cell_arrays": [cd.GetArrayName(i) for i in range(cd.GetNumberOfArrays())],
        "folded": int(vtk_to_numpy(cd.GetArray("Folded")).sum()),
        "min_scaled_jacobian": float(vtk_to_numpy(cd.GetArray("ScaledJacobian")).min()),
        "method": fd.GetAbstractArray("Method").GetValue(0),
        "patches": [fd.GetAbstractArray("PatchNames").GetValue(k) for k in range(6)],
        "types": [fd.GetAbstractArray("PatchTypes").GetValue(k) for k in range(6)],
        "report": json.loads(fd.GetAbstractArray("Report").GetValue(0)),
    }


proto = servermanager.ProxyManager().GetPrototypeProxy("filters", "PINNHexahedralMesh")
result["label"] = proto.GetXMLLabel()
result["menu_category"] = (
    proto.GetHints().FindNestedElementByName("ShowInMenu").GetAttribute("category")
)
shown = proto.GetHints().FindNestedElementByName("RepresentationType")
result["representation"] = shown.GetAttribute("type")
result["help"] = [proto.GetDocumentation().GetShortHelp(), proto.GetDocumentation().GetLongHelp()]

surface = XMLPolyDataReader(FileName=[os.path.join(EXAMPLES, "hexa_bend.vtp")])
mesh = simple.PINNHexahedralMesh(Input=surface, GridSize=SIZE, Method="tfi")
progress, texts = [], set()


def watch(obj, event):
    progress.append(obj.GetProgress())
    texts.add(obj.GetProgressText())


mesh.GetClientSideObject().AddObserver("ProgressEvent", watch)
with captured_errors() as quiet:
    result["tfi"] = grid_of(servermanager.Fetch(mesh))
result["messages"] = quiet["vtk"]
result["properties"] = mesh.ListProperties()
result["methods"] = mesh.GetProperty("Method").Available
result["progress"] = [min(progress), max(progress)] if progress else []
result["progress_texts"] = sorted(texts)

mesh.Method = "elliptic"
result["elliptic"] = grid_of(servermanager.Fetch(mesh))
mesh.Method = "pinn"  # the network trained inside ParaView's Python
result["pinn"] = grid_of(servermanager.Fetch(mesh))

# the command line's --patch and --spacing from the panel
mesh.Method = "tfi"
mesh.PatchNames = "imin=inlet:inflow kmin=floor:wall"
mesh.FirstEdgeSpacing = "kmin=0.01"
result["spaced"] = grid_of(servermanager.Fetch(mesh))
mesh.OrthogonalPatches = "kmin"  # tfi's lines cannot turn: one line in the panel's words
with captured_errors() as err:
    result["orthogonal_tfi_points"] = servermanager.Fetch(mesh).GetNumberOfPoints()
result["orthogonal_tfi_text"] = err["vtk"]
mesh.OrthogonalPatches = ""

# a surface without FaceId: empty output, one line in the panel's words
mesh.Input = simple.Sphere()
with captured_errors() as err:
    bad = servermanager.Fetch(mesh)
result["bad_points"] = bad.GetNumberOfPoints()
result["bad_vtk_text"] = err["vtk"]
result["bad_stderr"] = err["stderr"]

# ParaView goes on: the bend again
mesh.Input = surface
result["recovered_points"] = servermanager.Fetch(mesh).GetNumberOfPoints()
print("RESULT " + json.dumps(result))
