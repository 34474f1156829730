#!/bin/bash
# Journey: a box select, then Delete and Duplicate of all it took. The user drags a box
# with Ctrl+Shift from the glass sphere's middle to the brown sphere's, presses Delete,
# Ctrl+Z, Ctrl+D, Ctrl+Z.
# Checks: the box selects the two spheres and not the floor it also covers ("2 things
# selected: 2 objects"); Delete removes both blocks from the text in one step (the rest
# of the text as it was); Ctrl+Z gives both back, text byte for byte and the two
# selected again; Ctrl+D copies both in one step and selects the copies; Ctrl+Z again
# leaves the original text and the originals selected.
# Usage: j65_box_select.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

step "open default.txt; where the two spheres are"
start_viewer "$SCENES/default.txt" --samples 4
sphere_handles

step "Ctrl+Shift+drag a box from one sphere's middle to the other's"
xdotool mousemove "$x1" "$y1" keydown ctrl keydown shift
sleep 0.1
xdotool mousedown 1
for i in $(seq 1 10); do
    xdotool mousemove $((x1 + (x2 - x1) * i / 10)) $((y1 + (y2 - y1) * i / 10))
    sleep 0.03
done
wait_state message "^Box select"
shot 1-box
xdotool mouseup 1 keyup shift keyup ctrl
wait_state group "^2 things selected: 2 objects$"
shot 2-selected

step "Delete: both go in one step; Ctrl+Z brings both back, selected"
key Delete
wait_state message "^Deleted 2 things"
wait_state selection "^none$"
save
diff "$SCENES/default.txt" "$SCENE" > "$OUT/delete.diff" || true
[ "$(grep -c '^<' "$OUT/delete.diff")" = 10 ] && [ "$(grep -c '^>' "$OUT/delete.diff")" = 0 ] ||
    fail "not just the two sphere blocks (10 lines) went: $(cat "$OUT/delete.diff")"
grep -q "position 5 0.9 1\|position 7.5 -1.6 1.3" "$SCENE" && fail "a sphere is still in the text"
key ctrl+z
wait_state message "^Undid: Delete 2 things"
wait_state group "^2 things selected: 2 objects$"
save
cmp -s "$SCENES/default.txt" "$SCENE" || fail "undo did not restore the text: $(diff "$SCENES/default.txt" "$SCENE")"

step "Ctrl+D: a copy of each, the copies selected; Ctrl+Z: the originals selected again"
key ctrl+d
wait_state message "^Duplicated 2 things"
wait_state group "^2 things selected: 2 objects$"
wait_state selection "^object_4$"  # objects 1, copy, 2, copy: the last added is the 4th
[ "$(state group)" ] || fail "no group"
save
[ "$(grep -c '^ *sphere {' "$SCENE")" = 4 ] || fail "not four spheres after Ctrl+D: $(cat "$SCENE")"
key ctrl+z
wait_state message "^Undid: Duplicate 2 things"
wait_state selection "^object_2$"
wait_state group "^2 things selected: 2 objects$"
save
cmp -s "$SCENES/default.txt" "$SCENE" || fail "undo of the copies did not restore the text"
echo PASS
