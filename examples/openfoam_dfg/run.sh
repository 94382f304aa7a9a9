#!/usr/bin/env bash
# DFG 2D-1 (laminar flow round a cylinder in a channel, Re 20; docs/dfg.md): meshes a copy
# of this case with pinn-mesh from example_data/dfg.vtp and its 12 blocks (or, with
# MESHER=blockmesh, with blockMesh on the same blocks, counts and gradings), writes the
# inlet's parabola as values, runs checkMesh and simpleFoam to convergence and prints the
# drag and lift coefficients and the pressure difference.
#
#   bash examples/openfoam_dfg/run.sh [CASE_DIR] [CELL_SIZE]   # default out/openfoam_dfg 0.01
#
# PINN_MESH overrides the command (default: the checkout's .venv/bin/pinn-mesh), PYTHON
# the interpreter that runs dfg.py (default: the checkout's .venv/bin/python), ADAPT
# another case's solution the grid is adapted to (--adapt ADAPT, e.g. out/a/case.foam:U).
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
CASE=${1:-$ROOT/out/openfoam_dfg}
H=${2:-0.01}
PINN_MESH=${PINN_MESH:-$ROOT/.venv/bin/pinn-mesh}
PYTHON=${PYTHON:-$ROOT/.venv/bin/python}
MESHER=${MESHER:-pinn-mesh}
DEPTH=0.01  # the one cell in z of the 2D case
# Debian's openfoam package: solvers on PATH, etc/ files here (elsewhere: source OpenFOAM's
# etc/bashrc first, which sets WM_PROJECT_DIR)
export WM_PROJECT_DIR=${WM_PROJECT_DIR:-/usr/share/openfoam}

rm -rf "$CASE"
mkdir -p "$CASE"
cp -r "$HERE/0" "$HERE/constant" "$HERE/system" "$CASE/"
# downstream of the box round the cylinder: a third of the cells of a uniform size H, the
# cells at the box's right side H wide and growing to the outlet; the cylinder's first
# cells H / 4 thick and normal to it
DOWN=$("$PYTHON" -c "print(round(1.9 / $H / 3))")
WALL=$("$PYTHON" -c "print($H / 4)")
BLOCKS=("$ROOT/example_data/dfg.vtp" --blocks "$ROOT/example_data/dfg_blocks.vtp"
    --cell-size "$H" --cells 1.2,0.41="$DOWN" --spacing 0.3,0.2="$H"
    --patch boundary=walls:wall --patch hole1=cylinder:wall
    --patch 0,0.05=inlet:inflow --patch 0,0.2=inlet --patch 0,0.355=inlet
    --patch 2.2,0.05=outlet:outflow --patch 2.2,0.2=outlet --patch 2.2,0.355=outlet
    --spacing cylinder="$WALL" --orthogonal cylinder --quiet)
if [ -n "${ADAPT:-}" ]; then
    BLOCKS+=(--adapt "$ADAPT")
fi
if [ "$MESHER" = blockmesh ]; then
    # the same blocks, counts and gradings: pinn-mesh's grid of them gives the counts
    "$PINN_MESH" "${BLOCKS[@]}" -o "$CASE/pinn.vtm"
    "$PYTHON" "$HERE/dfg.py" blockmesh "$CASE" "$CASE/pinn.vtm" "$DEPTH"
    blockMesh -case "$CASE" >"$CASE/log.blockMesh"
else
    "$PINN_MESH" "${BLOCKS[@]}" --format openfoam --extrude "$DEPTH" -o "$CASE"
fi

checkMesh -case "$CASE" >"$CASE/log.checkMesh"
grep -E "Failed|Mesh OK" "$CASE/log.checkMesh"
"$PYTHON" "$HERE/dfg.py" inlet "$CASE"

simpleFoam -case "$CASE" >"$CASE/log.simpleFoam"
touch "$CASE/case.foam"  # what VTK's and ParaView's OpenFOAM readers open
grep -E "SIMPLE solution converged" "$CASE/log.simpleFoam" || echo "residualControl not met by endTime"
"$PYTHON" "$HERE/dfg.py" coefficients "$CASE"
