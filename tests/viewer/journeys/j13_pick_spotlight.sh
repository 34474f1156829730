#!/bin/bash
# Journey: a spotlight in the picture. A spotlight has no glow: the user selects it
# in the outline, sees its handle, right-clicks the handle; then clicks the sky, and
# right-clicks where the light is drawn.
# Checks: each right-click selects the spotlight (not the floor behind it) and the
# menu offers "Make it a lamp".
# Usage: j13_pick_spotlight.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

cat > "$OUT/spot.txt" <<'SCENE'
thing { sphere { material { colour 0.9 0.3 0.3 } position 6 0 1 radius 1 } }
special_thing {
  plane { material { colour 0.7 0.7 0.7 } point 1 0 0 0 point 2 1 0 0 point 3 0 1 0 point 4 0 0 1 }
}
light {
  lamp { colour 40 40 40 position 2 3 6 size 0.2 }
  spotlight { colour 4 4 4 position 6 -2.5 0.8 }
}
camera { position -2 0 2 centre 6 0 1 up 6 0 2 angle_x 60 angle_y 45 }
picture_size { x_max 640 y_max 480 }
end
SCENE

step "open the scene, select the spotlight in the outline"
start_viewer "$OUT/spot.txt" --samples 4
click_item "outline_light_2"
wait_state selection "^light_2$"
idle 0.3
[ "$(field handle 3)" = light ] || fail "no handle on the spotlight: $(field handle 1) $(field handle 2) $(field handle 3)"
hx=$(field handle 1) hy=$(field handle 2)
echo "the spotlight's handle is at $hx $hy"
shot 1-selected

step "right-click its handle"
click "$hx" "$hy" 3
idle 0.5
shot 2-handle-menu
wait_state selection "^light_2$" 2
wait_state "menu:Make_it_a_lamp" '^[0-9]' 2

step "close the menu, click the sky, right-click where the light is drawn"
click 1000 790  # outside the menu: it closes
wait_state popups "^none$" 3
select_nothing
wait_state render "done" 30
shot 3-nothing-selected
click "$hx" "$hy" 3
idle 0.5
shot 4-light-menu
wait_state selection "^light_2$" 2
wait_state "menu:Make_it_a_lamp" '^[0-9]' 2
echo PASS
