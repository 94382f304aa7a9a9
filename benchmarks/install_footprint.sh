#!/usr/bin/env bash
# The pip install's footprint (docs/install.md): pinn-mesh from this checkout's committed tree
# into a fresh venv, the CPU torch wheel first (as scripts/setup.sh does), then each extra on
# top; prints the packages (pip and setuptools aside) and the size of site-packages at each
# step. Downloads about 1 GB. Usage: bash benchmarks/install_footprint.sh [WORKDIR]
set -euo pipefail
cd "$(dirname "$0")/.."
WORK=${1:-$(mktemp -d)}
PYTHON=${PYTHON:-python3}
mkdir -p "$WORK/src"
git archive HEAD | tar -x -C "$WORK/src"  # the committed tree: no build output in the checkout
"$PYTHON" -m venv "$WORK/venv"
PIP="$WORK/venv/bin/python -m pip --quiet --disable-pip-version-check"
$PIP install --upgrade pip
SITE=$("$WORK/venv/bin/python" -c 'import site; print(site.getsitepackages()[0])')
measure() {
  local count
  count=$("$WORK/venv/bin/python" -m pip list --format=freeze 2>/dev/null | grep -vcE '^(pip|setuptools)=')
  echo "$1: $count packages, $(du -sm "$SITE" | cut -f1) MB"
}
measure "empty venv"
$PIP install "torch==2.13.0"
$PIP install "$WORK/src"
measure "pip install pinn-mesh"
for extra in cgns paper batch; do
  $PIP install "$WORK/src[$extra]"
  measure "+ pinn-mesh[$extra]"
done
