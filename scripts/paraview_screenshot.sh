#!/usr/bin/env bash
# Screenshot of the ParaView GUI with the PINN Structured Mesh filter applied to
# example_data/fig2.vtp + fig2_aux.vtp: Pipeline Browser, Properties panel with the filter's
# settings, and the grid coloured by MaxIncludedAngle.
#
#   bash scripts/paraview_screenshot.sh [OUT.png]     # default docs/images/paraview_gui.png
#
# Needs `bash scripts/setup_paraview.sh` (ParaView, .venv-pv, xvfb, xdotool, ImageMagick).
# Runs the GUI on its own Xvfb screen (1600x1000) even when a display exists.
# PINN_SHOT_MENU=menu.png also saves a picture of the open Filters menu.
set -euo pipefail

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="$(realpath -m "${1:-$REPO/docs/images/paraview_gui.png}")"

if [ "${PINN_SHOT_INNER:-}" != 1 ]; then
    for tool in paraview xvfb-run xdotool import; do
        command -v "$tool" >/dev/null || { echo "$tool missing: bash scripts/setup_paraview.sh" >&2; exit 2; }
    done
    mkdir -p "$(dirname "$OUT")"
    unset DISPLAY
    exec env PINN_SHOT_INNER=1 "$REPO/scripts/pvenv.sh" \
        xvfb-run -a -s "-screen 0 1600x1000x24" bash "${BASH_SOURCE[0]}" "$OUT"
fi

# --- inside Xvfb, with the pvenv.sh environment -----------------------------------------
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
export PINN_SHOT_READY="$WORK/ready" PINN_SHOT_REPO="$REPO"
paraview --dr --script="$REPO/scripts/paraview_screenshot_gui.py" >"$WORK/paraview.log" 2>&1 &
PV=$!
for _ in $(seq 1 240); do   # up to 2 minutes (start-up + training)
    [ -f "$PINN_SHOT_READY" ] && break
    kill -0 $PV 2>/dev/null || { cat "$WORK/paraview.log" >&2; echo "paraview exited" >&2; exit 1; }
    sleep 0.5
done
[ -f "$PINN_SHOT_READY" ] || { cat "$WORK/paraview.log" >&2; echo "timed out" >&2; kill $PV; exit 1; }
if ! head -1 "$PINN_SHOT_READY" | grep -q '^ready'; then
    cat "$PINN_SHOT_READY" >&2; kill $PV; exit 1
fi
sleep 1
# no window manager under Xvfb: move and enlarge the main window (skip tiny helper windows)
for w in $(xdotool search --onlyvisible --class paraview); do
    if xdotool getwindowgeometry "$w" | grep -q 'Geometry: [0-9]\{3,\}x'; then
        xdotool windowmove "$w" 0 0
        xdotool windowsize "$w" 1600 1000
    fi
done
sleep 2
# widen the Pipeline Browser / Properties dock: drag the splitter at its right edge
SPLIT_X="${PINN_SHOT_SPLIT_X:-296}"
xdotool mousemove "$SPLIT_X" 600; sleep 0.3; xdotool mousedown 1; sleep 0.3
for x in 320 360 400 440 470; do xdotool mousemove "$x" 600; sleep 0.2; done
xdotool mouseup 1; sleep 0.3
xdotool mousemove 1590 990
sleep 3   # relayout and repaint
import -window root "$OUT"
if [ -n "${PINN_SHOT_MENU:-}" ]; then   # optional second picture: the open Filters menu
    xdotool mousemove 215 10 click 1; sleep 1.5
    xdotool mousemove 290 330; sleep 0.3; xdotool mousemove 300 336 click 1; sleep 1.5  # "Mesh Generation" (5.11 layout)
    import -window root "$PINN_SHOT_MENU"
fi
kill $PV 2>/dev/null || true
wait $PV 2>/dev/null || true
if grep -q "PINN Structured Mesh:" "$WORK/paraview.log"; then
    grep "PINN Structured Mesh:" "$WORK/paraview.log" >&2
fi
echo "wrote $OUT"
