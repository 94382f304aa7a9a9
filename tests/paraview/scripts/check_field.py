"""pvpython check of the filters' Field input (SPEC 14): a solution read by a ParaView
reader connected to the Field port, its array picked in Field Array, as a new user does.

    scripts/pvenv.sh pvpython tests/paraview/scripts/check_field.py EXAMPLE_DIR FIELD_VTI

Prints one ``RESULT {json}`` line; any failed check raises (exit status 1).
"""

import json
import sys

import paraview.simple as simple
from paraview import servermanager
from paraview.simple import XMLImageDataReader, XMLPolyDataReader

EXAMPLES, FIELD = sys.argv[1], sys.argv[2]
boundary = XMLPolyDataReader(FileName=[f"{EXAMPLES}/wavy.vtp"])
field = XMLImageDataReader(FileName=[FIELD])
field.UpdatePipeline()  # the GUI's Apply on the reader, before the filter is made
mesh = simple.PINNStructuredMesh(Input=boundary, Field=field)
mesh.Method = "elliptic"
mesh.GridSize = [21, 11]
domain = mesh.GetProperty("FieldArray").FindDomain("vtkSMArrayListDomain")
domain.Update(None)
arrays = [domain.GetString(k) for k in range(domain.GetNumberOfStrings())]
mesh.FieldArray = ["POINTS", "p"]
mesh.AdaptStrength = 10.0
mesh.UpdatePipeline()
grid = servermanager.Fetch(mesh)
report = json.loads(grid.GetFieldData().GetAbstractArray("Report").GetValue(0))
assert grid.GetPointData().GetArray("Monitor") is not None
print(
    "RESULT "
    + json.dumps(
        {
            "arrays": arrays,
            "points": grid.GetNumberOfPoints(),
            "array": report["adaptation"]["array"],
            "strength": report["adaptation"]["strength"],
            "error": report["adaptation"]["interpolation_error"],
        }
    )
)
