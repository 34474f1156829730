#!/bin/bash
# Journey: an error message is not hidden by the pixel readout. With the pointer
# resting on the picture (the status bar then shows the hovered pixel), the user saves
# into a folder that does not exist, then opens /dev/zero (no scene file), then a FIFO
# no program writes to, and cancels the wait with Esc.
# Checks: each time the error is in the status bar beside the readout, and stays there
# while the mouse rests and after it moves over the picture, until the next message;
# the FIFO is waited for, and Esc ends the wait with the scene as it was.
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
# (The dialog stays, with the path, to be corrected: Escape gives up.)
wait_state browser_message "Cannot save" 30
key Escape
wait_state popups "^none$"
rest_on_picture 5
idle 2
wait_state status_bar "Cannot save $OUT/no/such/folder/x.txt" 1
wait_state readout "spp" 1
rest_on_picture -40
idle 1
wait_state status_bar "Cannot save $OUT/no/such/folder/x.txt" 1
shot 1-save-failed

open_file() {
    key ctrl+o
    wait_state popups "Open scene or model"
    wait_state browser_field "^active$"
    key ctrl+a
    type_text "$1"
    key Return
    wait_state popups "^none$"
}

step "Open /dev/zero (a device, not a scene file)"
open_file /dev/zero
rest_on_picture 10
idle 2
wait_state status_bar "Cannot open /dev/zero: not a regular file or a pipe" 1
wait_state title "^default.txt - raytracer-view$" 1  # the scene stays
wait_state readout "spp" 1
shot 2-open-failed

step "Open a FIFO no program writes to: it is waited for, and Esc ends the wait"
mkfifo "$OUT/pipe.txt"
open_file "$OUT/pipe.txt"
wait_state status_bar "Reading pipe.txt.*Esc cancels" 5
key Escape
wait_state message "^Cancelled opening; showing default.txt$" 5
wait_state title "^default.txt - raytracer-view$" 1
wait_state readout "spp" 5
echo PASS
