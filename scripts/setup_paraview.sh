#!/usr/bin/env bash
# Install a real ParaView (Debian's 5.11) plus a Python venv for pvpython.
#
# Idempotent: re-running skips what is already there.
#   * apt: paraview, python3-paraview, xvfb (+ x11-apps/imagemagick/xdotool for GUI
#     screenshots) -- only when one of pvpython, xvfb-run, import, xdotool is missing.
#   * .venv-pv in the repo root, built from /usr/bin/python3 (Debian's 3.11,
#     the interpreter pvpython embeds), with torch==2.13.0 (CPU wheel),
#     scikit-learn, shapely 2.0.x (multi-block faces) and numpy<2.4.  NEVER install pip vtk/pyvista into it:
#     mixing them with ParaView's own VTK 9.2 crashes pvpython (SIGSEGV).
#
# Usage: bash scripts/setup_paraview.sh     (as root, non-interactive)
# Then:  scripts/pvenv.sh pvpython my_script.py
set -euo pipefail

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="${PINN_PV_VENV:-$REPO/.venv-pv}"
SYS_PY=/usr/bin/python3

export DEBIAN_FRONTEND=noninteractive
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

if ! command -v pvpython >/dev/null 2>&1 || ! command -v xvfb-run >/dev/null 2>&1 \
        || ! command -v import >/dev/null 2>&1 || ! command -v xdotool >/dev/null 2>&1; then
    echo "[setup_paraview] installing ParaView from apt ..."
    $SUDO apt-get update -qq
    $SUDO apt-get install -y -qq \
        paraview python3-paraview xvfb xauth x11-apps imagemagick xdotool python3-venv >/dev/null
else
    echo "[setup_paraview] pvpython already installed: $(command -v pvpython)"
fi

# pvpython embeds Debian's system Python; the venv must use the same version
# (NOT the pyenv/other python3 that may come first on PATH).
PV_PYVER="$(env -u PYTHONPATH -u PYTHONHOME pvpython -c 'import sys; print("%d.%d" % sys.version_info[:2])' 2>/dev/null | tail -1)"
SYS_PYVER="$($SYS_PY -c 'import sys; print("%d.%d" % sys.version_info[:2])')"
echo "[setup_paraview] $(pvpython --version 2>/dev/null | head -1); embedded python $PV_PYVER; $SYS_PY is $SYS_PYVER"
if [ "$PV_PYVER" != "$SYS_PYVER" ]; then
    echo "[setup_paraview] ERROR: pvpython's Python ($PV_PYVER) != $SYS_PY ($SYS_PYVER)" >&2
    exit 1
fi

if [ ! -x "$VENV/bin/python" ] || ! "$VENV/bin/python" -c "import torch, sklearn, numpy, shapely, pyamg; assert shapely.geos_version[:2] == (3, 11)" >/dev/null 2>&1; then
    echo "[setup_paraview] creating $VENV ..."
    $SYS_PY -m venv "$VENV"
    # torch==2.13.0 exactly: the CPU wheel is available locally; any other
    # spec may resolve to the multi-GB CUDA build. shapely 2.0.x: its wheel bundles GEOS
    # 3.11 like Debian 12's, which ParaView's VTK (GDAL) loads first; shapely >= 2.1
    # bundles GEOS 3.13+, whose C API then binds to those 3.11 C++ symbols and aborts.
    # pyamg: the 3D Winslow solve's preconditioner (six-faced domains).
    "$VENV/bin/python" -m pip install -q --disable-pip-version-check \
        "torch==2.13.0" "scikit-learn" "shapely>=2.0,<2.1" "numpy<2.4" "pyamg>=5.0"
else
    echo "[setup_paraview] $VENV already has torch, sklearn, numpy, shapely, pyamg"
fi

SITE="$("$VENV/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')"
cat <<MSG
[setup_paraview] done. Use the wrapper (sets everything below):
    $REPO/scripts/pvenv.sh pvpython  script.py
    $REPO/scripts/pvenv.sh pvbatch   script.py
    $REPO/scripts/pvenv.sh paraview  --script=gui_script.py
or export by hand:
    export PYTHONPATH="$REPO/paraview_support:$SITE:$REPO"
    export PV_PLUGIN_PATH="$REPO/plugin"
    (and run under 'xvfb-run -a' when there is no DISPLAY)
MSG
