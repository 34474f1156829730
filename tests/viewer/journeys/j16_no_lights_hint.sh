#!/bin/bash
# Journey: a scene without lights. The user opens a scene with a floor and no light,
# right-clicks the floor and adds a sphere, which renders black.
# Checks: the viewer says why: the status bar names the missing lights when the sphere
# is added, and the outline's Lights list says how to add one.
# Usage: j16_no_lights_hint.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

cat > "$OUT/dark.txt" <<'SCENE'
special_thing {
  plane { material { colour 0.7 0.7 0.7 } point 1 0 0 0 point 2 1 0 0 point 3 0 1 0 point 4 0 0 1 }
}
camera { position -2 0 2 centre 6 0 1 up 6 0 2 angle_x 60 angle_y 45 }
picture_size { x_max 640 y_max 480 }
end
SCENE

step "open a scene without lights"
start_viewer "$OUT/dark.txt" --samples 4
wait_state render "done" 30
shot 1-opened
hint=$(state outline_hint)
echo "outline: $hint"
[[ "$hint" == *"No lights"* && "$hint" == *"lamp"* ]] || fail "the outline does not say the scene has no lights: '$hint'"

step "right-click the floor: Add here > sphere"
click $((ix + iw / 2)) $((iy + ih * 80 / 100)) 3
hover_item "menu:Add_here"
click_item "menu:sphere"
wait_state selection "^object_1$" 5
wait_state render "done" 30
shot 2-added
msg=$(state message)
echo "status: $msg"
[[ "$msg" == "Added a sphere"* && "$msg" == *"no light"* ]] || fail "adding an object to a scene without lights says nothing of them: '$msg'"
echo PASS
