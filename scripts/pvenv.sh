#!/usr/bin/env bash
# Run a ParaView executable with the pinn-mesh environment:
#   scripts/pvenv.sh pvpython script.py [args...]
#   scripts/pvenv.sh pvbatch  script.py
#   scripts/pvenv.sh paraview --script=gui.py
#   scripts/pvenv.sh env            # print the variables
#
# Sets
#   PYTHONPATH     = paraview_support (getargspec shim) : .venv-pv site-packages
#                    (torch, sklearn, numpy<2.4) : repo root (import pinn_engine)
#   PV_PLUGIN_PATH = <repo>/plugin   (override with PINN_PV_PLUGIN_PATH)
# and runs the command on a private Xvfb screen when DISPLAY is unset and the
# command renders (paraview, pvpython, pvbatch).  Set PINN_PV_NO_XVFB=1 to
# skip the X server (pure pipeline work without rendering).
# Other knobs: PINN_PV_VENV (default <repo>/.venv-pv), PINN_PV_EXTRA_PYTHONPATH,
# PINN_PV_NO_REPO_PATH=1 (leave the repo root off PYTHONPATH: the plugin must then
# find pinn_engine by itself, as it does when loaded by a plain ParaView).
set -euo pipefail

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="${PINN_PV_VENV:-$REPO/.venv-pv}"

if [ ! -x "$VENV/bin/python" ]; then
    echo "pvenv.sh: $VENV missing; run scripts/setup_paraview.sh first" >&2
    exit 2
fi
# site-packages path without starting python every time (venv layout is fixed)
SITE="$(echo "$VENV"/lib/python3.*/site-packages)"

# The caller's PYTHONPATH is deliberately dropped: a pip vtk/pyvista on it makes
# pvpython segfault.  Add extra entries with PINN_PV_EXTRA_PYTHONPATH.
unset PYTHONHOME
REPO_ON_PATH=":$REPO"
if [ -n "${PINN_PV_NO_REPO_PATH:-}" ]; then REPO_ON_PATH=""; fi
export PYTHONPATH="$REPO/paraview_support:$SITE$REPO_ON_PATH${PINN_PV_EXTRA_PYTHONPATH:+:$PINN_PV_EXTRA_PYTHONPATH}"
export PV_PLUGIN_PATH="${PINN_PV_PLUGIN_PATH:-$REPO/plugin}"
# Qt under Xvfb: no GPU, use Mesa's software GL; silence the XDG warning.
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp/runtime-$(id -u)}"
mkdir -p "$XDG_RUNTIME_DIR" && chmod 700 "$XDG_RUNTIME_DIR"

if [ $# -eq 0 ] || [ "$1" = "env" ]; then
    echo "export PYTHONPATH=\"$PYTHONPATH\""
    echo "export PV_PLUGIN_PATH=\"$PV_PLUGIN_PATH\""
    exit 0
fi

case "$(basename "$1")" in
    paraview|pvpython|pvbatch) needs_x=1 ;;
    *) needs_x=0 ;;
esac

if [ "$needs_x" = 1 ] && [ -z "${DISPLAY:-}" ] && [ -z "${PINN_PV_NO_XVFB:-}" ]; then
    # Our own Xvfb instead of `xvfb-run -a`, under which pvpython aborted now and then ("bad
    # X server connection", 2 runs in 19): Xvfb reset itself when its first client left, and
    # a connection during the reset failed. -noreset keeps it up; -displayfd lets it pick a
    # free display and write the number once it accepts connections.
    fifo="$(mktemp -u)"
    mkfifo "$fifo"
    Xvfb -displayfd 3 -screen 0 1600x1000x24 -nolisten tcp -noreset 3>"$fifo" >/dev/null 2>&1 &
    xvfb_pid=$!
    trap 'kill "$xvfb_pid" 2>/dev/null || true; rm -f "$fifo"' EXIT
    read -r -t 30 display_number <"$fifo" || { echo "pvenv.sh: Xvfb did not start" >&2; exit 2; }
    export DISPLAY=":$display_number"
    status=0
    "$@" || status=$?
    exit "$status"
fi
exec "$@"
