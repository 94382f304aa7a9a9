"""pvpython check of the PINN Structured Mesh (Multi-Block) filter (run by
tests/paraview/test_paraview.py).

    scripts/pvenv.sh pvpython tests/paraview/scripts/check_multiblock.py EXAMPLE_DIR

The backward-facing step of example_data (four blocks), its boundary and block edges selected
together (both on Input, as the GUI connects them) and on the two inputs; then a block edge
that ends nowhere; then the cylinder in a channel, its patch named, spaced and orthogonal
from the panel's fields; then the L-shape with an auxiliary line inside a block; then the
L-shape alone under Blocking Automatic, its proposed edges on the second output. Prints one
``RESULT {json}`` line; any failed check raises (exit status 1).
"""

import json
import os
import sys
import tempfile

import paraview.simple as simple
from paraview import servermanager
from paraview.modules.vtkRemotingServerManager import vtkSMProxyManager
from paraview.simple import XMLPolyDataReader
from pvcommon import captured_errors
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet

EXAMPLES = sys.argv[1]
CELL_SIZE = 0.1  # docs/multiblock.md's step: 1748 cells
result = {}


def blocks_of(dataset):
    """Per block: its name, class, node array (nj, ni, 3) as lists, cell arrays, folds."""
    out = []
    for k in range(dataset.GetNumberOfBlocks()):
        grid = dataset.GetBlock(k)
        ext = grid.GetExtent()
        pts = vtk_to_numpy(grid.GetPoints().GetData()).reshape(ext[3] + 1, ext[1] + 1, 3)
        cd = grid.GetCellData()
        out.append(
            {
                "name": dataset.GetMetaData(k).Get(vtkCompositeDataSet.NAME()),
                "class": grid.GetClassName(),
                "points": pts.tolist(),
                "cell_arrays": [cd.GetArrayName(i) for i in range(cd.GetNumberOfArrays())],
                "folded": int(vtk_to_numpy(cd.GetArray("Folded")).sum()),
            }
        )
    return out


proto = servermanager.ProxyManager().GetPrototypeProxy("filters", "PINNStructuredMeshMultiBlock")
result["label"] = proto.GetXMLLabel()
result["menu_category"] = (
    proto.GetHints().FindNestedElementByName("ShowInMenu").GetAttribute("category")
)
result["help"] = [proto.GetDocumentation().GetShortHelp(), proto.GetDocumentation().GetLongHelp()]

boundary = XMLPolyDataReader(FileName=[os.path.join(EXAMPLES, "step.vtp")])
edges = XMLPolyDataReader(FileName=[os.path.join(EXAMPLES, "step_blocks.vtp")])

# 1. boundary and block edges selected together: both on Input
mesh = simple.PINNStructuredMeshMultiBlock(Input=[boundary, edges], CellSize=CELL_SIZE)
progress = []
mesh.GetClientSideObject().AddObserver(
    "ProgressEvent", lambda obj, event: progress.append(obj.GetProgress())
)
with captured_errors() as quiet:
    dataset = servermanager.Fetch(mesh)
result["class"] = dataset.GetClassName()
result["properties"] = mesh.ListProperties()
result["methods"] = mesh.GetProperty("Method").Available
result["interfaces"] = mesh.GetProperty("Interfaces").Available
result["together"] = blocks_of(dataset)
result["together_messages"] = quiet["vtk"]
result["progress"] = [min(progress), max(progress)] if progress else []

# File > Save Data: the solver formats for the blocks (SU2 and OpenFOAM written here)
factory = vtkSMProxyManager.GetProxyManager().GetWriterFactory()
factory.UpdateAvailableWriters()
result["file_types"] = sorted(
    t for t in factory.GetSupportedFileTypes(mesh.SMProxy, 0).split(";;") if "PINN" in t
)
saved = tempfile.mkdtemp()
with captured_errors() as wrote:
    simple.SaveData(os.path.join(saved, "blocks.su2"), proxy=mesh)
    simple.SaveData(os.path.join(saved, "case.foam"), proxy=mesh)
result["su2"] = open(os.path.join(saved, "blocks.su2")).read()
result["foam_boundary"] = open(
    os.path.join(saved, "case", "constant", "polyMesh", "boundary")
).read()
result["save_messages"] = wrote["vtk"]

# 2. the block edges on their own input, Block Edges; tfi, interfaces fixed
apart = simple.PINNStructuredMeshMultiBlock(
    Input=boundary, BlockEdges=[edges], CellSize=CELL_SIZE, Method="tfi", Interfaces="fixed"
)
result["apart_tfi"] = blocks_of(servermanager.Fetch(apart))

# 3. a block edge that ends nowhere: empty output, one line in the panel's words
stray = simple.Line(Point1=[1.0, 0.6, 0.0], Point2=[1.5, 0.7, 0.0])
bad = simple.PINNStructuredMeshMultiBlock(
    Input=[boundary, edges], BlockEdges=[stray], CellSize=CELL_SIZE
)
with captured_errors() as err:
    bad_data = servermanager.Fetch(bad)
result["bad_blocks"] = bad_data.GetNumberOfBlocks()
result["bad_vtk_text"] = err["vtk"]
result["bad_stderr"] = err["stderr"]

# 4. ParaView goes on: drop the stray edge and update again
bad.BlockEdges = []
result["recovered_blocks"] = servermanager.Fetch(bad).GetNumberOfBlocks()

# 5. the cylinder's patch named, spaced and orthogonal from the panel's fields (elliptic)
cylinder = XMLPolyDataReader(FileName=[os.path.join(EXAMPLES, "cylinder_channel.vtp")])
cut = XMLPolyDataReader(FileName=[os.path.join(EXAMPLES, "cylinder_channel_blocks.vtp")])
walled = simple.PINNStructuredMeshMultiBlock(
    Input=[cylinder, cut],
    CellSize=CELL_SIZE,
    Method="elliptic",
    PatchNames="0.5,0=cylinder:wall 0,0.5=cylinder -0.5,0=cylinder 0,-0.5=cylinder",
    FirstEdgeSpacing="cylinder=0.005",
    OrthogonalPatches="cylinder",
)
walled_data = servermanager.Fetch(walled)
fields = [walled_data.GetBlock(k).GetFieldData() for k in range(walled_data.GetNumberOfBlocks())]
report = json.loads(fields[0].GetAbstractArray("Report").GetValue(0))
result["walls"] = report["multiblock"]["walls"]
names = [f.GetAbstractArray("PieceNames") for f in fields]
result["piece_names"] = sorted({a.GetValue(k) for a in names for k in range(a.GetNumberOfValues())})
# 6. an auxiliary line inside the L's bottom block on Auxiliary Lines (elliptic: reported)
lshape = XMLPolyDataReader(FileName=[os.path.join(EXAMPLES, "lshape.vtp")])
lshape_edges = XMLPolyDataReader(FileName=[os.path.join(EXAMPLES, "lshape_blocks.vtp")])
line = XMLPolyDataReader(FileName=[os.path.join(EXAMPLES, "lshape_aux.vtp")])
lined = simple.PINNStructuredMeshMultiBlock(
    Input=[lshape, lshape_edges], AuxiliaryLines=[line], CellSize=CELL_SIZE, Method="elliptic"
)
lined_data = servermanager.Fetch(lined)
first = lined_data.GetBlock(0).GetFieldData().GetAbstractArray("Report").GetValue(0)
result["aux_line_distance"] = json.loads(first)["multiblock"]["aux_line_distance"]
# 7. the L-shape alone under Blocking Automatic: its blocks, and its edges on output 1
auto = simple.PINNStructuredMeshMultiBlock(Input=[lshape], Blocking="Automatic", Method="elliptic")
result["blockings"] = auto.GetProperty("Blocking").Available
result["auto_blocks"] = servermanager.Fetch(auto).GetNumberOfBlocks()
proposed = servermanager.Fetch(auto, idx=1)
result["auto_edges"] = proposed.GetNumberOfLines()
print("RESULT " + json.dumps(result))
