#!/bin/bash
# The real raytracer-view window under Xvfb, driven with xdotool as a user would:
#  1. a 2 s left drag in the image orbits the view: the image area shows at least 5
#     new pictures during it (counted on screen by rtview-xframes), the camera panel
#     changes, and the title gains no '*' (the view is not the document);
#  2. Ctrl+K sets the scene camera from the view ('*'), and Ctrl+S saves atomically:
#     the file on disk equals the editor text and only camera lines changed;
#  3. typing a syntax error into the editor shows the error line (red text in the
#     diagnostics list) while the last good image stays;
#  4. clicking the error moves the cursor there (typing "//" comments the bad word out);
#  5. Ctrl+Q with unsaved changes asks (a modal) instead of quitting; Escape cancels;
#  6. a change made on disk by another program reloads by itself (the moved view stays);
#  7. F12 writes a screenshot of the whole window; the scene lands in the recent files;
#  8. a 100,000-sphere scene opens (the window paints while it loads) and navigates.
# Screenshots (import -window root) are kept in OUT_DIR to look at.
# Usage: xvfb_test.sh BIN_DIR OUT_DIR
set -euo pipefail
# shellcheck source=xvfb_start.sh
. "$(dirname "$0")/xvfb_start.sh" "$@"

SRC=$(cd "$(dirname "$0")/../.." && pwd)
XFRAMES=$BIN/rtview-xframes
SCENE=$OUT/scene.txt
rm -f "$OUT"/*.png "$OUT"/layout.txt
cp "$(dirname "$0")/../../scenes/default.txt" "$SCENE"
ORIGINAL=$OUT/original.txt
cp "$SCENE" "$ORIGINAL"

still_loading() { case "$(title)" in "(loading)"*) return 0 ;; esac; return 1; }

step "start the viewer"
cd "$OUT"
"$BIN/raytracer-view" "$SCENE" --size 1280x800 --samples 2 --print-layout > "$OUT/layout.txt" 2> "$OUT/viewer.err" &
VIEWER_PID=$!
WID=$(timeout 30 xdotool search --sync --name 'scene.txt' | head -1) || fail "no window appeared"
# The file loads in the background; the image area takes the scene's aspect then.
wait_until '! still_loading' 30 "the scene to load"
wait_until '[[ "$(state load)" == ready ]]' 10 "a frame that shows the loaded scene"
eval "$(xdotool getwindowgeometry --shell "$WID")"
[ "$X" = 0 ] && [ "$Y" = 0 ] || fail "expected the window at 0,0 (no window manager), got $X,$Y"
IMAGE=$(region image)
CAMERA=$(region camera)
SIDEBAR=$(region sidebar)
read -r ix iy iw ih <<< "$IMAGE"
cx=$((ix + iw / 2)); cy=$((iy + ih / 2))
echo "image $IMAGE, camera panel $CAMERA"

wait_stable before
colours=$("$TOOL" colours "$OUT/before.png" $IMAGE)
[ "$colours" -gt 1000 ] || fail "the image region has only $colours colours (black window?)"
[ "$("$TOOL" colours "$OUT/before.png" $SIDEBAR)" -gt 20 ] || fail "no panels drawn"
[[ "$(title)" == "scene.txt - raytracer-view" ]] || fail "title '$(title)'"

step "a 2 s drag orbits the view, with a new picture on many frames, and edits nothing"
# The middle of the image area (any new picture of an orbit changes it; sampling less
# of the screen keeps the counting itself from loading the X server).
"$XFRAMES" $((ix + iw / 4)) $((iy + ih / 4)) $((iw / 2)) $((ih / 2)) 10 2.4 > "$OUT/drag-frames.txt" &
XF_PID=$!
xdotool mousemove $cx $cy mousedown 1
for i in $(seq 1 60); do   # 30 pointer events a second for 2 s
    xdotool mousemove $((cx + i * 3)) $((cy + i / 2))
    sleep 0.033  # the pace of the drag is what is measured: not a wait for anything
done
xdotool mouseup 1
wait "$XF_PID"
# A screenshot in the middle of a drag, to look at (not during the count: grabbing
# the screen stalls the X server).
xdotool mousemove $cx $cy mousedown 1
for i in $(seq 1 10); do pointer_to $((cx - i * 3)) $((cy - i / 2)); done
shot mid-drag
for i in $(seq 11 20); do pointer_to $((cx - i * 3)) $((cy - i / 2)); done
xdotool mouseup 1
tail -1 "$OUT/drag-frames.txt"
drag_changes=$(awk '/^changes/ { print $2 }' "$OUT/drag-frames.txt")
[ "${drag_changes:-0}" -ge 5 ] || fail "the image area changed only ${drag_changes:-0} times during a 2 s drag"
wait_stable orbit
cam_change=$("$TOOL" diff "$OUT/before.png" "$OUT/orbit.png" $CAMERA)
img_change=$("$TOOL" diff "$OUT/before.png" "$OUT/orbit.png" $IMAGE)
echo "camera panel changed: $cam_change, image changed: $img_change"
awk -v c="$cam_change" 'BEGIN { exit !(c > 0.002) }' || fail "the camera panel did not change"
awk -v c="$img_change" 'BEGIN { exit !(c > 0.2) }' || fail "the image did not change"
[[ "$(title)" == "scene.txt - raytracer-view" ]] || fail "navigating marked the document modified: '$(title)'"
cmp -s "$SCENE" "$ORIGINAL" || fail "navigating wrote the file"

step "Ctrl+K sets the scene camera from the view; Ctrl+S saves the editor text"
xdotool key ctrl+k
wait_for "a '*' after setting the scene camera" title_is "scene.txt* - raytracer-view"
wait_stable set-camera
[ "$("$TOOL" diff "$OUT/orbit.png" "$OUT/set-camera.png" $IMAGE)" = "0.000000" ] || fail "setting the scene camera changed the picture"
xdotool key ctrl+s
wait_for "the '*' to go after Ctrl+S" title_is "scene.txt - raytracer-view"
cmp -s "$SCENE" "$ORIGINAL" && fail "the saved file did not change"
"$BIN/raytracer" --check "$SCENE" > /dev/null || fail "the saved scene does not parse"
diff <(grep -v '^ *\(position\|centre\|up\) ' "$ORIGINAL") <(grep -v '^ *\(position\|centre\|up\) ' "$SCENE") \
    > /dev/null || fail "saving changed more than camera lines"
# Temporary files are named .NAME.XXXXXX (core/image_io.cpp).
ls -A "$OUT" | grep -qE '^\..*\.[A-Za-z0-9]{6}$' && fail "a temporary file was left behind: $(ls -A "$OUT")"
cp "$SCENE" "$OUT/saved1.txt"

step "a syntax error shows, and the last image stays"
xdotool key ctrl+e
wait_until '[[ "$(state editor_grid)" == *nowrap* ]]' 10 "the text editor to open"
xdotool key ctrl+Home
xdotool type --delay 30 "zzbad "
# The live check runs once typing pauses: its diagnostics show.
has_errors() { [ "$(awk '$1 == "state" && $2 == "diagnostics" { n = $3 } END { print n + 0 }' "$LAYOUT")" -gt 0 ]; }
wait_for "the live check's diagnostics" has_errors
xdotool key ctrl+Return
input_seen
shot error
DIAG=$(region diagnostics)
red=$("$TOOL" near "$OUT/error.png" $DIAG 255 107 107 40)
echo "red pixels in the diagnostics list: $red"
[ "$red" -gt 30 ] || fail "no error line shown"
kept=$("$TOOL" diff "$OUT/orbit.png" "$OUT/error.png" $IMAGE)
[ "$kept" = "0.000000" ] || fail "the image changed after a failed apply ($kept)"

step "Ctrl+S asks first, then writes exactly the editor text, errors and all"
xdotool key ctrl+s
asks() { grep -q '^state button_save_anyway ' "$LAYOUT"; }
wait_for "Ctrl+S on text with errors to ask first" asks
read -r bx by <<< "$(awk '$1 == "state" && $2 == "button_save_anyway" { x = $3 + $5 / 2; y = $4 + $6 / 2 } END { print int(x), int(y) }' "$LAYOUT")"
[ "$bx" -gt 0 ] || fail "Ctrl+S on text with errors did not ask first"
xdotool mousemove "$bx" "$by" click 1
saved_with_error() { printf 'zzbad ' | cat - "$OUT/saved1.txt" | cmp -s - "$SCENE"; }
wait_for "the file to be the editor text" saved_with_error

step "clicking the error moves the cursor to it"
read -r dx dy dw dh <<< "$DIAG"
cursor=$(state editor_cursor)
xdotool mousemove $((dx + 60)) $((dy + 15)) click 1
wait_until '[ "$(state editor_cursor)" != "$cursor" ]' 10 "the click on the error to move the cursor"
xdotool type --delay 30 "//"
xdotool key ctrl+Return
xdotool key ctrl+s
commented_out() { printf '//zzbad ' | cat - "$OUT/saved1.txt" | cmp -s - "$SCENE"; }
wait_for "'//' to land at the error position (saved)" commented_out
shot fixed
[ "$("$TOOL" near "$OUT/fixed.png" $DIAG 255 107 107 40)" -lt 5 ] || fail "the error is still listed"
xdotool mousemove $cx $cy   # keyboard focus follows the pointer without a window manager

step "Ctrl+Q with unsaved changes asks first"
xdotool mousemove $cx $cy mousedown 3   # a right-drag pan
for dx in 10 20 30 40; do pointer_to $((cx + dx)) $((cy + dx / 4)); done
xdotool mouseup 3
wait_until '[[ "$(state pointer)" != *down* ]]' 10 "the end of the pan"
[[ "$(title)" == *"*"* ]] && fail "the pan modified the document"
xdotool key ctrl+k   # a real edit, so that quitting asks
modified() { [[ "$(title)" == *"*"* ]]; }
wait_for "Ctrl+K to modify the document" modified
wait_stable panned
xdotool key ctrl+q
wait_until '[[ "$(state popups)" == *Unsaved* ]]' 10 "Ctrl+Q to ask about the unsaved changes"
kill -0 "$VIEWER_PID" 2>/dev/null || fail "the viewer quit without asking"
wait_stable asking   # the modal's dimming fades in over a few frames
dim=$("$TOOL" diff "$OUT/panned.png" "$OUT/asking.png" $IMAGE)
awk -v c="$dim" 'BEGIN { exit !(c > 0.5) }' || fail "no modal dialog (image region changed only $dim)"
xdotool key Escape
wait_until '[[ "$(state popups)" == none ]]' 10 "Escape to close the dialog"
wait_stable cancelled   # the frame after the dialog, not the one the state was written in
[ "$("$TOOL" diff "$OUT/panned.png" "$OUT/cancelled.png" $IMAGE)" = "0.000000" ] || fail "the dialog did not close"

step "F12 writes a screenshot of the window"
xdotool key F12
# Written within a frame or two; a loaded machine may take seconds.
screenshot_written() { F12=$(ls "$OUT"/raytracer-view-2*.png 2>/dev/null | head -1 || true); [ -n "$F12" ]; }
wait_until screenshot_written 10 "the F12 screenshot"
[ "$("$TOOL" colours "$F12" 0 0 1280 800)" -gt 1000 ] || fail "the F12 screenshot looks empty"

step "a change on disk reloads by itself, keeping the moved view"
xdotool key ctrl+s
wait_for "the save" title_is "scene.txt - raytracer-view"
xdotool mousemove $cx $cy mousedown 3   # move the view away from the scene camera
for dx in 10 20 30; do pointer_to $((cx - dx)) $((cy + dx / 3)); done
xdotool mouseup 3
wait_stable cancelled
[[ "$(title)" == "scene.txt - raytracer-view" ]] || fail "the pan marked the document modified: '$(title)'"
sed 's/radius 1.3/radius 0.6/' "$SCENE" > "$OUT/edited.tmp"
mv "$OUT/edited.tmp" "$SCENE"   # as editors save: a new file renamed over the old
reloaded() { grep -q '^state message Reloaded' "$LAYOUT"; }
wait_for "the reload" reloaded
wait_stable reloaded
reload_change=$("$TOOL" diff "$OUT/cancelled.png" "$OUT/reloaded.png" $IMAGE)
awk -v c="$reload_change" 'BEGIN { exit !(c > 0.01) }' || fail "the image did not change after the file changed ($reload_change)"
[ "$("$TOOL" diff "$OUT/cancelled.png" "$OUT/reloaded.png" $CAMERA)" = "0.000000" ] || fail "the view was not kept"
grep -q "radius 0.6" "$SCENE" || fail "test setup: the edit did not happen"

step "after saving, Ctrl+Q quits"
xdotool key ctrl+s
wait_for "the save" title_is "scene.txt - raytracer-view"
xdotool key ctrl+q
wait_until '! kill -0 "$VIEWER_PID" 2>/dev/null' 10 "the viewer to quit"
wait "$VIEWER_PID" || fail "the viewer exited with status $?"
VIEWER_PID=
grep -q "radius 0.6" "$SCENE" || fail "the final save lost the reloaded change"
grep -qx "$SCENE" "$XDG_CONFIG_HOME/raytracer-view/recent.txt" || fail "the scene is not in the recent-files list"

step "a 100,000-sphere scene opens and navigates"
BIG=$OUT/grid100k.txt
[ -s "$BIG" ] || "$SRC/bench/make-grid.sh" 317 "$BIG"
"$BIN/raytracer-view" "$BIG" --size 1280x800 --samples 1 --print-layout > "$OUT/layout.txt" 2> "$OUT/viewer.err" &
VIEWER_PID=$!
WID=$(timeout 30 xdotool search --sync --name 'grid100k.txt' | head -1) || fail "no window appeared"
# The window paints while the file loads: its title says so, then drops the mark.
wait_until '! still_loading' 60 "the big scene to load"
[[ "$(title)" == "grid100k.txt - raytracer-view" ]] || fail "the big scene did not open: '$(title)'"
wait_until '[[ "$(state load)" == ready ]]' 10 "a frame that shows the loaded big scene"
IMAGE=$(region image)
read -r ix iy iw ih <<< "$IMAGE"
cx=$((ix + iw / 2)); cy=$((iy + ih / 2))
wait_stable big-before
xdotool mousemove $cx $cy mousedown 1
for i in $(seq 1 20); do pointer_to $((cx + i * 4)) $((cy - i)); done
xdotool mouseup 1
xdotool mousemove $cx $cy click --repeat 3 4   # three wheel notches in
wait_stable big-after
big_change=$("$TOOL" diff "$OUT/big-before.png" "$OUT/big-after.png" $IMAGE)
echo "big scene: image changed $big_change"
awk -v c="$big_change" 'BEGIN { exit !(c > 0.2) }' || fail "navigating the big scene did not change the image"
[[ "$(title)" == "grid100k.txt - raytracer-view" ]] || fail "navigating the big scene modified it: '$(title)'"
xdotool key ctrl+q
wait_until '! kill -0 "$VIEWER_PID" 2>/dev/null' 10 "the viewer to quit"
wait "$VIEWER_PID" || fail "the viewer exited with status $?"
VIEWER_PID=
echo "xvfb test passed; screenshots in $OUT"
