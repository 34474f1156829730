#!/bin/bash
# Journey: several things chosen in the outline, and one material for them. The user
# clicks sphere 1 in the outline, Ctrl+clicks the torus, Shift+clicks the tetrahedron,
# Shift+clicks the torus again, presses "Give all objects the material of ...", saves,
# undoes, saves, and presses Esc.
# Checks: the panel counts 3, then 2 things; the glass sphere's material line becomes
# the tetrahedron's and nothing else changes; one Ctrl+Z restores the file byte for
# byte; Esc selects nothing.
# Usage: j67_outline_select.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

# ctrl_click / shift_click KEY: the outline row KEY with the modifier held.
mod_click() {
    local x y
    wait_state "$2" '^-?[0-9]+ -?[0-9]+ [0-9]+ [0-9]+$' 5
    read -r x y <<< "$(item_xy "$2")"
    xdotool mousemove "$x" "$y" keydown "$1" click 1 keyup "$1"
}

start_viewer "$SCENES/default.txt" --samples 4
step "sphere 1, Ctrl+click the torus, Shift+click the tetrahedron, Shift+click the torus again"
click_item outline_object_1
wait_state selection "^object_1$"
mod_click ctrl outline_object_3
wait_state group "^2 things selected: 2 objects$"
mod_click shift outline_object_5
wait_state group "^3 things selected: 3 objects$"
mod_click shift outline_object_3
wait_state group "^2 things selected: 2 objects$"
wait_state selection "^object_5$"
shot 1-two-in-outline

step "the tetrahedron's material for both: one undo step"
click_item button_give_material
wait_state message "^Gave 1 object the material of "
save
diff "$SCENES/default.txt" "$SCENE" > "$OUT/material.diff" || true
cat "$OUT/material.diff"
[ "$(grep -c '^>' "$OUT/material.diff")" = 1 ] || fail "not exactly one line changed"
# The scene as raytracer reads it: sphere 1's material is the tetrahedron's, key for key.
"$BIN/raytracer" --print-scene "$SCENE" > "$OUT/printed.txt" || fail "the saved file does not parse"
want=$(grep -m1 -A1 'tetrahedron {' "$OUT/printed.txt" | tail -1)
got=$(grep -m1 -A1 'sphere {' "$OUT/printed.txt" | tail -1)
echo "sphere 1: $got"
[ "$got" = "$want" ] || fail "sphere 1's material is not the tetrahedron's: '$got' vs '$want'"
key ctrl+z
wait_state message "^Undid: Material of "
save
cmp -s "$SCENES/default.txt" "$SCENE" || fail "undo did not restore the file"

step "Esc: nothing selected"
xdotool mousemove $((ix + iw / 2)) $((iy + ih / 2))
key Escape
wait_state selection "^none$"
echo PASS
