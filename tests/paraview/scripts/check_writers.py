"""pvpython check of the solver-format writers (run by tests/paraview/test_paraview.py).

    scripts/pvenv.sh pvpython tests/paraview/scripts/check_writers.py EXAMPLE_DIR OUT_DIR

Meshes fig2 (tfi, 13 x 7, Patch Names "bottom=wall top=wall left=inlet"), lists the file
types File > Save Data offers for the filter's output, writes every PINN Mesh format (and a
.vts with ParaView's own writer) into OUT_DIR and a CGNS file with no helper Python. Prints
one ``RESULT {json}`` line; the test reads the files back with independent readers.
"""

import json
import os
import sys

import paraview.simple as simple
from paraview import servermanager
from paraview.modules.vtkRemotingServerManager import vtkSMPropertyHelper, vtkSMProxyManager
from pvcommon import captured_errors

EXAMPLES, OUT = sys.argv[1], sys.argv[2]


boundary = simple.XMLPolyDataReader(FileName=[os.path.join(EXAMPLES, "fig2.vtp")])
mesh = simple.PINNStructuredMesh(
    Input=boundary, Method="tfi", GridSize=[13, 7], PatchNames="bottom=wall top=wall left=inlet"
)
grid = servermanager.Fetch(mesh)
names = grid.GetFieldData().GetAbstractArray("PatchNames")
result = {
    "patch_names": [names.GetValue(k) for k in range(names.GetNumberOfValues())],
    "point_arrays": [
        grid.GetPointData().GetArrayName(k) for k in range(grid.GetPointData().GetNumberOfArrays())
    ],
}

factory = vtkSMProxyManager.GetProxyManager().GetWriterFactory()
factory.UpdateAvailableWriters()
result["file_types"] = [
    t
    for t in factory.GetSupportedFileTypes(mesh.SMProxy, 0).split(";;")
    if t.startswith("PINN Mesh")
]

simple.SaveData(os.path.join(OUT, "grid.vts"), proxy=mesh)  # ParaView's own writer
jobs = [
    ("PINNMeshPLOT3DWriter", "grid.xyz", {}),
    ("PINNMeshPLOT3DWriter", "grid3.xyz", {"ExtrudeThickness": 0.25}),
    ("PINNMeshCGNSWriter", "grid.cgns", {}),
    ("PINNMeshCGNSWriter", "grid3.cgns", {"ExtrudeThickness": 0.25}),
    ("PINNMeshSU2Writer", "grid.su2", {}),
    ("PINNMeshGmshWriter", "grid.msh", {}),
    ("PINNMeshGmshWriter", "grid3.msh", {"ExtrudeThickness": 0.25}),
    ("PINNMeshOpenFOAMWriter", "case.foam", {"ExtrudeThickness": 0.25}),
]
result["errors"] = {}
for proxy_name, file_name, props in jobs:
    writer = getattr(servermanager.writers, proxy_name)(
        Input=mesh, FileName=os.path.join(OUT, file_name), **props
    )
    with captured_errors() as err:
        writer.UpdatePipeline()
    result["errors"][file_name] = err["vtk"].strip()
    del writer

# File > Save Data by the file name alone, as ParaView 5.11's dialog does: ours for .cgns
writer = factory.CreateWriter(os.path.join(OUT, "unwritten.cgns"), mesh.SMProxy, 0)
# what Save Data's writer dialog sees before the information is read: a value, so that
# Extrude Thickness (shown where IsThreeD is 0) makes the dialog appear for a 2D grid
before = writer.GetProperty("IsThreeD")
result["is_three_d_unread"] = [before.GetElement(k) for k in range(before.GetNumberOfElements())]
writer.UpdatePropertyInformation()
result["cgns_writer"] = writer.GetXMLName()
result["is_three_d"] = vtkSMPropertyHelper(writer, "IsThreeD").GetAsInt()
del writer
with captured_errors() as err:
    simple.SaveData(os.path.join(OUT, "saved.cgns"), proxy=mesh)
result["errors"]["saved.cgns"] = err["vtk"].strip()

os.environ["PINN_MESH_PYTHON"] = "/nonexistent/python"  # no helper: CGNS cannot be written
writer = servermanager.writers.PINNMeshCGNSWriter(
    Input=mesh, FileName=os.path.join(OUT, "none.cgns")
)
with captured_errors() as err:
    writer.UpdatePipeline()
result["no_helper"] = {"vtk": err["vtk"], "traceback": "Traceback" in err["stderr"]}
result["files"] = sorted(os.listdir(OUT))
print("RESULT " + json.dumps(result))
