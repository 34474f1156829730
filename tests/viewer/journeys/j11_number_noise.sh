#!/bin/bash
# Journey: numbers the panels write into the text. The user selects the lamp in the
# outline and drags its "intensity" field (the colour follows, keeping its tint), then
# selects the sphere 2 and drags the red channel of its material colour; saves.
# Checks: the lamp's colour in the saved file is what the colour field shows, written
# as a person would type it (36.667, not 36.666666666666664); the sphere's green and
# blue stay as they were (0.8 0.7, not 0.800000011920929), its red has no more digits
# than the field shows; the picture equals `raytracer`'s render of the saved file (the
# scene holds exactly the numbers the text reads back to).
# Usage: j11_number_noise.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

# decimals NUMBER: how many digits follow its decimal point.
decimals() { awk -v n="$1" 'BEGIN { i = index(n, "."); print i ? length(n) - i : 0 }'; }

step "open default.txt, select the lamp and drag its intensity to the left"
start_viewer "$SCENES/default.txt" --samples 4
scroll_to "outline_light_1" $(region_mid outline)
click_item "outline_light_1"
wait_state selection "^light_1$"
wait_state "field_intensity" '^[0-9]'
read -r x y <<< "$(item_xy field_intensity)"
drag "$x" "$y" $((x - 90)) "$y"
idle 0.5
shot 1-intensity
shown=$(state light_colour)
echo "the colour field shows: $shown"

step "select sphere 2 (in the picture) and drag the red channel of its colour"
click $((ix + iw * 66 / 100)) $((iy + ih * 35 / 100))
wait_state selection "^object_2$"
idle 0.3
# The colour is below the sliders: scroll the properties (under the outline) to it.
read -r ox oy ow oh <<< "$(region outline)"
scroll_to "field_material_colour" $((ox + ow / 2)) $((oy + oh + 150))
read -r cx cy cw _ <<< "$(state field_material_colour)"
# The widget is three number fields, a swatch and the label: red is the first field.
rx=$((cx + cw / 8))
drag "$rx" $((cy + 8)) $((rx - 40)) $((cy + 8))
idle 0.5
shot 2-red
save
grep -n 'lamp {' "$SCENE"
grep -n 'colour 0.* 0.8 0.7\|reflection 0.5 scattering 0.5' "$SCENE"

step "the lamp's colour is written as shown"
read -r c1 c2 c3 <<< "$(awk '/lamp \{/ { for (i = 1; i <= NF; ++i) if ($i == "colour") { print $(i+1), $(i+2), $(i+3); exit } }' "$SCENE")"
[ "$c1" != 120 ] || fail "the intensity drag did not change the lamp"
for c in "$c1" "$c2" "$c3"; do
    [ "$(decimals "$c")" -le 3 ] || fail "the lamp's colour is written as '$c1 $c2 $c3': more digits than the field shows ($shown)"
done
[ "$(printf '%.3f %.3f %.3f' "$c1" "$c2" "$c3")" = "$shown" ] ||
    fail "the file holds colour $c1 $c2 $c3, the panel shows $shown"

step "the sphere's colour: red as shown, green and blue untouched"
line=$(grep -A1 'sphere {' "$SCENE" | grep 'reflection 0.5 scattering 0.5' || true)
echo "$line"
read -r r g b <<< "$(echo "$line" | awk '{ for (i = 1; i <= NF; ++i) if ($i == "colour") { print $(i+1), $(i+2), $(i+3); exit } }')"
[ "$g $b" = "0.8 0.7" ] || fail "green and blue were 0.8 0.7, the file now says $g $b"
[ "$r" != 0.9 ] || fail "the red drag did not change the colour"
[ "$(decimals "$r")" -le 3 ] || fail "red is written as $r: more digits than the field shows"

step "the picture is raytracer's render of the saved text"
select_nothing
picture_agrees 3-saved
echo PASS
