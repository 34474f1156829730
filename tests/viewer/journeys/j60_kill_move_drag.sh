#!/bin/bash
# Journey: the viewer is killed (SIGKILL) in the middle of a move drag. The user selects
# the second sphere, drags the move handle's green arrow and holds the button; more than
# a second later the viewer is killed. The user starts it again on the same file.
# Checks: the file on disk is untouched and nothing else is left beside it; the new
# start offers the unsaved work (the banner), and Restore then Save give the sphere the
# position it had when the viewer was killed (the drag, never committed, is not lost).
# Usage: j60_kill_move_drag.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"
. "$(dirname "$0")/kill_lib.sh"

step "select sphere 2 and drag the move handle, holding the button"
start_viewer "$SCENES/default.txt" --samples 4
select_outline object_2
before=$(state value_position)
hx=$(field handle 1) hy=$(field handle 2)
# The y arrow points left in this view (the camera looks along +x, z up).
pointer_to $((hx - 45)) "$hy"
xdotool mousedown 1
wait_state pointer " down$"
for i in $(seq 1 10); do
    pointer_to $((hx - 45 - 10 * i)) "$hy"
done
wait_changed value_position "$before"
# Held still for more than a second: no work of the last second is at stake.
idle 1.5
moved=$(state value_position)
echo "position $before -> $moved (held)"
kill_viewer
xdotool mouseup 1

step "the file is as it was, with nothing beside it"
file_untouched "$SCENES/default.txt"

step "start again: the unsaved move is offered; restore it and save"
restore_and_save
# Line 10 of default.txt is the second sphere's position; the edit rewrote its numbers.
[ "$(sed -n 10p "$SCENE")" = "    position $moved" ] ||
    fail "the restored position is '$(sed -n 10p "$SCENE")', the drag had it at '$moved'"
echo PASS
