#!/bin/bash
# Journey: a model file opened on its own. The user starts the viewer on
# models/bunny.obj, saves the new scene beside the folder, moves the bunny with the
# handle's red (x) arrow, right-clicks the floor for Add here > model... and adds a
# second one, then replaces the model file on disk.
# Checks: the window shows a new unsaved scene named after the model (the bunny on a
# floor: raytracer's picture of the saved text); the handle moves the mesh (its
# position's x grows in the saved text); the added mesh names the file from the
# scene's folder; a changed model file is read again and the picture follows it, also
# after undo; a cancelled Add here > model... leaves no point behind for File > Add model.
# Usage: j21_open_model.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

MODELS=$(cd "$SCENES/models" && pwd)
mkdir -p "$OUT/models"
cp "$MODELS/bunny.obj" "$OUT/models/bunny.obj"
meshes() { grep -c '^[[:space:]]*mesh[[:space:]]*{' "$SCENE" || true; }
# open_add_here X Y: right-click at image point (X, Y), Add here > model...: the dialog.
open_add_here() {
    click "$1" "$2" 3
    hover_item "menu:Add_here"
    click_item "menu:model"
    wait_state popups "Add model"
}
# choose_model N: types the bunny's path into the open Add model dialog; mesh N selected.
choose_model() {
    wait_state browser_field "^active$"
    key ctrl+a
    type_text "$OUT/models/bunny.obj"
    key Return
    wait_state message "^Added bunny.obj"
    wait_state selection "^object_$1$"
}

step "raytracer-view models/bunny.obj: a new scene called bunny.txt"
open_model models/bunny.obj bunny.txt --samples 4
wait_stable 0-opened

step "Save As bunny.txt in the folder above the model's"
key ctrl+shift+s
wait_state popups "Save scene as"
wait_state browser_field "^active$"
key ctrl+a
type_text "$OUT/bunny.txt"
key Return
wait_state message "^Saved $OUT/bunny.txt"
SCENE=$OUT/bunny.txt
[ "$(meshes)" = 1 ] || fail "expected one mesh in the saved scene: $(cat "$SCENE")"
grep -qF "file \"$OUT/models/bunny.obj\"" "$SCENE" || fail "the mesh does not name the model: $(grep file "$SCENE")"
picture_agrees 1-saved

step "select the bunny (the picture's centre) and drag the red arrow right"
click $((ix + iw / 2)) $((iy + ih / 2))
wait_state selection "^object_1$"
idle 0.5
hx=$(field handle 1) hy=$(field handle 2)
echo "handle at $hx $hy"
x0=$(awk '/position/ && !/camera/ { print $2; exit }' "$SCENE")
drag $((hx + 45)) "$hy" $((hx + 165)) "$hy"
idle 0.5
[ "$(field handle 1)" -gt $((hx + 60)) ] || fail "the handle did not follow the drag ($hx -> $(field handle 1))"
save
grep -A3 '^ *mesh' "$SCENE"
x1=$(awk '/^ *position/ { print $2; exit }' "$SCENE")
awk -v x="$x1" 'BEGIN { exit !(x > 0.01) }' || fail "the mesh's x is '$x1' (was '$x0'), expected it to grow from 0"

step "right-click the floor in front: Add here > model... models/bunny.obj"
open_add_here $((ix + iw * 25 / 100)) $((iy + ih * 88 / 100))
choose_model 2
save
[ "$(meshes)" = 2 ] || fail "expected two meshes in the saved text, found $(meshes)"
grep -qF 'file "models/bunny.obj"' "$SCENE" || fail "the added mesh does not name models/bunny.obj: $(grep file "$SCENE")"
select_nothing
picture_agrees 2-added

step "the model file changes on disk: read again"
cp "$(dirname "$MODELS")/../tests/models/cube.obj" "$OUT/models/bunny.obj"
wait_state message "^Read the scene's models and textures again" 10
wait_state render "done" 60
picture_agrees 3-reloaded
changed=$("$TOOL" diff "$OUT/2-added-shown.png" "$OUT/3-reloaded-shown.png" $IMAGE)
echo "fraction of the picture changed: $changed"
awk -v f="$changed" 'BEGIN { exit !(f > 0.02) }' || fail "only $changed of the picture changed: the new model is not shown"

step "Add here > model... on the left, cancelled; then File > Add model...: in the middle, not where the menu was"
open_add_here $((ix + iw * 8 / 100)) $((iy + ih * 90 / 100))
key Escape
wait_state popups "^none$"
click_item "menu:File"
click_item "menu:Add_model"
wait_state popups "Add model"
choose_model 3
idle 0.5
echo "the new mesh's handle at $(field handle 1) $(field handle 2) in the image at $ix $iy ${iw}x$ih"
[ "$(field handle 1)" -gt $((ix + iw * 25 / 100)) ] || fail "the mesh went where the cancelled menu was opened"

step "undo three times (the adds, the move): the model as it is on disk now, where it was"
key ctrl+z
key ctrl+z
key ctrl+z
wait_state message "^Undid: Move"
save
[ "$(meshes)" = 1 ] || fail "expected one mesh after the undos, found $(meshes)"
x2=$(awk '/^ *position/ { print $2; exit }' "$SCENE")
[ "$x2" = "$x0" ] || fail "the mesh's x is '$x2' after undoing the move, expected '$x0'"
picture_agrees 4-undone
quit_viewer
echo PASS
