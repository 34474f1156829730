#!/bin/bash
# Journey: a material defined once and used by name, edited in the panels while the
# scene text holds an unapplied draft. The user types a smaller radius for the third
# gold ball into the text and does not apply it; then picks the middle ball and types a
# reflection into its material, which is gold, shared by three balls.
# Checks: the edit is made (no refusal in the status bar, the panel shows it); the
# draft stays unapplied and keeps the typed radius; the text gains gold's new
# reflection in its definition, whose comment stays, and the balls still name gold;
# Save applies the draft: the file has both, and the picture equals raytracer's render
# of it.
# Usage: j56_shared_material_draft.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

# Three gold balls on a chess plane, gold defined once and used by name.
cp "$HERE/gold_balls.txt" "$OUT/gold.txt"
start_viewer "$OUT/gold.txt" --samples 2

step "type radius 0.5 for the third ball (line 7), not applied"
key ctrl+e
wait_state editor_grid "nowrap"
read -r x y <<< "$(editor_xy 7 38 0.9)"
click "$x" "$y"
wait_state editor_cursor "^7 [0-9]+ focused$"
key End
for _ in $(seq 1 16); do key Left; done  # after "radius 0.9"
wait_state editor_cursor "^7 39 focused$"
key BackSpace
type_text "5"
wait_state text "^unapplied"
wait_state diagnostics "^0" 5

step "pick the middle ball: its material is gold, used by three things"
click $((ix + iw / 2)) $((iy + ih / 2))
wait_state selection "^object_2$"
wait_state material_shared '^material `gold`, used by 3 things' 5
read -r px py <<< "$(item_xy field_radius)"
scroll_to field_material_reflection "$px" "$py"
xdotool click 5 click 5; idle 0.3  # the whole row in sight

step "type reflection 0.6 into the shared material while the draft is there"
type_value material_reflection 0.6 reflection
idle 0.5
shot 1-edited
case "$(state status_bar)" in *"edit was undone"*|*"cannot be written"*) fail "refused: $(state status_bar)" ;; esac
wait_state text "^unapplied"
wait_state material_shared '^material `gold`, used by 3 things' 5

step "save: the draft is applied, with gold's new reflection"
save
grep -Eq '^  material gold \{ reflection 0.6 colour 1 0.8 0.2 \}  // the gold$' "$SCENE" ||
    fail "gold's definition is not rewritten in place: $(grep -n 'material gold {' "$SCENE")"
grep -q '^  sphere { position 6 2.2 1 radius 0.5 material gold }$' "$SCENE" ||
    fail "the typed radius is lost: $(grep -n 'position 6 2.2' "$SCENE")"
[ "$(grep -c 'material gold' "$SCENE")" -eq 4 ] || fail "the balls no longer name gold: $(grep -n material "$SCENE")"
wait_state text "^applied$"
select_nothing
picture_agrees 2-saved
quit_viewer
echo PASS
