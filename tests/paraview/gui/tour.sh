#!/usr/bin/env bash
# Drives Debian's ParaView 5.11 GUI through the hexahedral filter as a new user would, under
# its own Xvfb screen (tests/paraview/gui/tour.py is the session script):
#   bash tests/paraview/gui/tour.sh OUTDIR
# 1. select hexa_bend.stl in the Pipeline Browser, Ctrl+Space, type "PINN hex", Return: PINN
#    Structured Mesh (Hexahedral) meshes the STL (faces found at Face Angle); View > Output Messages;
#    OUTDIR/stl.json holds what the update gave and how it is shown, OUTDIR/stl.png the screen;
# 2. select fig2.vtp (a 2D curve) and the same: a failed Apply; OUTDIR/curve.json,
#    OUTDIR/curve.png (the curve still shown, the message pointing to the 2D filters);
# 3. the first grid selected, Method pinn: OUTDIR/time_limit.png shows Time Limit;
# 4. File > Save Data of that grid as OUTDIR/bend.cgns and OUTDIR/bend.foam (no options
#    dialog: a hexahedral grid has no Extrude Thickness);
# 5. the grid's "?" in the Properties panel: OUTDIR/help.png (its page, the property table);
#    the help's Search tab, "PINN": OUTDIR/help_search.png.
# Needs paraview, xvfb-run, xdotool and ImageMagick's import (scripts/setup_paraview.sh).
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../../.." && pwd)"
OUT="$(realpath -m "${1:?usage: tour.sh OUTDIR}")"
mkdir -p "$OUT"

if [ "${PINN_GUI_INNER:-}" != 1 ]; then
    for tool in paraview xvfb-run xdotool import; do
        command -v "$tool" >/dev/null || { echo "$tool missing: bash scripts/setup_paraview.sh" >&2; exit 2; }
    done
    unset DISPLAY
    exec env PINN_GUI_INNER=1 "$REPO/scripts/pvenv.sh" \
        xvfb-run -a -s "-screen 0 1600x1000x24" bash "${BASH_SOURCE[0]}" "$OUT"
fi

export PINN_GUI_REPO="$REPO" PINN_GUI_READY="$OUT/ready" PINN_GUI_RESULT="$OUT/result"
rm -f "$PINN_GUI_READY" "$PINN_GUI_RESULT".*
paraview --dr --script="$REPO/tests/paraview/gui/tour.py" >"$OUT/tour.log" 2>&1 &
PV=$!
trap 'kill "$PV" 2>/dev/null || true' EXIT
for _ in $(seq 1 240); do
    [ -f "$PINN_GUI_READY" ] && break
    kill -0 "$PV" 2>/dev/null || { cat "$OUT/tour.log" >&2; echo "paraview exited" >&2; exit 1; }
    sleep 0.5
done
head -1 "$PINN_GUI_READY" | grep -q '^ready' || { cat "$PINN_GUI_READY" "$OUT/tour.log" >&2; exit 1; }
sleep 2
for w in $(xdotool search --onlyvisible --class paraview); do  # no window manager here
    if xdotool getwindowgeometry "$w" | grep -q 'Geometry: [0-9]\{3,\}x'; then
        xdotool windowmove "$w" 0 0
        xdotool windowsize "$w" 1600 1000
    fi
done
sleep 3

wait_for() {  # wait_for FILE SECONDS
    for _ in $(seq 1 $(($2 * 2))); do [ -f "$1" ] && return 0; sleep 0.5; done
    echo "no $1 after $2 s" >&2
    return 1
}

quick_launch() {  # quick_launch TEXT: Ctrl+Space, type, Return (ParaView 5.11's layout)
    xdotool key ctrl+space; sleep 2  # (a loaded machine's GUI answers slowly)
    xdotool type --delay 80 "$1"; sleep 1
    xdotool key Return
}

launch() {  # launch NAME TEXT X Y: select the Pipeline Browser's row at (X, Y), quick_launch
    # TEXT, until filter NAME exists (3 tries: a loaded machine's GUI may miss the
    # quick-launch's keys, and keys typed into the Pipeline Browser select another row)
    for _ in 1 2 3; do
        xdotool mousemove "$3" "$4" click 1; sleep 0.5
        quick_launch "$2"
        wait_for "$PINN_GUI_RESULT.$1.created" 20 2>/dev/null && return 0
        xdotool key Escape; sleep 1
    done
    import -window root "$OUT/$1.failed.png"
    echo "the quick-launch made no $1 (the screen: $OUT/$1.failed.png)" >&2
    return 1
}

# 1. the STL meshed; Output Messages opened from the View menu
launch PINNStructuredMeshHexahedral1 "PINN hex" 112 196      # hexa_bend.stl
wait_for "$PINN_GUI_RESULT.PINNStructuredMeshHexahedral1.json" 120
cp "$PINN_GUI_RESULT.PINNStructuredMeshHexahedral1.json" "$OUT/stl.json"
xdotool mousemove 100 10 click 1; sleep 1                    # View
xdotool mousemove 166 311 click 1; sleep 2                   # Output Messages
import -window root "$OUT/stl.png"

# 2. a 2D curve given to the hexahedral filter: a failed Apply
launch PINNStructuredMeshHexahedral2 "PINN hex" 91 240       # fig2.vtp
wait_for "$PINN_GUI_RESULT.PINNStructuredMeshHexahedral2.json" 60
cp "$PINN_GUI_RESULT.PINNStructuredMeshHexahedral2.json" "$OUT/curve.json"
sleep 2
import -window root "$OUT/curve.png"

# 3. the grid again, Method pinn: Time Limit under Grid Size
xdotool mousemove 139 218 click 1; sleep 1                   # PINNStructuredMeshHexahedral1
rm -f "$PINN_GUI_RESULT.PINNStructuredMeshHexahedral1.json"
xdotool mousemove 205 602 click 1; sleep 1                   # Method
xdotool mousemove 162 554 click 1; sleep 3                   # pinn (auto-apply trains)
import -window root "$OUT/time_limit.png"
wait_for "$PINN_GUI_RESULT.PINNStructuredMeshHexahedral1.json" 120

# 4. File > Save Data by file name: CGNS, then OpenFOAM; Return again takes the writer's
#    options dialog as it is (its Extrude Thickness is shown before the writer knows the grid
#    is 3D, and a 3D grid ignores it)
for name in bend.cgns bend.foam; do
    xdotool mousemove 139 218 click 1; sleep 0.5
    xdotool key ctrl+s; sleep 2
    xdotool type --delay 30 "$OUT/$name"; sleep 0.5
    xdotool key Return; sleep 2
    xdotool key Return; sleep 8
done
import -window root "$OUT/saved.png"

# 5. the panel's "?" opens the filter's page; the help's search finds the plugin's pages
xdotool mousemove 139 218 click 1; sleep 0.5                 # PINNStructuredMeshHexahedral1
xdotool mousemove 268 508 click 1; sleep 4                   # the Properties panel's "?"
import -window root "$OUT/help.png"
xdotool mousemove 117 14 click 1; sleep 1                    # the help's Search tab
xdotool mousemove 92 69 click 1; sleep 0.3
xdotool type --delay 80 "PINN"; xdotool key Return; sleep 4
import -window root "$OUT/help_search.png"
