"""pvpython check of the filters' Field input (SPEC 14): a solution read by the ParaView
reader a user would open it with (an OpenFOAM case's ``.foam`` file, or an XML VTK file),
connected to the Field port, its array picked in Field Array, as a new user does.

    scripts/pvenv.sh pvpython tests/paraview/scripts/check_field.py BOUNDARY FIELD ARRAY NI NJ

Prints one ``RESULT {json}`` line; any failed check raises (exit status 1).
"""

import json
import sys

import paraview.simple as simple
from paraview import servermanager
from paraview.simple import OpenDataFile, OpenFOAMReader, XMLPolyDataReader

BOUNDARY, FIELD, ARRAY = sys.argv[1:4]
SIZE = [int(n) for n in sys.argv[4:6]]
boundary = XMLPolyDataReader(FileName=[BOUNDARY])
# a .foam file opens in the OpenFOAM reader at its defaults (the zero time skipped, the
# cell arrays also given as point arrays), as the GUI's File > Open does
field = OpenFOAMReader(FileName=FIELD) if FIELD.endswith(".foam") else OpenDataFile(FIELD)
times = list(getattr(field, "TimestepValues", None) or [])
field.UpdatePipeline(max(times) if times else 0.0)  # the GUI's Apply at the last time
mesh = simple.PINNStructuredMesh(Input=boundary, Field=field)
mesh.Method = "elliptic"
mesh.GridSize = SIZE
domain = mesh.GetProperty("FieldArray").FindDomain("vtkSMArrayListDomain")
domain.Update(None)
arrays = [domain.GetString(k) for k in range(domain.GetNumberOfStrings())]
mesh.FieldArray = ["POINTS", ARRAY]
mesh.AdaptStrength = 10.0
mesh.UpdatePipeline(max(times) if times else 0.0)
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
            "worst": report["adaptation"]["worst_max_angle"],
            "folded": report["adaptation"]["folded_cells"],
        }
    )
)
