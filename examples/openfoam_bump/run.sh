#!/usr/bin/env bash
# Laminar flow (Re 100) over the bump on a channel floor (docs/openfoam.md): meshes a copy of
# this case with pinn-mesh from example_data/bump_channel.vtp, runs checkMesh and simpleFoam
# to convergence (seconds) and prints the fluxes through inlet and outlet and the pressure
# drop. tests/io/test_openfoam_case.py runs this script.
#
#   bash examples/openfoam_bump/run.sh [CASE_DIR]     # default out/openfoam_bump
#
# PINN_MESH overrides the command (default: the checkout's .venv/bin/pinn-mesh).
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
CASE=${1:-$ROOT/out/openfoam_bump}
PINN_MESH=${PINN_MESH:-$ROOT/.venv/bin/pinn-mesh}
# Debian's openfoam package: solvers on PATH, etc/ files here (elsewhere: source OpenFOAM's
# etc/bashrc first, which sets WM_PROJECT_DIR)
export WM_PROJECT_DIR=${WM_PROJECT_DIR:-/usr/share/openfoam}

rm -rf "$CASE"
mkdir -p "$CASE"
cp -r "$HERE/0" "$HERE/constant" "$HERE/system" "$CASE/"
# 60 x 20 cells; into an existing case pinn-mesh writes constant/polyMesh only
"$PINN_MESH" "$ROOT/example_data/bump_channel.vtp" --size 61 21 \
    --patch bottom=wall --patch top=wall --patch left=inlet:inflow --patch right=outlet:outflow \
    --format openfoam --extrude 0.1 -o "$CASE" --quiet

checkMesh -case "$CASE" >"$CASE/log.checkMesh"
grep -E "Failed|Mesh OK" "$CASE/log.checkMesh"

simpleFoam -case "$CASE" >"$CASE/log.simpleFoam"
grep -E "SIMPLE solution converged" "$CASE/log.simpleFoam" || echo "residualControl not met by endTime"

last() { tail -n 1 "$CASE/postProcessing/$1/0/surfaceFieldValue.dat" | awk '{ print $2 }'; }
echo "flux in $(last inletFlux), out $(last outletFlux); pressure drop $(last inletPressure)"
