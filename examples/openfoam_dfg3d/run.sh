#!/usr/bin/env bash
# DFG 3D-1Z (laminar flow round a cylinder in a square channel, Re 20; docs/dfg3d.md): writes
# the channel's blockMeshDict (example_data/blockmesh/make_dictionaries.py's dfg3d, every
# block's counts SIZE times the default's) into a copy of this case, meshes it with
# pinn-mesh (or, with MESHER=blockmesh, with blockMesh), writes the inlet's profile as
# values, runs checkMesh and simpleFoam to convergence and prints the drag and lift
# coefficients and the pressure difference.
#
#   bash examples/openfoam_dfg3d/run.sh [CASE_DIR] [SIZE]   # default out/openfoam_dfg3d 0.5
#
# PINN_MESH overrides the command (default: the checkout's .venv/bin/pinn-mesh), PYTHON
# the interpreter (default: the checkout's .venv/bin/python).
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
CASE=${1:-$ROOT/out/openfoam_dfg3d}
SIZE=${2:-0.5}
PINN_MESH=${PINN_MESH:-$ROOT/.venv/bin/pinn-mesh}
PYTHON=${PYTHON:-$ROOT/.venv/bin/python}
MESHER=${MESHER:-pinn-mesh}
export WM_PROJECT_DIR=${WM_PROJECT_DIR:-/usr/share/openfoam}

rm -rf "$CASE"
mkdir -p "$CASE"
cp -r "$HERE/0" "$HERE/constant" "$HERE/system" "$CASE/"
"$PYTHON" -c "import sys; sys.path.insert(0, '$ROOT/example_data/blockmesh')
from make_dictionaries import dfg3d
open('$CASE/system/blockMeshDict', 'w').write(dfg3d(size=$SIZE))"
if [ "$MESHER" = blockmesh ]; then
    blockMesh -case "$CASE" >"$CASE/log.blockMesh"
else
    "$PINN_MESH" "$CASE/system/blockMeshDict" --format openfoam -o "$CASE" >"$CASE/log.pinn-mesh"
fi

checkMesh -case "$CASE" >"$CASE/log.checkMesh"
grep -E "Failed|Mesh OK" "$CASE/log.checkMesh"
"$PYTHON" "$HERE/dfg3d.py" inlet "$CASE"

simpleFoam -case "$CASE" >"$CASE/log.simpleFoam"
touch "$CASE/case.foam"  # what VTK's and ParaView's OpenFOAM readers open
grep -E "SIMPLE solution converged" "$CASE/log.simpleFoam" || echo "residualControl not met by endTime"
"$PYTHON" "$HERE/dfg3d.py" coefficients "$CASE"
