#!/bin/bash
# Journey: a material defined once and used by name. The user picks the middle of
# three gold balls; the material editor says the material is `gold`, used by three
# things; typing a reflection there changes gold for all three (one undo step, and
# Ctrl+Z takes it back); then "Make local" gives the middle ball its own copy, whose
# reflection the user types.
# Checks: the saved text after the edit is the original with only gold's definition
# rewritten (the balls' blocks still say `material gold`); the undo gives back the
# original bytes; after Make local and its reflection, gold is as it was, the middle ball's
# block spells out its own material, the other two still name gold; the picture
# equals raytracer's render of each saved text.
# Usage: j53_shared_material.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

# Three gold balls on a chess plane, gold defined once and used by name.
cp "$HERE/gold_balls.txt" "$OUT/gold.txt"
start_viewer "$OUT/gold.txt" --samples 2
cp "$SCENE" "$OUT/original.txt"
gold_uses() { grep -c "material gold" "$SCENE"; }

step "pick the middle ball: its material is gold, used by three things"
click $((ix + iw / 2)) $((iy + ih / 2))
wait_state selection "^object_2$"
wait_state material_shared '^material `gold`, used by 3 things' 5
echo "said: $(state material_shared)"
read -r px py <<< "$(item_xy field_radius)"
scroll_to field_material_reflection "$px" "$py"
xdotool click 5 click 5; idle 0.3  # the whole row in sight
shot 1-shared

step "type reflection 0.6 into the shared material: gold changes for all"
type_value material_reflection 0.6 reflection
wait_state title '^gold.txt\* - raytracer-view$'
save
grep -Eq '^  material gold \{ reflection 0.6 .*\}  // the gold$' "$SCENE" ||
    fail "gold's definition is not rewritten: $(grep -n 'material gold {' "$SCENE")"
[ "$(gold_uses)" -eq 4 ] || fail "the balls no longer name gold: $(grep -n material "$SCENE")"
diff <(grep -v 'material gold {' "$OUT/original.txt") <(grep -v 'material gold {' "$SCENE") ||
    fail "more than gold's definition changed"
select_nothing
picture_agrees 2-gold-reflects

step "Ctrl+Z: one step takes the edit back"
key ctrl+z
save
cmp "$SCENE" "$OUT/original.txt" || fail "undo did not give back the original text: $(diff "$OUT/original.txt" "$SCENE")"

step "Make local for the middle ball, then its own reflection"
click $((ix + iw / 2)) $((iy + ih / 2))
wait_state selection "^object_2$"
wait_state material_shared '^material `gold`' 5
click_item make_local
wait_state material_shared '^$' 5
read -r px py <<< "$(item_xy field_radius)"
scroll_to field_material_reflection "$px" "$py"
xdotool click 5 click 5; idle 0.3  # the whole row in sight
type_value material_reflection 0.3 reflection
wait_state title '^gold.txt\* - raytracer-view$'
save
grep -Eq '^  material gold \{ reflection 0 colour 1 0.8 0.2 \}  // the gold$' "$SCENE" ||
    fail "gold changed with the local copy: $(grep -n 'material gold {' "$SCENE")"
[ "$(gold_uses)" -eq 3 ] || fail "not exactly the middle ball left gold: $(grep -n material "$SCENE")"
grep -Eq 'material \{ reflection 0.3 .*colour 1 0.8 0.2 \}' "$SCENE" ||
    fail "the middle ball's own material is not in the text: $(cat "$SCENE")"
"$BIN/raytracer" --check "$SCENE" || fail "the saved text does not parse"
select_nothing
picture_agrees 3-local
quit_viewer
echo PASS
