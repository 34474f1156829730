#!/bin/bash
# Journey: the scene text shown while panels, the move handle and undo change it. With
# the Text tab open the user types a comment at the top and applies it (Ctrl+Enter),
# picks sphere 2 in the picture, goes back to the Text tab and moves the sphere with
# the handle's green arrow (the text on the screen changes under the cursor), types a second comment below the moved sphere's block,
# applies and saves; then, in the Objects tab, types radius 1.5 for sphere 1, goes
# back to the Text tab, types a third comment on the first line, applies, undoes the
# typing and the radius with Ctrl+Z outside the text, and saves again.
# Checks: every comment lands exactly where it was typed and nothing else of the text
# changes but the moved position and the radius (the file's bytes against default.txt
# edited the same way); the saved text parses; the undo leaves the text of the first
# save, byte for byte; Ctrl+Y and Ctrl+Z typed in the text then redo and undo the
# radius (the text's own history starts again at the undo: the keys pass to the
# document's).
# Usage: j35_text_follows_edits.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

ORIG=$SCENES/default.txt
# Line (1-based) of the first line of $1 that is exactly $2.
line_of() { awk -v want="$2" '$0 == want { print NR; exit }' "$1"; }
# Types $2 and Return at the start of line $1 of the scene text.
type_line_at() {
    read -r x y <<< "$(editor_xy "$1" 1 0.1)"
    click "$x" "$y"
    wait_state editor_cursor "^$1 1 focused$" 3
    type_text "$2"
    key Return
}
# Sphere 2's position line (the 2nd sphere block's `position`).
sphere2_position() { awk '/^  sphere \{/ { n++ } n == 2 && $1 == "position" { print; exit }' "$1"; }

start_viewer "$ORIG" --samples 4
click_item tab_Text
wait_state editor_grid '^[0-9]'

step "a comment typed at the top and applied"
type_line_at 1 "// first"
key ctrl+Return
wait_state title '^default.txt\* - raytracer-view$'

step "sphere 2 moved with the handle while the text is shown"
click $((ix + iw * 66 / 100)) $((iy + ih * 35 / 100))
wait_state selection "^object_2$"
click_item tab_Text  # (a pick shows the Objects tab; the user goes back to the text)
wait_state editor_grid '^[0-9]'
idle 0.3
hx=$(field handle 1) hy=$(field handle 2)
drag $((hx - 45)) "$hy" $((hx - 105)) "$hy"
wait_state message "^Moved by"
idle 0.5
shot 1-moved

step "a comment typed below the moved block, applied, saved"
torus=$(( $(line_of "$ORIG" "  torus {") + 1 ))
type_line_at "$torus" "// second"
key ctrl+Return
idle 0.5
save
moved=$(sphere2_position "$SCENE")
[ "$moved" != "$(sphere2_position "$ORIG")" ] || fail "the move did not reach the text: $moved"
# default.txt with the same edits, made here.
awk -v moved="$moved" '
    NR == 1 { print "// first" }
    $0 == "  torus {" { print "// second" }
    /^  sphere \{/ { n++ }
    n == 2 && $1 == "position" && !done { print moved; done = 1; next }
    { print }' "$ORIG" > "$OUT/want1.txt"
cmp "$SCENE" "$OUT/want1.txt" || fail "the saved text is not default.txt with the typed comments and the move: $(diff "$OUT/want1.txt" "$SCENE" | head)"
"$BIN/raytracer" --check "$SCENE" || fail "the saved text does not parse"
cp "$SCENE" "$OUT/saved1.txt"
shot 2-saved

step "radius 1.5 for sphere 1 in the Objects tab, then a comment typed in the Text tab"
click $((ix + iw * 37 / 100)) $((iy + ih * 55 / 100))
wait_state selection "^object_1$"
click_item tab_Objects
type_value radius 1.5
wait_state title '^default.txt\* - raytracer-view$'
click_item tab_Text
wait_state editor_grid '^[0-9]'
type_line_at 1 "// third"
key ctrl+Return
idle 0.5
save
awk '
    NR == 1 { print "// third" }
    /^  sphere \{/ { n++ }
    n == 1 && $1 == "radius" && !done { sub(/radius 1$/, "radius 1.5"); done = 1 }
    { print }' "$OUT/saved1.txt" > "$OUT/want2.txt"
cmp "$SCENE" "$OUT/want2.txt" || fail "the second save is not the first with the radius and the third comment: $(diff "$OUT/want2.txt" "$SCENE" | head)"
shot 3-third

step "Ctrl+Z outside the text: the typing, its apply and the radius undone; saved"
select_nothing
undos=""
for _ in 1 2 3 4 5; do
    key ctrl+z
    idle 0.5
    undos="$undos | $(state message)"
    [[ "$(state message)" == "Undid: Edit radius of sphere 1"* ]] && break
done
echo "undone:$undos"
wait_state message "^Undid: Edit radius of sphere 1" 1
save
cmp "$SCENE" "$OUT/saved1.txt" || fail "after the undo the text is not the first save's: $(diff "$OUT/saved1.txt" "$SCENE" | head)"
shot 4-undone

step "Ctrl+Y and Ctrl+Z typed in the text, which has no steps of its own: the document's redo and undo"
click_item tab_Text
wait_state editor_grid '^[0-9]'
read -r x y <<< "$(editor_xy 1 1 0.1)"
click "$x" "$y"
wait_state editor_cursor "^1 1 focused$" 3
key ctrl+y
wait_state message "^Redid: Edit radius of sphere 1" 3
wait_state title '^default.txt\* - raytracer-view$'
key ctrl+z
wait_state message "^Undid: Edit radius of sphere 1" 3
wait_state title '^default.txt - raytracer-view$'
wait_state editor_cursor "focused$" 1
echo PASS
