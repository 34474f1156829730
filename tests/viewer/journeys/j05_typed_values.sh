#!/bin/bash
# Journey: typing a value into a panel field. With sphere 1 selected the user
# Ctrl+clicks its radius and types 1e16 and Enter, then "abc" and Enter, then 1.5 and
# Enter, then (double-click) 1.25 and clicks elsewhere instead of pressing Enter.
# Checks: the too-large and the non-number text are refused with the parser's message
# and change nothing (no "*", Save writes the file unchanged: never the partial "1e1");
# 1.5 and 1.25 apply whole, and the saved file and raytracer's picture of it agree
# with the picture on the screen. Last, in the Render tab, 256 typed into samples per
# pixel applies on Enter only (never 2, then 25).
# Usage: j05_typed_values.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

start_viewer "$SCENES/default.txt" --samples 4 --select "object 1"
wait_state field_radius "^[0-9]"
read -r fx fy fw fh <<< "$(state field_radius)"
rx=$((fx + fw / 4)) ry=$((fy + fh / 2))
radius_of_sphere_1() { awk '/^  sphere \{/ { n++ } n == 1 && $1 == "radius" { print $2; exit }' "$SCENE"; }
type_radius() {  # $1: how the field is opened (ctrl or double), $2: text
    if [ "$1" = ctrl ]; then xdotool mousemove $rx $ry keydown ctrl click 1 keyup ctrl
    else xdotool mousemove $rx $ry click --repeat 2 --delay 80 1; fi
    # (the text field takes the keyboard within a frame or two)
    wait_state typing "^radius active$"
    type_text "$2"
}

step "1e16 and Enter: refused as out of range, nothing changes"
type_radius ctrl 1e16
key Return
wait_state field_message "radius: number '1e\+?16' is out of range"
idle 0.5
wait_state title '^default.txt - raytracer-view$' 1
save
cmp -s "$SCENE" "$SCENES/default.txt" || fail "the refused value reached the file: radius $(radius_of_sphere_1)"

step "abc and Enter: refused as no number, not dropped silently"
type_radius ctrl abc
key Return
wait_state field_message "radius: expected a number, got 'abc'"
wait_state title '^default.txt - raytracer-view$' 1

step "1.5 and Enter: applied whole"
type_radius ctrl 1.5
idle 0.5
wait_state title '^default.txt - raytracer-view$' 1  # not yet: typing applies nothing
key Return
wait_state title '^default.txt\* - raytracer-view$'
save
[ "$(radius_of_sphere_1)" = 1.5 ] || fail "radius in the file is $(radius_of_sphere_1), expected 1.5"

step "double-click, 1.25, then a click elsewhere: applied on leaving the field"
type_radius double 1.25
click $((fx + fw / 2)) $((fy - 60))
wait_state title '^default.txt\* - raytracer-view$'
save
[ "$(radius_of_sphere_1)" = 1.25 ] || fail "radius in the file is $(radius_of_sphere_1), expected 1.25"
select_nothing
picture_agrees typed
step "Render tab: 256 typed into samples per pixel applies on Enter, not a digit at a time"
click_item tab_Render
wait_state field_samples '^-?[0-9]+ '
read -r sx sy sw sh <<< "$(state field_samples)"
xdotool mousemove $((sx + sw / 4)) $((sy + sh / 2)) keydown ctrl click 1 keyup ctrl
wait_state typing "^samples per pixel active$"
before=$(state render_settings)
type_text "256"
idle 0.5
[ "$(state render_settings)" = "$before" ] || fail "typing applied a partial value: $(state render_settings) (was $before)"
key Return
wait_state render_settings "^--samples 256( |$)"
shot 5-render-tab
echo PASS
