"""pvpython check of the airfoil route (run by tests/paraview/test_paraview.py): the Airfoil (.dat)
reader, the Airfoil source and the filter's Topology setting.

    scripts/pvenv.sh pvpython tests/paraview/scripts/check_airfoil.py EXAMPLE_DIR

Prints one ``RESULT {json}`` line; any failed check raises (exit status 1).
"""

import json
import os
import sys

import paraview.simple as simple
from paraview import servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy

EXAMPLES = sys.argv[1]
result = {}


def summary(grid):
    fd = grid.GetFieldData()
    pts = vtk_to_numpy(grid.GetPoints().GetData())
    ext = grid.GetExtent()
    ni, nj = ext[1] + 1, ext[3] + 1
    pts = pts.reshape(nj, ni, 3)
    return {
        "extent": list(ext),
        "topology": fd.GetAbstractArray("Topology").GetValue(0)
        if fd.GetAbstractArray("Topology")
        else None,
        "patches": [fd.GetAbstractArray("PatchNames").GetValue(k) for k in range(4)],
        "seam_gap": float(abs(pts[:, 0] - pts[:, -1]).max()),
        "folded": int(vtk_to_numpy(grid.GetCellData().GetArray("Folded")).sum()),
        "far_radius": float(((pts[-1, :, 0] - 0.5) ** 2 + pts[-1, :, 1] ** 2).max() ** 0.5),
    }


# 1. a .dat file through the reader, O-grid by elliptic
reader = simple.AirfoilReader(FileName=os.path.join(EXAMPLES, "naca0012.dat"))
body = servermanager.Fetch(reader)
result["reader_points"] = body.GetNumberOfPoints()
mesh = simple.PINNStructuredMesh(
    Input=reader, Method=3, Topology=1, GridSize=[81, 25], FarFieldRadius=10.0, WallSpacing=1e-3
)
result["o_grid"] = summary(servermanager.Fetch(mesh))

# 2. the Airfoil source (NACA 4412, sharp), C-grid by tfi
source = simple.Airfoil(NACA="4412")
mesh_c = simple.PINNStructuredMesh(Input=source, Method=2, Topology=2, GridSize=[121, 25])
result["c_grid"] = summary(servermanager.Fetch(mesh_c))

# 3. OpenDataFile picks the reader by the .dat extension
opened = simple.OpenDataFile(os.path.join(EXAMPLES, "naca4412.dat"))
result["opened_with"] = opened.GetXMLName()
print("RESULT " + json.dumps(result))
