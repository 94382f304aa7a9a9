#!/usr/bin/env bash
# NACA 0012 at 4 degrees, Re 6e6, Spalart-Allmaras (docs/openfoam.md): meshes a copy of this
# case with pinn-mesh (the mesh files are not edited afterwards), runs checkMesh and
# simpleFoam (one process) and prints Cl and Cd from the forceCoeffs output.
#
#   bash examples/openfoam_naca0012/run.sh [CASE_DIR]     # default out/openfoam_naca0012
#
# PINN_MESH overrides the command (default: the checkout's .venv/bin/pinn-mesh).
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
CASE=${1:-$ROOT/out/openfoam_naca0012}
PINN_MESH=${PINN_MESH:-$ROOT/.venv/bin/pinn-mesh}
# Debian's openfoam package: solvers on PATH, etc/ files here (elsewhere: source OpenFOAM's
# etc/bashrc first, which sets WM_PROJECT_DIR)
export WM_PROJECT_DIR=${WM_PROJECT_DIR:-/usr/share/openfoam}

rm -rf "$CASE"
mkdir -p "$CASE"
cp -r "$HERE/0" "$HERE/constant" "$HERE/system" "$CASE/"
# into an existing case pinn-mesh writes constant/polyMesh only: 0/ and system/ stay ours
"$PINN_MESH" --naca 0012 --topology c --size 320 90 --spacing bottom=1e-5 --farfield 15 \
    --format openfoam --extrude 0.1 -o "$CASE" --quiet

checkMesh -case "$CASE" >"$CASE/log.checkMesh"
echo "checkMesh (log.checkMesh):"
grep -E "aspect ratio|non-orthogonality Max|Failed|Mesh OK" "$CASE/log.checkMesh" | sed 's/^ */  /'

start=$SECONDS
simpleFoam -case "$CASE" >"$CASE/log.simpleFoam"
echo "simpleFoam (log.simpleFoam): $((SECONDS - start)) s, $(grep -c '^Time =' "$CASE/log.simpleFoam") iterations"
grep -E "SIMPLE solution converged" "$CASE/log.simpleFoam" || echo "  residualControl not met by endTime"

# Cl and Cd at the last iteration, with how far each moved over the last AVG iterations
AVG=200
awk -v n=$AVG '/^# Time/ { for (k = 2; k <= NF; k++) col[$k] = k - 1; next }
     !/^#/ { row[++m] = $0 }
     END {
         for (r = m - n + 1; r <= m; r++) {
             split(row[r], v); l = v[col["Cl"]]; d = v[col["Cd"]]
             if (r == m - n + 1 || l < llo) llo = l; if (r == m - n + 1 || l > lhi) lhi = l
             if (r == m - n + 1 || d < dlo) dlo = d; if (r == m - n + 1 || d > dhi) dhi = d
         }
         printf "Cl = %.4f  Cd = %.5f  (iteration %d; over iterations %d-%d Cl moved %.1e, Cd %.1e)\n", \
             l, d, m, m - n + 1, m, lhi - llo, dhi - dlo
     }' "$CASE/postProcessing/forceCoeffs/0/coefficient.dat"
