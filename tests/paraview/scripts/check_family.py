"""pvpython check of the filter's Model property (run by tests/paraview/test_paraview.py): a
family model fitted here on four channels meshes a fifth through the filter.

    scripts/pvenv.sh pvpython tests/paraview/scripts/check_family.py WORK_DIR

Prints one ``RESULT {json}`` line; any failed check raises (exit status 1).
"""

import json
import sys
from pathlib import Path

import numpy as np
import paraview.simple as simple
from paraview import servermanager

from pinn_engine import job
from pinn_engine.geometry.boundary import Boundary
from pinn_engine.settings import OBJECTIVES, make_settings

WORK = Path(sys.argv[1])
SIZE = (21, 11)


def channel(height):
    x = np.linspace(0.0, 3.0, 61)
    bottom = np.column_stack([x, height * np.exp(-(((x - 1.5) / 0.4) ** 2))])
    top = np.column_stack([x, np.ones_like(x)])[::-1]
    return np.vstack([bottom[:-1], np.linspace(bottom[-1], top[0], 11)[:-1], top[:-1],
                      np.linspace(top[-1], bottom[0], 11)[:-1]])  # fmt: skip


settings = make_settings("pinn", size=SIZE, lattice=SIZE, objective="winslow")
members, targets = [], []
for h in (0.1, 0.15, 0.25, 0.3):
    g = job.Geometry(boundary=Boundary.from_points(channel(h), source="channel"))
    member = job.family_member(settings, g)
    members.append(member)
    targets.append(job.member_target(member, job.run(settings, g)))
model = WORK / "channels.pt"
job.fit_family_model(members, targets, epochs=10).save(model)
ring = channel(0.2)
source = simple.PolyLineSource(
    Points=np.column_stack([ring, np.zeros(len(ring))]).ravel().tolist(), Closed=1
)
mesh = simple.PINNStructuredMesh(Input=source)
mesh.GridSize = list(SIZE)
mesh.Model = str(model)
mesh.Objective = OBJECTIVES.index("winslow")  # the family's: a family of Winslow grids
mesh.UpdatePipeline()
grid = servermanager.Fetch(mesh)
fd = grid.GetFieldData()
result = {
    "points": grid.GetNumberOfPoints(),
    "result": fd.GetAbstractArray("NetworkResult").GetValue(0),
    "model": fd.GetAbstractArray("FamilyModel").GetValue(0),
    "expected_model": str(model),
}
print("RESULT " + json.dumps(result))
