#!/bin/bash
# Journey: a big scene at 2560x1600 with the UI at 2x, on a machine whose every
# processor renders. The user starts the viewer on a 160,000-sphere grid
# (bench/make-grid.sh), rests the pointer on the picture while it renders, opens
# Ctrl+O and types a 40-character path.
# Checks: the window shows its first frame, with the load's progress, while the file
# still loads, within 1.5 s; while the picture renders under the pointer, the
# window shows at least 4 new frames a second (counted on the screen by
# rtview-xframes: the picture's changes), each repainting only a small part of the
# window (the software rasteriser's cost is per pixel painted: a whole frame took
# some 40 ms of processor time and held it to 5-9 frames a second); every typed
# character is in the field within 2 s of the last key (it showed about two
# characters a second).
# Usage: j50_big_scene_frames.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@" 2560x1600

mkdir -p "$XDG_CONFIG_HOME/raytracer-view"
echo "ui_scale 2" > "$XDG_CONFIG_HOME/raytracer-view/settings.txt"
"$HERE/../../../bench/make-grid.sh" 400 "$OUT/grid.txt"
SCENE=$OUT/grid.txt

step "start on the grid: the first frame, with the load's progress, at once"
# The screen's status-bar corner watched from before the start: the first change is the
# first frame on the screen.
read -r sw sh <<< "$(echo "$SCREEN" | tr x ' ')"
"$BIN/rtview-xframes" 0 $((sh - 60)) 1000 60 10 4 > "$OUT/first-frame.txt" &
XF=$!
wait_until 'grep -q "^start " "$OUT/first-frame.txt"' 5 "rtview-xframes to start watching"
launched=$EPOCHREALTIME
(cd "$OUT" && exec "$BIN/raytracer-view" "$SCENE" --size "$SCREEN" --print-layout --verbose > "$LAYOUT" 2> "$OUT/viewer.err") &
VIEWER_PID=$!
wait "$XF"
# Seconds from the start to the first change: xframes' times count from its "start".
first=$(awk -v l="${launched/,/.}" '$1 == "start" { s = $2 } $2 == "change" { printf "%.3f\n", s + $1 - l; exit }' "$OUT/first-frame.txt")
echo "first frame on the screen $first s after the start; load: $(state load)"
[ -n "$first" ] || fail "nothing was drawn in 4 s"
shot 1-first-frames
# The first frame drawn, as it showed: the load going on, and its progress.
first_block=$(awk '$1 == "end-layout" { exit } { print }' "$LAYOUT")
echo "$first_block" | grep -q '^state load loading$' || fail "the first frame came after the load"
echo "$first_block" | grep -Eq '^state status_bar .*(Reading|Parsing|Building|Opening)' ||
    fail "the first frame shows no progress: $(echo "$first_block" | grep '^state status_bar')"
# And soon: 0.36-0.41 s here beside two busy processes and a test suite; in one of seven
# such suite runs the scheduler made it 1.19 s. A window black until the load ends
# (the defect) shows its first frame after 2 s or more.
[ "$(echo "$first < 1.5" | bc)" = 1 ] || fail "the first frame came $first s after the start"
wait_state load "^ready$" 120

step "the picture renders under the pointer: frames on the screen"
image_region
xdotool mousemove $((ix + iw / 2)) $((iy + ih / 3))
wait_state render "running" 30
wait_state readout "spp" 10
# The UI thread's processor time over 3 s (utime + stime of the main thread, in clock
# ticks) beside the frames the screen shows meanwhile.
cpu() { awk '{ print $14 + $15 }' "/proc/$VIEWER_PID/task/$VIEWER_PID/stat"; }
reports=$(grep -c "frames/s" "$OUT/viewer.err" || true)
c0=$(cpu)
n=$("$BIN/rtview-xframes" "$ix" "$iy" "$iw" "$ih" 10 3 | awk '/^changes/ { print $2 }')
c1=$(cpu)
# --verbose reports every 3 s of frames: the share of the window the frames painted.
wait_until '[ "$(grep -c "frames/s" "$OUT/viewer.err")" -gt "$reports" ]' 10 "a report of the frames"
report=$(grep "frames/s" "$OUT/viewer.err" | tail -n +$((reports + 1)) | head -1)
echo "$report"
painted=$(echo "$report" | sed -nE 's/.*painted ([0-9]+)% of the window.*/\1/p')
[ -n "$painted" ] || fail "the report says nothing of the pixels painted: $report"
[ "$painted" -le 25 ] || fail "while the picture renders, frames paint $painted % of the window"
ticks=$(getconf CLK_TCK)
ui_ms=$(( (c1 - c0) * 1000 / ticks ))
echo "the picture changed $n times in 3 s; the UI thread used $ui_ms ms of processor time"
shot 2-rendering
[ "$ui_ms" -le 1200 ] || fail "while rendering, the UI thread took $ui_ms ms of the processors in 3 s"
[ "$n" -ge 12 ] || fail "while rendering, the picture changed only $n times in 3 s"

step "Ctrl+O and a 40-character path, typed while it renders"
key ctrl+o
wait_state browser_field "^active$" 10
key ctrl+a
path=/tmp/abcdefghijklmnopqrstuvwxyz/0123456789
xdotool type --delay 25 "$path"
wait_state browser "^open $path$" 2
idle 1
shot 3-typed
wait_state render "running" 1
key Escape
grep "frames/s" "$OUT/viewer.err" | tail -3 || true
echo PASS
