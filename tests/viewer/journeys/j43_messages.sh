#!/bin/bash
# Journey: messages beside the pointer's readout, and messages that go stale. With the
# pointer resting on the picture the user presses F12; types "abc" into sphere 1's
# radius after typing 1.5, then undoes the 1.5 and types 2; types an error into the scene text,
# applies it and reverts it; opens a PLY model.
# Checks: the screenshot's message, with its full path, shows beside the readout while
# the pointer stays on the picture; the radius field's message goes once the radius
# changes by the undo; the undo's "(Ctrl+Y redoes)" goes once another edit is made; "the scene text has errors" goes once the text is reverted; a
# model opened says the model's name and the new scene's.
# Usage: j43_messages.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

cp "$HERE/../../models/cube_ascii.ply" "$OUT/cube_ascii.ply"
start_viewer "$SCENES/default.txt" --samples 4 --select "object 1"

step "F12 with the pointer on the picture: the message shows beside the readout"
xdotool mousemove $((ix + iw / 2)) $((iy + 20))
wait_state readout "spp" 5
key F12
wait_state status_bar "Wrote screenshot $OUT/raytracer-view-[0-9-]+\.png" 5
idle 1
wait_state readout "spp" 1
wait_state status_bar "x [0-9]+ y [0-9]+.*Wrote screenshot $OUT/raytracer-view-" 1
shot 1-screenshot-message

step "a refused radius, then an undo that changes the radius: the message goes"
type_value radius 1.5
wait_state value_radius '^1\.5$' 5
type_value radius abc
wait_state field_message "radius: expected a number, got 'abc'" 5
xdotool mousemove $((ix + iw / 2)) $((iy + 20))
key ctrl+z
wait_state value_radius '^1$' 5
idle 0.5
[ -z "$(state field_message)" ] || fail "the radius message stayed after the radius changed: $(state field_message)"

step "an undo said, then another edit: the undo's message goes (Ctrl+Y would no longer redo it)"
wait_state message "^Undid: .*\(Ctrl\+Y redoes\)" 5
type_value radius 2
wait_state value_radius '^2$' 5
idle 0.5
state message | grep -q "Ctrl+Y redoes" && fail "the undo's message stayed after another edit: $(state message)"
key ctrl+z  # (back to the file's text: the Open below asks nothing)
wait_state value_radius '^1$' 5

step "an error applied, then reverted: its message goes"
click_item tab_Text
wait_state editor_grid "."
read -r x y <<< "$(editor_xy 1 1)"
click "$x" "$y"
key ctrl+Home
type_text "oops "
key ctrl+Return
wait_state status_bar "The scene text has errors" 5
click_item button_revert
wait_state text "^applied$" 5
idle 0.5
state status_bar | grep -q "has errors" && fail "the errors' message stayed after Revert: $(state status_bar)"

step "a PLY model opened: the message names it"
key ctrl+o
wait_state popups "Open scene or model"
wait_state browser_field "^active$"
key ctrl+a
type_text "$OUT/cube_ascii.ply"
wait_state browser "^open $OUT/cube_ascii.ply$" 30
key Return
wait_state message "^Opened cube_ascii.ply as the new scene cube_ascii.txt" 30
echo PASS
