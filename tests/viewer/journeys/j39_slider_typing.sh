#!/bin/bash
# Journey: typing a value into a material slider. With sphere 1 of the default scene
# selected (reflection 0.1, refractive_index 1.5) the user Ctrl+clicks near the left
# end of the reflection slider and presses Escape; Ctrl+clicks mid-slider and types
# "abc" and Enter; Ctrl+clicks refractive_index and types 0.5 and Enter; undoes.
# Checks: the Ctrl+click opens the text field at the value as it was (the slider never
# takes the value under the pointer), Escape changes nothing, "abc" gets the parser's
# message and changes nothing; 0.5 (below the format's least refractive index) is one
# undo step to 1 with a note saying so, never a step through the value under the
# pointer, and one undo goes back to 1.5. A negative reflection is warned about.
# Usage: j39_slider_typing.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

start_viewer "$SCENES/default.txt" --samples 4 --select "object 1"
wait_state field_material_reflection '^-?[0-9]+ -?[0-9]+ [0-9]+ [0-9]+$' 10
wait_state value_material_reflection '^0\.1$' 1
wait_state value_material_refractive_index '^1\.5$' 1
depth=$(state undo_depth)
[ "$depth" = 0 ] || fail "undo depth '$depth' at the start"

# ctrl_click FIELD FRACTION: Ctrl+click the material slider FIELD at FRACTION of its
# width; waits until its text field takes the keyboard.
ctrl_click() {
    local x y w h
    read -r x y w h <<< "$(state "field_material_$1")"
    xdotool mousemove "$(awk -v x="$x" -v w="$w" -v f="$2" 'BEGIN { printf "%d", x + w * f }')" $((y + h / 2)) \
        keydown ctrl click 1 keyup ctrl
    wait_state typing "^$1 active$"
}
unchanged() {
    wait_state value_material_reflection '^0\.1$' 1
    wait_state value_material_refractive_index '^1\.5$' 1
    wait_state title '^default.txt - raytracer-view$' 1
    wait_state undo_depth '^0$' 1
}

step "Ctrl+click near the slider's left end: the field opens at 0.1; Escape changes nothing"
ctrl_click reflection 0.03
idle 0.3
unchanged
shot 1-typing-open
key Escape
wait_state typing '^$' 5
idle 0.3
unchanged

step "Ctrl+click mid-slider, abc and Enter: the parser's message, nothing changes"
ctrl_click reflection 0.5
type_text abc
key Return
wait_state field_message "reflection: expected a number, got 'abc'" 5
idle 0.3
unchanged
shot 2-abc-refused

wait_state typing '^$' 5

step "refractive_index: 0.5 and Enter is one step, to 1, with a note"
read -r px py _ _ <<< "$(state field_material_reflection)"
# (until the field after it shows too: the field whole, above the window's edge)
scroll_to field_material_specular $((px + 20)) "$py"
idle 0.3
ctrl_click refractive_index 0.5
type_text 0.5
key Return
wait_state value_material_refractive_index '^1$' 5
wait_state field_message "refractive_index 0\.5 is below the least value, 1: set to 1" 5
wait_state title '^default.txt\* - raytracer-view$' 5
wait_state undo_depth '^1$' 5
shot 3-refractive-index
key ctrl+z
wait_state value_material_refractive_index '^1\.5$' 5
wait_state undo_depth '^0$' 5
wait_state title '^default.txt - raytracer-view$' 5

step "reflection -0.5: taken as typed, and the panel says weights are 0 or more"
[ -z "$(state weights_material)" ] || fail "a warning with no negative weight: $(state weights_material)"
ctrl_click reflection 0.5
key minus
type_text 0.5
key Return
wait_state value_material_reflection '^-0\.5$' 5
wait_state weights_material "^reflection is negative: weights are 0 or more" 5
shot 4-negative-weight
echo PASS
