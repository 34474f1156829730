#!/bin/bash
# Journey: finding an object in a long outline. The user opens a scene of 3,000 small
# spheres (the outline lists the first 2,002 and says how many more), types 2900 into
# the outline's filter, clicks the one row it leaves and then types a word instead.
# Checks: the filter's number finds object 2900 past the list's end, a click on its
# row selects it (the properties follow), a word matches every row that has it, and an
# empty filter lists all the objects again.
# Usage: j45_outline_filter.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

step "open a scene of 3,000 spheres"
{
    for i in $(seq 0 2999); do
        echo "thing { sphere { position $((10 + i / 60)) $(( (i % 60) - 30 )) 0 radius 0.3 } }"
    done
    echo "light { spotlight { position 0 0 40 colour 900 900 900 } }"
    echo "camera { position -20 0 30 centre 35 0 0 up 35 0 1 angle_x 60 angle_y 45 }"
    echo "picture_size { x_max 320 y_max 240 }"
    echo "end"
} > "$OUT/many.txt"
start_viewer "$OUT/many.txt" --samples 1
wait_state outline_object_1 '^-?[0-9]+ -?[0-9]+ [0-9]+ [0-9]+$' 10
shot 1-opened

step "type 2900 into the filter: the one row left is object 2900"
click_item field_outline_filter
type_text "2900"
wait_state outline_filter "^1 done$" 5
wait_state outline_object_2900 '^-?[0-9]+ -?[0-9]+ [0-9]+ [0-9]+$' 5
[ -z "$(state outline_object_1)" ] || fail "object 1 is still listed under the filter 2900"
shot 2-filtered

step "click its row: object 2900 is selected"
click_item outline_object_2900
wait_state selection "^object_2900$" 5
shot 3-selected

step "a word instead: every sphere matches; an empty filter lists them all"
click_item field_outline_filter
key ctrl+a BackSpace
type_text "SPHERE"
wait_state outline_filter "^3000 done$" 10
key ctrl+a BackSpace
wait_state outline_filter "^off$" 5
wait_state outline_object_2 '^-?[0-9]+ -?[0-9]+ [0-9]+ [0-9]+$' 5
shot 4-all-again
echo PASS
