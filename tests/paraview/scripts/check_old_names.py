"""pvpython check of the filters' old names (PINNMultiBlockMesh, PINNHexahedralMesh): the
names scripts and saved states used before the filters were labelled PINN Structured Mesh
(Multi-Block) and (Hexahedral) (run by tests/paraview/test_paraview.py).

    scripts/pvenv.sh pvpython tests/paraview/scripts/check_old_names.py EXAMPLE_DIR

For each old name: its paraview.simple constructor, the filter class it runs, whether its
definition has the ShowInMenu hint (which puts a filter in the menus and the quick launch)
and the grid it makes beside the new name's. Prints one ``RESULT {json}`` line.
"""

import json
import os
import sys

import paraview.simple as simple
from paraview import servermanager
from paraview.simple import XMLPolyDataReader

EXAMPLES = sys.argv[1]
OLD_TO_NEW = {
    "PINNMultiBlockMesh": "PINNStructuredMeshMultiBlock",
    "PINNHexahedralMesh": "PINNStructuredMeshHexahedral",
}
step = [
    XMLPolyDataReader(FileName=[os.path.join(EXAMPLES, f)]) for f in ("step.vtp", "step_blocks.vtp")
]
bend = XMLPolyDataReader(FileName=[os.path.join(EXAMPLES, "hexa_bend.vtp")])
settings = {
    "PINNMultiBlockMesh": {"Input": step, "Method": "tfi", "CellSize": 0.25},
    "PINNHexahedralMesh": {"Input": bend, "Method": "tfi", "GridSize": [5, 4, 3]},
}
definitions = servermanager.ProxyManager().SMProxyManager.GetProxyDefinitionManager()


def points(dataset):
    """All the nodes of a grid or of a multi-block's grids, in order."""
    if dataset.IsA("vtkMultiBlockDataSet"):
        return [p for k in range(dataset.GetNumberOfBlocks()) for p in points(dataset.GetBlock(k))]
    return [list(dataset.GetPoint(k)) for k in range(dataset.GetNumberOfPoints())]


result = {}
for old, new in OLD_TO_NEW.items():
    hints = [
        definitions.GetProxyDefinition("filters", name).FindNestedElementByName("Hints")
        for name in (old, new)
    ]
    grids = [
        points(servermanager.Fetch(getattr(simple, name)(**settings[old]))) for name in (old, new)
    ]
    result[old] = {
        "label": definitions.GetProxyDefinition("filters", old).GetAttribute("label"),
        "class": definitions.GetProxyDefinition("filters", old).GetAttribute("class"),
        "new_class": definitions.GetProxyDefinition("filters", new).GetAttribute("class"),
        "in_menu": [h.FindNestedElementByName("ShowInMenu") is not None for h in hints],
        "nodes": len(grids[0]),
        "same_grid": grids[0] == grids[1],
    }
print("RESULT " + json.dumps(result))
