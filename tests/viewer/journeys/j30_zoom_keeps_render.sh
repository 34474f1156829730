#!/bin/bash
# Journey: zoom and pan only look at the render, and Save Image writes the scene's
# picture. The user opens default.txt (picture_size 640x480) and waits for the render
# to finish, zooms in one Ctrl+wheel notch over the picture, pans it (Ctrl+right drag),
# presses 1 with the pointer near the area's corner, then Home, resting after each;
# saves the image (Ctrl+P), zooms in again and saves it once more.
# Checks: the film is the scene's 640x480 picture from the start, and zoom, pan, 1 and
# Home keep that very render with all its samples (no restart: the same generation,
# 16 spp, done); after 1 the picture is whole and centred, one screen pixel a picture
# pixel, and the screen there equals `raytracer --samples 16` of the scene; both saved
# images are that picture, byte for byte, whatever the zoom.
# Usage: j30_zoom_keeps_render.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

# One Ctrl+wheel notch in at (X, Y), the keys and the wheel as separate events: each
# taken by the viewer (the zoom changed) before the next.
ctrl_wheel_in() {
    local zoom
    zoom=$(state zoom)
    pointer_to "$1" "$2"
    xdotool keydown ctrl
    input_seen
    xdotool click 4
    wait_until '[ "$(state zoom)" != "$zoom" ]' 3 "Ctrl+wheel to zoom in (zoom $zoom)"
    xdotool keyup ctrl
}

# The render seen at the start, still on the screen after a rest with no input.
same_render() {
    idle 1.5
    [ "$(state film)" = "$film" ] || fail "$1: the render was restarted or lost samples: '$(state film)', was '$film'"
    wait_state render "^16 done" 1
}

# Save Image (Ctrl+P) to $1; waits for the status line to say it was written.
save_image() {
    key ctrl+p
    wait_state popups "Save image" 5
    key ctrl+a
    type_text "$1"
    key Return
    wait_state message "^Wrote $1 " 10
    echo "$(state message)"
}

step "open default.txt and let the render finish"
start_viewer "$SCENES/default.txt" --samples 16 --aa-threshold off
wait_state render "^16 done" 120
film=$(state film)
echo "film: $film"
[[ "$film" == "640x480 16 spp "* ]] || fail "the picture frame renders '$film', not the scene's 640x480 picture"
"$BIN/raytracer" --quiet --samples 16 "$SCENE" "$OUT/ref.png" || fail "raytracer could not render the scene"
shot 1-fitted

step "one Ctrl+wheel notch in over the picture"
ctrl_wheel_in $((ix + iw / 3)) $((iy + ih / 3))
wait_state zoom '^[0-9]' 3
echo "zoom $(state zoom)"
same_render "Ctrl+wheel"
shot 2-zoomed

step "pan the zoomed picture (Ctrl+right drag)"
before=$(region image)
pointer_to $((ix + iw / 2)) $((iy + ih / 2))
xdotool keydown ctrl
input_seen
xdotool mousedown 3
wait_state pointer " down$"
for i in $(seq 1 12); do
    pointer_to $((ix + iw / 2 + i * 8)) $((iy + ih / 2 + i * 5))
done
shot 3-mid-pan
xdotool mouseup 3
wait_state pointer "^[0-9]+ [0-9]+( ui)?$"
xdotool keyup ctrl
wait_state popups '^none$' 2
[ "$(region image)" != "$before" ] || fail "the pan did not move the picture ($before)"
same_render "panning"

step "1 with the pointer near the area's corner: the whole picture, centred, at 1:1"
read -r ax ay aw ah <<< "$(region area)"
xdotool mousemove $((ax + 25)) $((ay + 25))
key 1
wait_state zoom '^1\.0+$' 3
wait_until '[ "$(field image 3)" = 640 ]' 2 "the picture 640 pixels wide at 1:1"
read -r zx zy zw zh <<< "$(region image)"
[ "$zw $zh" = "640 480" ] || fail "at 1:1 the picture should be 640x480 on the screen, it is ${zw}x${zh}"
dx=$((2 * zx + zw - 2 * ax - aw)) dy=$((2 * zy + zh - 2 * ay - ah))
[ "${dx#-}" -le 1 ] && [ "${dy#-}" -le 1 ] ||
    fail "at 1:1 the picture is at $zx,$zy, not centred in the area ($ax $ay $aw $ah)"
same_render "1:1"
pointer_to $((ax + aw + 50)) $((ay + 50))  # off the picture: no readout over it
wait_state readout '^none$' 5
IMAGE="$zx $zy $zw $zh"
wait_stable 4-one-to-one
"$TOOL" match "$OUT/4-one-to-one.png" "$zx" "$zy" 640 480 "$OUT/ref.png" ||
    fail "at 1:1 the screen differs from raytracer's picture of the scene"

step "Home: fitted again, the same render"
key Home
wait_state zoom '^fit$' 3
same_render "Home"

step "save the image, fitted and zoomed in: the scene's picture both times"
save_image "$OUT/saved.png"
cmp "$OUT/saved.png" "$OUT/ref.png" || fail "the saved image is not raytracer's 640x480 picture of the scene"
ctrl_wheel_in $((ix + iw / 2)) $((iy + ih / 2))
ctrl_wheel_in $((ix + iw / 2)) $((iy + ih / 2))
wait_state zoom '^[0-9]' 3
save_image "$OUT/saved-zoomed.png"
cmp "$OUT/saved-zoomed.png" "$OUT/ref.png" || fail "zoomed in, the saved image is not the scene's picture"
same_render "saving"
echo PASS
