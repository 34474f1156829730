#!/bin/bash
# Journey: the view's distance after a dolly. The user turns the wheel three notches
# toward the middle of the picture and reads the camera panel.
# Checks: the eye moved toward the scene, and the panel's "dist" (eye to the point
# looked at) shrank with it instead of staying what it was.
# Usage: j19_dolly_dist.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

step "open default.txt"
start_viewer "$SCENES/default.txt" --samples 4
wait_state render "done" 60
eye0=$(state view_eye)
d0=$(state view_angles | awk '{ print $3 }')
echo "eye $eye0, dist $d0"

step "three wheel notches toward the middle of the picture"
pointer_to $((ix + iw / 2)) $((iy + ih / 2))
for _ in 1 2 3; do
    eye=$(state view_eye)
    xdotool click 4
    wait_until '[ "$(state view_eye)" != "$eye" ]' 5 "a wheel notch to move the eye"
done
idle 1
wait_state render "done" 60
shot 1-dollied
eye1=$(state view_eye)
d1=$(state view_angles | awk '{ print $3 }')
moved=$(awk -v a="$eye0" -v b="$eye1" 'BEGIN { split(a, p); split(b, q); printf "%.3f", sqrt((p[1]-q[1])^2 + (p[2]-q[2])^2 + (p[3]-q[3])^2) }')
echo "eye $eye1 (moved $moved), dist $d1"
awk -v m="$moved" 'BEGIN { exit !(m > 1) }' || fail "the wheel did not move the eye (moved $moved)"
awk -v a="$d0" -v b="$d1" -v m="$moved" 'BEGIN { exit !(b < a - 0.5 * m) }' ||
    fail "the eye moved $moved toward the scene, but dist went from $d0 to $d1"
echo PASS
