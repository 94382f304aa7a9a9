#!/usr/bin/env bash
# Laminar flow over a backward-facing step (Re 100, expansion ratio 2; docs/adaptation.md):
# meshes a copy of this case with pinn-mesh from example_data/step.vtp and its blocks at one
# cell size, writes the inlet's parabola as values, runs checkMesh and simpleFoam to
# convergence and prints the reattachment length behind the step.
#
#   bash examples/openfoam_step/run.sh [CASE_DIR] [CELL_SIZE]   # default out/openfoam_step 0.1
#
# PINN_MESH overrides the command (default: the checkout's .venv/bin/pinn-mesh), PYTHON the
# interpreter that runs step.py, ADAPT another case's solution the grid is adapted to
# (--adapt ADAPT, e.g. out/a/case.foam:U), ADAPT_STRENGTH its --adapt-strength.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
CASE=${1:-$ROOT/out/openfoam_step}
H=${2:-0.1}
PINN_MESH=${PINN_MESH:-$ROOT/.venv/bin/pinn-mesh}
PYTHON=${PYTHON:-$ROOT/.venv/bin/python}
DEPTH=0.1  # the one cell in z of the 2D case
export WM_PROJECT_DIR=${WM_PROJECT_DIR:-/usr/share/openfoam}

rm -rf "$CASE"
mkdir -p "$CASE"
cp -r "$HERE/0" "$HERE/constant" "$HERE/system" "$CASE/"
ARGS=("$ROOT/example_data/step.vtp" --blocks "$ROOT/example_data/step_blocks.vtp"
    --cell-size "$H" --patch boundary=walls:wall --patch -2,1.5=inlet:inflow
    --patch 6,0.5=outlet:outflow --patch 6,1.5=outlet --quiet)
if [ -n "${ADAPT:-}" ]; then
    ARGS+=(--adapt "$ADAPT" --adapt-strength "${ADAPT_STRENGTH:-20}")
fi
"$PINN_MESH" "${ARGS[@]}" --format openfoam --extrude "$DEPTH" -o "$CASE"

checkMesh -case "$CASE" >"$CASE/log.checkMesh"
grep -E "Failed|Mesh OK" "$CASE/log.checkMesh"
"$PYTHON" "$HERE/step.py" inlet "$CASE"

simpleFoam -case "$CASE" >"$CASE/log.simpleFoam"
touch "$CASE/case.foam"  # what VTK's and ParaView's OpenFOAM readers open
grep -E "SIMPLE solution converged" "$CASE/log.simpleFoam" || echo "residualControl not met by endTime"
"$PYTHON" "$HERE/step.py" reattachment "$CASE"
