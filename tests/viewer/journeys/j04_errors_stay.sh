#!/bin/bash
# Journey: an error message is not hidden by the pixel readout. With the pointer
# resting on the picture (the status bar then shows the hovered pixel), the user saves
# into a folder that does not exist, then opens a FIFO (no scene file).
# Checks: each time the error is in the status bar beside the readout, and stays there
# while the mouse rests and after it moves over the picture, until the next message.
# Usage: j04_errors_stay.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

start_viewer "$SCENES/default.txt" --samples 4
rest_on_picture() {
    xdotool mousemove $((ix + iw / 2 + $1)) $((iy + ih / 2))
    wait_state readout "spp" 5
}

step "Save As into a folder that does not exist, the pointer on the picture"
rest_on_picture 0
key ctrl+shift+s
wait_state popups "Save scene as"
wait_state browser_field "^active$"
key ctrl+a
type_text "$OUT/no/such/folder/x.txt"
key Return
wait_state popups "^none$"
rest_on_picture 5
idle 2
wait_state status_bar "Save failed" 1
wait_state readout "spp" 1
rest_on_picture -40
idle 1
wait_state status_bar "Save failed" 1
shot 1-save-failed

step "Open a FIFO (not a scene file: no writer will ever come)"
mkfifo "$OUT/pipe.txt"
key ctrl+o
wait_state popups "Open scene"
wait_state browser_field "^active$"
key ctrl+a
type_text "$OUT/pipe.txt"
key Return
wait_state popups "^none$"
rest_on_picture 10
idle 2
wait_state status_bar "Cannot open.*pipe.txt: not a regular file" 1
wait_state title "^default.txt - raytracer-view$" 1  # the scene stays
wait_state readout "spp" 1
shot 2-open-failed
echo PASS
