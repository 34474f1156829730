#!/bin/bash
# Journey: moving one operand of a CSG with the move handle. The user selects
# "left: sphere" under the CSG in the outline, drags the handle's green (y) arrow and
# saves.
# Checks: only the operand's line of the saved text
# changed (its y grew), the other operand ("right: cylinder") is as it was; the picture
# equals `raytracer`'s render of the saved file.
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
y=$(awk '/left \{ sphere/ { print $6 }' "$SCENE")
awk -v y="$y" 'BEGIN { exit !(y > 2.5) }' || fail "the operand's y is $y, expected it to grow from 2.4"

step "the picture is raytracer's render of the saved text"
select_nothing
picture_agrees 3-saved
echo PASS
