#!/bin/bash
# Journey: orbiting with the pointer on a far part of the floor (an infinite plane).
# The user presses the left button on the floor near the horizon and drags 60 pixels
# to the right.
# Checks: the eye turns about a point near the scene, not about the far floor point:
# it moves by about what a 60-pixel orbit is (18 degrees) at the scene's scale, and
# the objects stay in view (the picture is not the dark far floor).
# Usage: j14_orbit_far_plane.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

step "open default.txt"
start_viewer "$SCENES/default.txt" --samples 4
wait_state render "done" 60
eye0=$(state view_eye)
echo "eye before: $eye0 ($(state view_angles))"

step "drag 60 pixels from the far floor near the horizon"
x=$((ix + iw * 5 / 100)) y=$((iy + ih * 33 / 100))
drag "$x" "$y" $((x + 60)) "$y"
idle 0.5
wait_state render "done" 60
shot 1-orbited
eye1=$(state view_eye)
echo "eye after: $eye1 ($(state view_angles))"
moved=$(awk -v a="$eye0" -v b="$eye1" 'BEGIN { split(a, p); split(b, q); printf "%.3f", sqrt((p[1]-q[1])^2 + (p[2]-q[2])^2 + (p[3]-q[3])^2) }')
echo "the eye moved $moved"
# An 18-degree turn about the farthest object (tens of units away at most) moves the
# eye a few units; about the far floor point it moved it by more than 60.
awk -v m="$moved" 'BEGIN { exit !(m > 0.1 && m < 8) }' || fail "the eye moved $moved for a 60-pixel orbit"
colours=$("$TOOL" colours "$OUT/1-orbited.png" $IMAGE)
echo "distinct colours in the picture: $colours"
[ "$colours" -gt 5000 ] || fail "after the orbit the picture is nearly flat ($colours colours): the objects left the view"
echo PASS
