"""pvpython check of the blockMeshDict reader (run by tests/paraview/test_paraview.py): the
PINN blockMeshDict Reader on the example bend and pipe, opened by name and by the reader.

    scripts/pvenv.sh pvpython tests/paraview/scripts/check_blockmesh.py EXAMPLE_DIR

Prints one ``RESULT {json}`` line; any failed check raises (exit status 1).
"""

import json
import os
import sys

import paraview.simple as simple
from paraview import servermanager

EXAMPLES = sys.argv[1]
result = {}
bend = os.path.join(EXAMPLES, "blockmesh", "bend", "system", "blockMeshDict")
reader = simple.PINNblockMeshDictReader(FileName=bend)
reader.Method = "tfi"
blocks = servermanager.Fetch(reader)
result["bend"] = {
    "blocks": blocks.GetNumberOfBlocks(),
    "cells": sum(blocks.GetBlock(k).GetNumberOfCells() for k in range(blocks.GetNumberOfBlocks())),
    "arrays": sorted(
        blocks.GetBlock(0).GetCellData().GetArrayName(k)
        for k in range(blocks.GetBlock(0).GetCellData().GetNumberOfArrays())
    ),
}
opened = simple.OpenDataFile(bend)
result["opened_with"] = opened.GetXMLName() if opened is not None else None
print("RESULT " + json.dumps(result))
