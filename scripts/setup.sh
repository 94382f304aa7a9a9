#!/usr/bin/env bash
# Create .venv in the repository root with everything pinn-mesh needs (idempotent).
# torch is pinned to the CPU wheel first: an unpinned torch would pull GBs of CUDA packages.
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON=${PYTHON:-python3}
stamp=.venv/.installed
if [ -f "$stamp" ] && [ "$stamp" -nt pyproject.toml ]; then
  exit 0
fi
"$PYTHON" -c 'import sys; assert sys.version_info >= (3, 10), "pinn-mesh needs Python 3.10+"'
[ -x .venv/bin/python ] || "$PYTHON" -m venv .venv
.venv/bin/python -m pip install --quiet --upgrade pip
.venv/bin/python -m pip install --quiet "torch==2.13.0"
.venv/bin/python -m pip install --quiet -e ".[test]"
touch "$stamp"
echo "pinn-mesh installed in .venv (command: .venv/bin/pinn-mesh)"
