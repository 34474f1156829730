#!/bin/bash
# Journey: F frames the scene. The user opens a scene of one sphere lit by a lamp far
# away, and presses F (the pointer resting on the picture).
# Checks: the sphere fills the view (across the picture's middle row it is more than
# 40 % of the picture's height wide: its bounding box's corners are in view), instead
# of a dot framed together with the lamp.
# Usage: j18_frame_objects.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

cat > "$OUT/far-lamp.txt" <<'SCENE'
thing { sphere { material { colour 0.9 0.3 0.3 } position 10 0 0 radius 1 } }
light { lamp { colour 3000 3000 3000 position -20 30 20 size 0.1 } }
camera { position 0 0 0 centre 10 0 0 up 10 0 1 angle_x 60 angle_y 45 }
picture_size { x_max 640 y_max 480 }
end
SCENE

# The sphere's width on the picture's middle row (0 if it is not there).
middle_width() {
    "$TOOL" ink "$1" "$ix" $((iy + ih / 2 - 2)) "$iw" 4 | awk '{ print ($1 < 0 ? 0 : $2 - $1 + 1) }'
}

step "open the scene"
start_viewer "$OUT/far-lamp.txt" --samples 4
wait_state render "done" 30
idle 0.5
shot 1-opened
echo "the sphere is $(middle_width "$OUT/1-opened.png") pixels wide"

step "F"
xdotool mousemove $((ix + iw / 2)) $((iy + ih / 3))
key f
idle 0.5
wait_state render "done" 30
idle 0.5
shot 2-framed
w=$(middle_width "$OUT/2-framed.png")
echo "after F the sphere is $w pixels wide (the picture is $ih high)"
[ "$w" -gt $((ih * 4 / 10)) ] || fail "after F the sphere is $w pixels wide: the lamp was framed too"
echo PASS
