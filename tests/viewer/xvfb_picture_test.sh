#!/bin/bash
# The picture tools in the real raytracer-view window under Xvfb, driven with xdotool:
#  1. hovering the picture prints the readout of the pixel under the cursor (the
#     status line, echoed on stdout with --verbose): the pixel the fitted picture
#     puts there, its linear colour, and the object its ray hits with the distance;
#  2. key 1 zooms to 1:1: the 320x240 picture, smaller than the area, is shown whole
#     and centred in it (wherever the cursor is), the readout names the pixel under
#     the cursor by that placement, and moving the cursor by N screen pixels moves the
#     readout by exactly N picture pixels; the picture's centre pixel reads
#     "object 1 (sphere) at 9" (camera 9 units from it);
#  3. K keeps a snapshot; the sphere's material changes on disk (red -> blue) and the
#     window reloads it; B shows snapshot | live: left of the split line the sphere is
#     red (the snapshot), right of it blue (live); B again: the difference image is
#     bright on the sphere and black on the unchanged floor.
# Screenshots are kept in OUT_DIR to look at.
# Usage: xvfb_picture_test.sh BIN_DIR OUT_DIR
set -euo pipefail
# shellcheck source=xvfb_start.sh
. "$(dirname "$0")/xvfb_start.sh" "$@"

rm -rf "$OUT"/*.png "$OUT/config"

# A red sphere of radius 1 straight ahead, 10 units from the camera: the picture's
# centre pixel hits it at distance 9. A floor below, lit by one lamp.
SCENE=$OUT/picture.txt
write_scene() {
    cat > "$SCENE" <<EOF
thing { sphere { material { colour $1 } position 10 0 1 radius 1 } }
special_thing { chess_plane { point 1 0 0 0 point 2 1 0 0 point 3 0 1 0 point 4 0 0 5 } }
light { lamp { position 3 -3 6 colour 40 40 40 size 0.2 } }
camera { position 0 0 1 centre 10 0 1 up 10 0 2 angle_x 40 angle_y 30 }
picture_size { x_max 320 y_max 240 }
end
EOF
}
write_scene "0.9 0.1 0.1"

LAYOUT=$OUT/viewer.out   # --verbose --print-layout: the layout and readout lines
# The last readout line.
readout() { grep '^readout: ' "$OUT/viewer.out" | tail -n 1; }
# Waits until the last readout line matches a pattern (grep -E).
wait_readout() {
    local re=$1
    wait_until 'readout | grep -Eq "$re"' 10 "a readout matching '$re'"
}
wait_message() {
    local m=$1
    wait_until 'grep -q "^message: $m" "$OUT/viewer.out"' 10 "the message '$m'"
}
# The live readout of the sphere's pixel reads blue; else the pointer moves off it and
# back, for a new readout.
sphere_reads_blue() {
    R=$(readout)
    read -r RR RG RB <<< "$(echo "$R" | awk '{ print $7, $8, $9 }')"
    awk -v r="$RR" -v b="$RB" 'BEGIN { exit !(b > 2 * r) }' && return 0
    xdotool mousemove "$((CX + 1))" "$CY"
    xdotool mousemove "$CX" "$CY"
    return 1
}
# Mean colour "R G B" (0..255) of a region of a screenshot.
mean() {
    convert "$OUT/$1.png" -crop "$4x$5+$2+$3" +repage -scale '1x1!' \
        -format '%[fx:int(255*r+0.5)] %[fx:int(255*g+0.5)] %[fx:int(255*b+0.5)]' info:
}

step "start the viewer"
cd "$OUT"
"$BIN/raytracer-view" "$SCENE" --size 1280x800 --samples 2 --verbose --print-layout \
    > "$OUT/viewer.out" 2> "$OUT/viewer.err" &
VIEWER_PID=$!
WID=$(timeout 30 xdotool search --sync --name 'picture.txt' | head -1) || fail "no window appeared"
wait_until 'grep -q "first picture on screen" "$OUT/viewer.err"' 10 "the first picture on the screen"
wait_until '[[ "$(state render)" == *done* ]]' 30 "the render to finish"
IX=$(field image 1); IY=$(field image 2); IW=$(field image 3); IH=$(field image 4)
echo "image region ${IW}x${IH} at $IX,$IY"
[ "$IW" -gt 320 ] || fail "expected the 320x240 picture fitted larger than itself, got ${IW}x${IH}"

step "hover: the readout names the pixel the fitted picture shows there"
# A point a third of the way in: which picture pixel it shows follows from the
# letterboxing alone (the picture spans IW x IH from IX, IY).
MX=$((IX + IW / 3)); MY=$((IY + IH * 2 / 3))
EX=$(( (MX - IX) * 320 / IW )); EY=$(( (MY - IY) * 240 / IH ))
pointer_to "$MX" "$MY"
pointer_to "$((MX + 1))" "$MY"
pointer_to "$MX" "$MY"
wait_readout "^readout: x $EX y $EY .*plane 1 \(chess_plane\) at "
echo "$(readout)"

step "1:1: the picture whole and centred, then exact pixel steps"
xdotool key 1
wait_message "Zoom 1:1"
wait_until '[ "$(field image 3) $(field image 4)" = "320 240" ]' 5 "the picture drawn at 320x240"
shot one-to-one
read -r AX AY AW AH <<< "$(region area)"
read -r ZX ZY ZW ZH <<< "$(region image)"
[ "$ZW $ZH" = "320 240" ] || fail "1:1 should show the picture at 320x240, it is ${ZW}x${ZH}"
[ $((2 * ZX + ZW - 2 * AX - AW)) -le 1 ] && [ $((2 * AX + AW - 2 * ZX - ZW)) -le 1 ] &&
    [ $((2 * ZY + ZH - 2 * AY - AH)) -le 1 ] && [ $((2 * AY + AH - 2 * ZY - ZH)) -le 1 ] ||
    fail "1:1 should centre the picture in the area ($AX $AY $AW $AH), it is at $ZX $ZY"
# The pixel under the cursor is where that placement puts it.
pointer_to "$((MX + 1))" "$MY"
pointer_to "$MX" "$MY"
PX=$((MX - ZX)); PY=$((MY - ZY))
wait_readout "^readout: x $PX y $PY "
xdotool mousemove "$((MX + 7))" "$((MY - 5))"
wait_readout "^readout: x $((PX + 7)) y $((PY - 5)) "
# The picture's centre pixel: the sphere, 9 units away, red.
CX=$((MX + 160 - PX)); CY=$((MY + 120 - PY))
xdotool mousemove "$CX" "$CY"
wait_readout "^readout: x 160 y 120 .* object 1 \(sphere\) at 9(\.0+)?$"
R=$(readout)
echo "$R"
read -r RR RG RB <<< "$(echo "$R" | awk '{ print $7, $8, $9 }')"
awk -v r="$RR" -v g="$RG" -v b="$RB" 'BEGIN { exit !(r > 2 * g && r > 2 * b && r > 0.05) }' \
    || fail "the sphere's pixel should read red, got RGB $RR $RG $RB"
# At 1:1 the sphere (radius 1 at distance 10, 40 degrees wide over 320 pixels) is
# about 46 pixels across: a 20x20 square at the cursor is all sphere.
read -r r g b <<< "$(mean one-to-one $((CX - 10)) $((CY - 10)) 20 20)"
[ "$r" -gt $((2 * g)) ] || fail "at 1:1 the centre of the picture is not the red sphere ($r $g $b)"

step "snapshot, a material change on disk, A/B"
xdotool key k
wait_message "Kept snapshot 1"
write_scene "0.1 0.1 0.9"
# The window reloads the file (no unsaved edits); the live readout turns blue.
wait_until sphere_reads_blue 10 "the reloaded sphere to read blue"
wait_until '[[ "$(state render)" == *done* ]]' 30 "the reloaded scene's render to finish"
# Still at 1:1, so that snapshot and live picture are the same 320x240 film: picture
# pixel (160, 120) is at (CX, CY), and the split line starts at the picture's middle.
pointer_to 1000 700  # over the sidebar, away from the picture
xdotool key b
wait_message "Compare: snapshot"
input_seen
shot ab-split
read -r lr lg lb <<< "$(mean ab-split $((CX - 14)) $((CY - 4)) 8 8)"
read -r rr rg rb <<< "$(mean ab-split $((CX + 6)) $((CY - 4)) 8 8)"
echo "left of the split (snapshot): $lr $lg $lb; right (live): $rr $rg $rb"
[ "$lr" -gt $((2 * lb)) ] || fail "left of the split should be the red snapshot ($lr $lg $lb)"
[ "$rb" -gt $((2 * rr)) ] || fail "right of the split should be the blue live picture ($rr $rg $rb)"

xdotool key b
wait_message "Compare: difference"
input_seen
shot ab-difference
read -r dr dg db <<< "$(mean ab-difference $((CX - 8)) $((CY - 8)) 16 16)"
read -r fr fg fb <<< "$(mean ab-difference $((CX - 140)) $((CY + 100)) 20 12)"
echo "difference on the sphere: $dr $dg $db; on the floor: $fr $fg $fb"
[ $((dr + db)) -gt 200 ] || fail "the difference image should be bright where the sphere changed ($dr $dg $db)"
[ $((fr + fg + fb)) -lt 30 ] || fail "the difference image should be black where nothing changed ($fr $fg $fb)"

quit_viewer
echo "picture tools under Xvfb: ok"
