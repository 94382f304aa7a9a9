"""pvpython check of the PINN Structured Mesh (Hexahedral) filter (run by
tests/paraview/test_paraview.py).

    scripts/pvenv.sh pvpython tests/paraview/scripts/check_hexa.py EXAMPLE_DIR

The 90-degree bend of example_data by tfi, elliptic and pinn (the default), by tfi with
Patch Names and First Edge Spacing, with Orthogonal Patches (refused for tfi), then a sphere
(no FaceId) and the bend again on the same filter, the bend's STL with faces named by FaceId,
a 2D curve (refused, pointing to the 2D filters) and the writer Save Data picks for a .cgns
file of the grid. Prints one ``RESULT {json}`` line; any failed check raises (exit status 1).
"""

import json
import os
import sys

import paraview.simple as simple
from paraview import servermanager
from paraview.modules.vtkRemotingServerManager import vtkSMPropertyHelper, vtkSMProxyManager
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


proto = servermanager.ProxyManager().GetPrototypeProxy("filters", "PINNStructuredMeshHexahedral")
result["label"] = proto.GetXMLLabel()
result["menu_category"] = (
    proto.GetHints().FindNestedElementByName("ShowInMenu").GetAttribute("category")
)
shown = proto.GetHints().FindNestedElementByName("RepresentationType")
result["representation"] = shown.GetAttribute("type")
result["help"] = [proto.GetDocumentation().GetShortHelp(), proto.GetDocumentation().GetLongHelp()]

surface = XMLPolyDataReader(FileName=[os.path.join(EXAMPLES, "hexa_bend.vtp")])
mesh = simple.PINNStructuredMeshHexahedral(Input=surface, GridSize=SIZE, Method="tfi")
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
mesh.Method = "pinn"  # the default: the start kept untrained (no spacing or orthogonal patch)
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

# the STL: faces found at Face Angle, named by the summary line's numbers
mesh.Input = simple.STLReader(FileNames=[os.path.join(EXAMPLES, "hexa_bend.stl")])
mesh.PatchNames = "face0=inner:wall face3=outlet"
with captured_errors() as told:
    result["stl"] = grid_of(servermanager.Fetch(mesh))
result["stl_told"] = told["vtk"]

# a 2D curve: pointed to the filters that mesh it
mesh.Input = XMLPolyDataReader(FileName=[os.path.join(EXAMPLES, "fig2.vtp")])
with captured_errors() as err:
    result["curve_points"] = servermanager.Fetch(mesh).GetNumberOfPoints()
result["curve_text"] = err["vtk"]

# File > Save Data as .cgns: the writer ParaView 5.11 picks by the extension, and whether its
# panel hides Extrude Thickness (a hexahedral grid is not extruded)
mesh.Input = surface
servermanager.Fetch(mesh)
factory = vtkSMProxyManager.GetProxyManager().GetWriterFactory()
factory.UpdateAvailableWriters()
writer = factory.CreateWriter(os.path.join(EXAMPLES, "unwritten.cgns"), mesh.SMProxy, 0)
writer.UpdatePropertyInformation()
result["cgns_writer"] = writer.GetXMLName()
result["is_three_d"] = vtkSMPropertyHelper(writer, "IsThreeD").GetAsInt()
print("RESULT " + json.dumps(result))
