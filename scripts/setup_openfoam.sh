#!/usr/bin/env bash
# Install OpenFOAM's checkMesh and simpleFoam (Debian's `openfoam` package) for the OpenFOAM
# export tests and tests/io/test_openfoam_case.py.
# Idempotent: does nothing when checkMesh is already on PATH. The test runs
# `checkMesh -case DIR` with WM_PROJECT_DIR=/usr/share/openfoam (Debian's layout).
set -euo pipefail
if command -v checkMesh >/dev/null 2>&1; then
    echo "[setup_openfoam] checkMesh already installed: $(command -v checkMesh)"
    exit 0
fi
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "[setup_openfoam] installing openfoam from apt ..."
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq openfoam >/dev/null
command -v checkMesh >/dev/null || { echo "[setup_openfoam] checkMesh still missing" >&2; exit 1; }
