#!/usr/bin/env bash
# Create .venv in the repository root with everything pinn-mesh needs (idempotent).
# torch first: torch==2.13.0 is the CPU wheel this project's machines hold on disk. Elsewhere
# install PyTorch's CPU build from its index (docs/install.md):
#   pip install torch --index-url https://download.pytorch.org/whl/cpu
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON=${PYTHON:-python3}
stamp=.venv/.installed
# what the install builds from: the package's metadata and the C++ kernels it compiles
sources=(pyproject.toml setup.py pinn_engine/neural/jet/kernels.cpp pinn_engine/bodies/march.cpp)
fresh=1
for source in "${sources[@]}"; do
  [ -f "$stamp" ] && [ "$stamp" -nt "$source" ] || fresh=0
done
if [ "$fresh" = 1 ]; then
  exit 0
fi
"$PYTHON" -c 'import sys; assert sys.version_info >= (3, 10), "pinn-mesh needs Python 3.10+"'
[ -x .venv/bin/python ] || "$PYTHON" -m venv .venv
.venv/bin/python -m pip install --quiet --upgrade pip
.venv/bin/python -m pip install --quiet "torch==2.13.0"
echo "installing pinn-mesh: its C++ jet kernels compile now, not at the first run (a minute or two)"
.venv/bin/python -m pip install --quiet -e ".[test]"
# the package's bytecode now: an editable install compiles none, and where the shell sets
# PYTHONDONTWRITEBYTECODE=1 every run would compile every module again (0.1 s of CPU a run:
# the blockMeshDict pipe as an OpenFOAM case 0.91 -> 0.81 s)
.venv/bin/python -m compileall -q pinn_engine > /dev/null
touch "$stamp"
echo "pinn-mesh installed in .venv (command: .venv/bin/pinn-mesh)"
