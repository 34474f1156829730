#!/bin/bash
# Journey: whatever a worker changes reaches the screen while the mouse rests. The user
# leaves the pointer on the picture until the render is done, renders to a file and
# waits without touching anything, types an error in the text and waits, fixes it and
# waits, and another program changes the file on disk.
# Checks, each after a stretch with no input at all: the hover readout gives the
# finished render's samples; the Render to file dialog ends in "Saved to PATH" (and the
# file is there) instead of staying at "Rendering ... 100 %", and Escape closes it
# without the key reaching anything else; the live check lists the error, then none;
# the reloaded file's change is shown.
# Usage: j02_idle_redraw.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

step "open default.txt and rest the pointer on the picture until the render is done"
start_viewer "$SCENES/default.txt" --samples 16 --aa-threshold off  # every pixel to 16, in passes
xdotool mousemove $((ix + iw / 3)) $((iy + ih / 2))
idle 0.3
wait_state render "^16 done" 60
idle 1
wait_state readout " 16 spp" 2
shot 1-done

step "render to a file (the viewer's 16 samples), then wait without input"
key ctrl+r
wait_state render_dialog "^setup"
wait_state render_field "^active$"
key ctrl+a
type_text "$OUT/render.png"
key Return
idle 3
wait_state render_dialog "^saved $OUT/render.png" 30
[ -s "$OUT/render.png" ] || fail "the dialog says saved, but there is no $OUT/render.png"
idle 2
wait_state render_dialog "^saved" 1  # it stays until the user closes it
wait_state message "^Saved to $OUT/render.png"
shot 2-saved
key Escape
wait_state popups "^none$" 3
[ "$(field handle 1)" = none ] || fail "closing the dialog selected something: handle $(field handle 1)"

step "type an error in the text, wait; fix it, wait"
key ctrl+e
wait_state editor_grid "nowrap"
read -r x y <<< "$(editor_xy 6 14 0.9)"  # after "radius 1" of the first sphere
click "$x" "$y"
wait_state editor_cursor "^6 [0-9]+ focused$"
key End
type_text "abc"
wait_state editor_cursor "^6 16 focused$"
idle 1.5
wait_state diagnostics "^1 .*radius" 2
shot 3-error
key BackSpace BackSpace BackSpace
wait_state editor_cursor "^6 13 focused$"
idle 1.5
wait_state diagnostics "^0" 2
wait_state text "^unapplied$|^applied$"

step "another program changes the file: the viewer reloads it by itself"
key Escape
sed -i 's/^\(    radius \)1$/\11.25/' "$SCENE"
grep -q 'radius 1.25' "$SCENE" || fail "the test's edit of the file did not apply"
idle 3
wait_state message "^Reloaded" 5
shot 4-reloaded
echo PASS
