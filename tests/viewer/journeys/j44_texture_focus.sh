#!/bin/bash
# Journey: a model with its materials, made into a picture worth showing. The user
# opens an OBJ whose MTL file gives its faces a colour with a highlight and a texture,
# saves the new scene, adds a lamp and drags its radius (a sphere light: soft
# shadows), chooses a texture for the floor through the file browser (first a file
# that is no image), types names into the texture field and undoes, lets another
# program replace the texture file, focuses on the model with the picture's menu,
# opens the lens, and renders to a file.
# Checks: the picture shows the MTL's colours (raytracer's render of the saved text);
# the radius is in the saved text; the file that is no image gets the texture
# reader's message under the field and the scene keeps its floor; the chosen texture
# is named from the scene's folder and is one undo step; the replaced file is read
# again and the picture follows it; the focus distance is the
# model's; the rendered file equals raytracer's render of the saved scene, byte for
# byte.
# Usage: j44_texture_focus.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

# A pyramid: two faces of an MTL colour with a highlight, two textured.
mkdir -p "$OUT/model" "$OUT/textures"
cat > "$OUT/model/pyramid.obj" <<'OBJ'
mtllib pyramid.mtl
v -1 0 -1
v 1 0 -1
v 1 0 1
v -1 0 1
v 0 1.6 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vt 0.5 0.5
usemtl red
f 1/1 5/5 2/2
f 2/2 5/5 3/3
usemtl pictured
f 3/3 5/5 4/4
f 4/4 5/5 1/1
OBJ
cat > "$OUT/model/pyramid.mtl" <<'MTL'
newmtl red
Kd 0.8 0.12 0.1
Ks 0.6 0.6 0.6
Ns 80
newmtl pictured
Kd 1 1 1
map_Kd faces.png
MTL
cp "$SCENES/textures/uv-grid.png" "$OUT/model/faces.png"
cp "$SCENES/textures/beach-ball.png" "$OUT/textures/floor.png"
printf 'this is no image\n' > "$OUT/textures/notes.png"

step "raytracer-view model/pyramid.obj; Save As scene.txt"
open_model model/pyramid.obj pyramid.txt --samples 2
key ctrl+shift+s
wait_state popups "Save scene as"
wait_state browser_field "^active$"
key ctrl+a
type_text "$OUT/scene.txt"
key Return
wait_state message "^Saved $OUT/scene.txt"
SCENE=$OUT/scene.txt
picture_agrees 1-opened
# The MTL's colours: red faces, not one colour of the scene's own for the whole mesh.
red=$("$TOOL" near "$OUT/1-opened-shown.png" $IMAGE 170 30 25 85)
echo "red pixels: $red"
[ "$red" -gt $((iw * ih / 50)) ] || fail "the model's red faces are not shown ($red red pixels)"

step "right-click the floor on the right: Add here > lamp; drag its radius"
click $((ix + iw * 85 / 100)) $((iy + ih * 80 / 100)) 3
hover_item "menu:Add_here"
click_item "menu:lamp"
wait_state selection "^light_2$"
wait_state field_radius '^[0-9]+ [0-9]+ [0-9]+ [0-9]+$' 5
read -r fx fy fw fh <<< "$(state field_radius)"
drag $((fx + fw / 2)) $((fy + fh / 2)) $((fx + fw / 2 + 40)) $((fy + fh / 2))
idle 0.5
radius=$(state value_radius)
echo "radius after the drag: $radius"
awk -v r="$radius" 'BEGIN { exit !(r > 0) }' || fail "dragging the radius field left it at '$radius'"
save
grep -Eq "^ *radius $radius\$" "$SCENE" || fail "the lamp's radius $radius is not in the saved text: $(grep -n radius "$SCENE")"
shot 2-lamp
select_nothing
picture_agrees 2-lamp

step "select the floor; its texture through the browser: a file that is no image first"
click $((ix + iw * 15 / 100)) $((iy + ih * 92 / 100))
wait_state selection "^plane_1$"
# (The properties scroll: the wheel over the first point's field.)
read -r px py <<< "$(item_xy field_point_1)"
scroll_to button_material_1_texture_browse "$px" "$py"
wheel_down "to bring the whole row in sight"
choose_texture() {
    click_item button_material_1_texture_browse
    wait_state popups "Choose texture"
    wait_state browser_field "^active$"
    key ctrl+a
    type_text "$1"
    key Return
    wait_state popups "^none$"
}
choose_texture "$OUT/textures/notes.png"
wait_state field_message "^material 1: textures/notes.png: " 5
echo "said: $(state field_message)"
shot 3-not-an-image
save
grep -q 'texture "' "$SCENE" && fail "a file that is no image was written into the scene: $(grep -n texture "$SCENE")"
choose_texture "$OUT/textures/floor.png"
wait_state message "^Texture $OUT/textures/floor.png set" 5
wait_state value_material_1_texture "^textures/floor.png$" 5
save
grep -q 'texture "textures/floor.png"' "$SCENE" || fail "the floor's texture is not in the saved text: $(grep -n texture "$SCENE")"

step "type names into the texture field: one of no file, then none; undo"
click_item field_material_1_texture
key ctrl+a
type_text "textures/none.png"
key Return
wait_state field_message "^material 1: textures/none.png: " 5
wait_state value_material_1_texture "^textures/floor.png$" 2
click_item field_material_1_texture
key ctrl+a BackSpace Return
wait_state value_material_1_texture "^$" 5
save
grep -q 'texture "' "$SCENE" && fail "the texture is still in the saved text: $(grep -n texture "$SCENE")"
key ctrl+z
wait_state value_material_1_texture "^textures/floor.png$" 5
save
grep -q 'texture "textures/floor.png"' "$SCENE" || fail "undo did not bring the texture back: $(grep -n texture "$SCENE")"
select_nothing
picture_agrees 4-textured

step "another program replaces the floor's texture file: read again"
cp "$SCENES/textures/uv-grid.png" "$OUT/textures/floor.png"
wait_state message "^Read the scene's models and textures again" 10
picture_agrees 5-reloaded
changed=$("$TOOL" diff "$OUT/4-textured-shown.png" "$OUT/5-reloaded-shown.png" $IMAGE)
echo "fraction of the picture changed: $changed"
awk -v f="$changed" 'BEGIN { exit !(f > 0.05) }' || fail "only $changed of the picture changed: the new texture is not shown"

step "right-click the model: Focus here; open the lens"
click $((ix + iw / 2)) $((iy + ih / 2)) 3
click_item "menu:Focus_here"
wait_state popups "^none$"
grep -Eq "focus_distance [0-9.]+" "$SCENE" || save
grep -E "focus_distance" "$SCENE" || fail "no focus distance in the saved text"
select_nothing
[ -n "$(state field_camera_aperture)" ] || click_item camera_lens_section
type_value camera_aperture 0.08 aperture
idle 0.5
save
grep -Eq "aperture 0.08" "$SCENE" || fail "the aperture is not in the saved text: $(grep -n aperture "$SCENE")"
wait_state render "done" 60
shot 6-focused

step "Render to file: the file equals raytracer's render of the saved scene"
key ctrl+r
wait_state render_dialog "^setup"
wait_state render_field "^active$"
key ctrl+a
type_text "$OUT/render.ppm"
key Return
wait_state render_dialog "^saved $OUT/render.ppm" 120
key Escape
wait_state popups "^none$" 3
# shellcheck disable=SC2046
"$BIN/raytracer" --quiet $(state render_settings) "$SCENE" "$OUT/render-ref.ppm" ||
    fail "raytracer could not render the saved scene"
cmp "$OUT/render.ppm" "$OUT/render-ref.ppm" || fail "the viewer's render to file differs from raytracer's"
quit_viewer
echo PASS
