#!/bin/bash
# Journey: moving one operand of a CSG with the move handle. The user selects
# "left: sphere" under the CSG in the outline, drags the handle's green (y) arrow and
# saves; then deletes the other operand and undoes that.
# Checks: only the operand's line of the saved text
# changed (its y grew), the other operand ("right: cylinder") is as it was; the picture
# equals `raytracer`'s render of the saved file. Delete on the right operand leaves
# the left sphere where the drag put it, in the CSG's material; Ctrl+Z restores the CSG.
# Usage: j10_operand_move.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

step "open default.txt and select the CSG's left operand in the outline"
start_viewer "$SCENES/default.txt" --samples 4
click_item "outline_object_4_left"
wait_state selection "^object_4_left$"
idle 0.5
hx=$(field handle 1) hy=$(field handle 2)
echo "handle at $hx $hy"
shot 1-selected

step "drag the green arrow 120 pixels further left"
# The y arrow points left in this view (the camera looks along +x, z up).
drag $((hx - 45)) "$hy" $((hx - 165)) "$hy"
idle 0.5
shot 2-dragged
[ "$(field handle 1)" -lt $((hx - 60)) ] || fail "the handle did not follow the drag ($hx -> $(field handle 1))"
save

step "only the left operand moved"
diff "$SCENES/default.txt" "$SCENE" > "$OUT/move.diff" || true
cat "$OUT/move.diff"
grep -q '^> *left { sphere { position 8 [0-9.]* 1 radius 1 } }$' "$OUT/move.diff" ||
    fail "the left operand's line did not change as a move along y: $(cat "$OUT/move.diff")"
[ "$(grep -c '^>' "$OUT/move.diff")" = 1 ] || fail "more than the left operand's line changed: $(cat "$OUT/move.diff")"
grep -qF 'right { cylinder { end_1 6.5 2.4 1 end_2 9.5 2.4 1 radius 0.45 } }' "$SCENE" ||
    fail "the right operand moved too: $(grep 'right {' "$SCENE")"
y=$(awk '/left \{ sphere/ { print $7 }' "$SCENE")  # left { sphere { position X Y Z
awk -v y="$y" 'BEGIN { exit !(y > 2.5) }' || fail "the operand's y is $y, expected it to grow from 2.4"

step "select the right operand (the cylinder) and press Delete: the CSG is its left sphere now"
click_item "outline_object_4_right"
wait_state selection "^object_4_right$"
shot 3-cylinder-selected
key Delete
idle 0.5
wait_state selection "^object_4$"
shot 4-operand-deleted
save
grep -q constructive_solid_geometry "$SCENE" && fail "the CSG is still in the text: $(cat "$SCENE")"
grep -q "cylinder { end_1 6.5" "$SCENE" && fail "the deleted cylinder is still in the text"
tr -s ' \n' ' ' < "$SCENE" |
    grep -Eq "sphere \{ material \{[^}]* colour 0\.3 0\.9 0\.4 \} position 8 $y 1 radius 1 \}" ||
    fail "no sphere at 8 $y 1 with the CSG's green material: $(cat "$SCENE")"

step "Ctrl+Z brings the CSG back as it was before the delete"
key ctrl+z
idle 0.5
save
grep -q "right { cylinder { end_1 6.5 2.4 1 end_2 9.5 2.4 1 radius 0.45 } }" "$SCENE" ||
    fail "undo did not restore the cylinder operand: $(cat "$SCENE")"

step "the picture is raytracer's render of the saved text"
select_nothing
picture_agrees 5-saved
echo PASS
