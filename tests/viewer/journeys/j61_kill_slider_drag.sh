#!/bin/bash
# Journey: the viewer is killed (SIGKILL) in the middle of a slider drag. The user
# selects the second sphere, presses on its "radius" field and drags it to the right,
# holding the button; more than a second later the viewer is killed. The user starts it
# again on the same file.
# Checks: the file on disk is untouched and nothing else is left beside it; the new
# start offers the unsaved work, and Restore then Save give the radius the value the
# field showed when the viewer was killed.
# Usage: j61_kill_slider_drag.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"
. "$(dirname "$0")/kill_lib.sh"

step "select sphere 2 and drag its radius field to the right, holding the button"
start_viewer "$SCENES/default.txt" --samples 4
select_outline object_2
before=$(state value_radius)
wait_state field_radius "^[0-9]+ [0-9]+ [0-9]+ [0-9]+$"
read -r fx fy fw fh <<< "$(state field_radius)"
x0=$((fx + fw / 2)) y0=$((fy + fh / 2))
pointer_to "$x0" "$y0"
xdotool mousedown 1
wait_state pointer " down$"
for i in $(seq 1 10); do
    pointer_to $((x0 + 6 * i)) "$y0"
done
wait_changed value_radius "$before"
idle 1.5
radius=$(state value_radius)
echo "radius $before -> $radius (held)"
kill_viewer
xdotool mouseup 1

step "the file is as it was, with nothing beside it"
file_untouched "$SCENES/default.txt"

step "start again: the unsaved radius is offered; restore it and save"
restore_and_save
# Line 11 of default.txt is the second sphere's radius.
[ "$(sed -n 11p "$SCENE")" = "    radius $radius" ] ||
    fail "the restored radius is '$(sed -n 11p "$SCENE")', the field showed '$radius'"
echo PASS
