#!/usr/bin/env bash
# Laminar flow over the backward-facing step of Armaly et al. (Re 389, expansion ratio 1.94;
# docs/openfoam.md): meshes the domain of example_data/armaly_step.csv with pinn-mesh's
# automatic blocking and a wall spacing (or, with MESHER=blockmesh, with blockMesh on three
# blocks of the same counts and first cells), N cells across the step, writes the inlet's
# parabola as values, runs checkMesh and simpleFoam to convergence (the step case's
# dictionaries, examples/openfoam_step) and prints the reattachment length behind the step.
#
#   bash examples/openfoam_armaly/run.sh [CASE_DIR] [N]   # default out/openfoam_armaly 20
#
# PINN_MESH overrides the command (default: the checkout's .venv/bin/pinn-mesh), PYTHON the
# interpreter that runs armaly.py.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
CASE=${1:-$ROOT/out/openfoam_armaly}
N=${2:-20}
PINN_MESH=${PINN_MESH:-$ROOT/.venv/bin/pinn-mesh}
PYTHON=${PYTHON:-$ROOT/.venv/bin/python}
MESHER=${MESHER:-pinn-mesh}
DEPTH=0.1  # the one cell in z of the 2D case (mm)
export WM_PROJECT_DIR=${WM_PROJECT_DIR:-/usr/share/openfoam}

rm -rf "$CASE"
mkdir -p "$CASE"
cp -r "$ROOT/examples/openfoam_step/"{0,constant,system} "$CASE/"
"$PYTHON" "$HERE/armaly.py" viscosity "$CASE"
if [ "$MESHER" = blockmesh ]; then
    "$PYTHON" "$HERE/armaly.py" blockmesh "$CASE" "$N" "$DEPTH"
    blockMesh -case "$CASE" >"$CASE/log.blockMesh"
else
    mapfile -t ITEMS < <("$PYTHON" "$HERE/armaly.py" args "$N")
    "$PINN_MESH" "$ROOT/example_data/armaly_step.csv" "${ITEMS[@]}" --quiet \
        --format openfoam --extrude "$DEPTH" -o "$CASE"
fi

checkMesh -case "$CASE" >"$CASE/log.checkMesh"
grep -E "Failed|Mesh OK" "$CASE/log.checkMesh"
"$PYTHON" "$HERE/armaly.py" inlet "$CASE"

simpleFoam -case "$CASE" >"$CASE/log.simpleFoam"
touch "$CASE/case.foam"  # what VTK's and ParaView's OpenFOAM readers open
grep -E "SIMPLE solution converged" "$CASE/log.simpleFoam" || echo "residualControl not met by endTime"
"$PYTHON" "$HERE/armaly.py" reattachment "$CASE"
