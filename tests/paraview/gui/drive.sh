#!/usr/bin/env bash
# Drives Debian's ParaView 5.11 GUI as a user would, under its own Xvfb screen:
#   bash tests/paraview/gui/drive.sh OUTDIR
# 1. select fig2.vtp and fig2_aux.vtp in the Pipeline Browser (click, ctrl+click), open the
#    quick-launch (Ctrl+Space), type "PINN" (OUTDIR/quick_launch.png: the list it offers),
#    press Return: PINN Structured Mesh is created on both sources and auto-applied;
#    OUTDIR/aux_lines.json holds what its update gave and OUTDIR/aux_lines.png the screen;
# 2. the same with a long training (Preset paper, 200000 Adam epochs): once the filter's
#    progress says it trains, `kill -USR1` stops it with the best grid so far;
#    OUTDIR/stop.json holds the filter's result, OUTDIR/alive whether ParaView still runs
#    afterwards and OUTDIR/stopped.png the screen with the grid and the warning;
#    2b. the same long training stopped by the progress bar's abort button (clicked at
#    its place in ParaView 5.11's status bar), after a click on fig2_aux.vtp's row:
#    OUTDIR/abort.json, OUTDIR/abort_display.json (the source still selected afterwards),
#    OUTDIR/abort_clicked and abort_done (the times), OUTDIR/training.png (the window
#    repainted during the training) and OUTDIR/aborted.png;
# 3. the same long training with a Time Limit of 4 s: OUTDIR/limit.json, OUTDIR/limit.png;
# 4. a failed first Apply (only fig2_aux.vtp selected: no closed boundary), then the input
#    fixed (both sources) and Apply pressed: OUTDIR/failed_display.json and
#    OUTDIR/fixed_display.json hold the display's representation and colour array after
#    each, OUTDIR/failed.png and OUTDIR/fixed.png the screen.
# Needs paraview, xvfb-run, xdotool and ImageMagick's import (scripts/setup_paraview.sh).
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../../.." && pwd)"
OUT="$(realpath -m "${1:?usage: drive.sh OUTDIR}")"
mkdir -p "$OUT"

if [ "${PINN_GUI_INNER:-}" != 1 ]; then
    for tool in paraview xvfb-run xdotool import; do
        command -v "$tool" >/dev/null || { echo "$tool missing: bash scripts/setup_paraview.sh" >&2; exit 2; }
    done
    unset DISPLAY
    exec env PINN_GUI_INNER=1 "$REPO/scripts/pvenv.sh" \
        xvfb-run -a -s "-screen 0 1600x1000x24" bash "${BASH_SOURCE[0]}" "$OUT"
fi

export PINN_GUI_REPO="$REPO" PINN_GUI_READY="$OUT/ready"

session() {  # session NAME LONG: start ParaView, wait until the session script is done
    export PINN_GUI_RESULT="$OUT/$1.json" PINN_GUI_LONG="$2"
    rm -f "$PINN_GUI_RESULT" "$PINN_GUI_RESULT.training" "$PINN_GUI_READY"
    paraview --dr --script="$REPO/tests/paraview/gui/session.py" >"$OUT/$1.log" 2>&1 &
    PV=$!
    for _ in $(seq 1 240); do
        [ -f "$PINN_GUI_READY" ] && break
        kill -0 "$PV" 2>/dev/null || { cat "$OUT/$1.log" >&2; echo "paraview exited" >&2; exit 1; }
        sleep 0.5
    done
    head -1 "$PINN_GUI_READY" 2>/dev/null | grep -q '^ready' || { cat "$PINN_GUI_READY" "$OUT/$1.log" >&2; exit 1; }
    sleep 2
    for w in $(xdotool search --onlyvisible --class paraview); do  # no window manager here
        if xdotool getwindowgeometry "$w" | grep -q 'Geometry: [0-9]\{3,\}x'; then
            xdotool windowmove "$w" 0 0
            xdotool windowsize "$w" 1600 1000
        fi
    done
    sleep 3
}

quick_launch_pinn() {  # quick_launch_pinn [SCREENSHOT]: Ctrl+Space, "PINN", Return
    xdotool key ctrl+space; sleep 2  # (a loaded machine's GUI answers slowly)
    xdotool type --delay 80 "PINN"; sleep 2
    [ -z "${1:-}" ] || import -window root "$1"
    xdotool key Return
}

select_both_and_apply() {  # rows of the Pipeline Browser in ParaView 5.11's default layout
    xdotool mousemove 91 196 click 1; sleep 1                             # fig2.vtp
    xdotool keydown ctrl mousemove 106 218 click 1 keyup ctrl; sleep 2    # + fig2_aux.vtp
    quick_launch_pinn "${1:-}"
}

wait_for() {  # wait_for FILE SECONDS
    for _ in $(seq 1 $(($2 * 2))); do [ -f "$1" ] && return 0; sleep 0.5; done
    return 1
}

start_training() {  # select both, quick-launch PINN, until the filter trains (3 tries: a
    # loaded machine's GUI may miss the quick-launch's keys)
    for _ in 1 2 3; do
        select_both_and_apply
        wait_for "$PINN_GUI_RESULT.training" 60 && return 0
        xdotool key Escape; sleep 1
    done
    return 1
}

# 1. both sources selected, filter from the quick-launch
session aux_lines 0
select_both_and_apply "$OUT/quick_launch.png"
wait_for "$PINN_GUI_RESULT" 120 || { echo "no result from the filter" >&2; kill "$PV"; exit 1; }
sleep 3
xdotool mousemove 1590 990
import -window root "$OUT/aux_lines.png"
kill "$PV"; wait "$PV" 2>/dev/null || true

# 2. a long training, stopped
session stop 1
start_training || { echo "the training did not start" >&2; kill "$PV"; exit 1; }
sleep 3    # well into the training
kill -USR1 "$PV"
wait_for "$PINN_GUI_RESULT" 60 || { echo "the training did not stop" >&2; kill "$PV"; exit 1; }
sleep 2
if kill -0 "$PV" 2>/dev/null; then echo yes >"$OUT/alive"; else echo no >"$OUT/alive"; fi
import -window root "$OUT/stopped.png"
kill "$PV"; wait "$PV" 2>/dev/null || true

# 2b. a long training stopped by the progress bar's abort button, a click on another
#     source's row made meanwhile (dropped, never replayed: the filter stays selected)
session abort 1
start_training || { echo "the training did not start" >&2; kill "$PV"; exit 1; }
sleep 4    # into the training: the window repaints meanwhile
import -window root "$OUT/training.png"
xdotool mousemove 106 218 click 1; sleep 0.5                       # fig2_aux.vtp's row
date +%s.%N >"$OUT/abort_clicked"
xdotool mousemove 533 985 click 1                                  # the progress bar's abort
wait_for "$PINN_GUI_RESULT" 60 || { echo "abort did not stop the training" >&2; kill "$PV"; exit 1; }
date +%s.%N >"$OUT/abort_done"
sleep 5    # any click replayed would have acted by now
echo "$OUT/abort_display.json" >"$PINN_GUI_RESULT.probe"
wait_for "$OUT/abort_display.json" 10 || { echo "no display state" >&2; kill "$PV"; exit 1; }
xdotool mousemove 1590 990
import -window root "$OUT/aborted.png"
kill "$PV"; wait "$PV" 2>/dev/null || true

# 3. a long training under a time limit
export PINN_GUI_TIME_LIMIT=4
session limit 1
select_both_and_apply
wait_for "$PINN_GUI_RESULT" 90 || { echo "the time limit did not stop the training" >&2; kill "$PV"; exit 1; }
sleep 3
import -window root "$OUT/limit.png"
kill "$PV"; wait "$PV" 2>/dev/null || true

# 4. a failed first Apply, the input fixed, Apply again
unset PINN_GUI_TIME_LIMIT
session failed 0
xdotool mousemove 106 218 click 1; sleep 0.5                           # fig2_aux.vtp only
quick_launch_pinn
wait_for "$PINN_GUI_RESULT" 60 || { echo "no result from the failing filter" >&2; kill "$PV"; exit 1; }
sleep 2
echo "$OUT/failed_display.json" >"$PINN_GUI_RESULT.probe"
wait_for "$OUT/failed_display.json" 10 || { echo "no display state" >&2; kill "$PV"; exit 1; }
import -window root "$OUT/failed.png"
rm -f "$PINN_GUI_RESULT"
touch "$PINN_GUI_RESULT.fix"; sleep 2                                  # Change Input: both
xdotool mousemove 138 283 click 1; sleep 1                              # the filter's row
xdotool mousemove 47 508 click 1                                        # Apply
wait_for "$PINN_GUI_RESULT" 60 || { echo "no result after the fix" >&2; kill "$PV"; exit 1; }
sleep 3
echo "$OUT/fixed_display.json" >"$PINN_GUI_RESULT.probe"
wait_for "$OUT/fixed_display.json" 10 || { echo "no display state" >&2; kill "$PV"; exit 1; }
xdotool mousemove 1590 990
import -window root "$OUT/fixed.png"
kill "$PV"; wait "$PV" 2>/dev/null || true
