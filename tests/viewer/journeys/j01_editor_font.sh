#!/bin/bash
# Journey: the scene text editor with the fonts setup.sh installs. The user opens the
# text (Ctrl+E), types two lines of ten characters each, one narrow ("iiiiiiiiii") and
# one wide ("MMMMMMMMMM"), deletes them, clicks on the "g" of "geometry" on line 17 and
# types Z; undoes it and saves.
# Checks: the two lines are equally wide on the screen (the editor draws on a grid of
# equal columns, as its caret, selection and clicks assume); the Z lands where the user
# clicked, before the "g" (the live check reports 'constructive_solid_Zgeometry');
# the saved file is the original again.
# Usage: j01_editor_font.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

step "open default.txt and the scene text"
start_viewer "$SCENES/default.txt"
key ctrl+e
wait_state editor_grid "nowrap"
grid=$(state editor_grid)
echo "editor grid: $grid"

step "type a narrow and a wide line at the top"
read -r x y <<< "$(editor_xy 1 1 0.1)"
click "$x" "$y"
key ctrl+Home
type_text "iiiiiiiiii"
key Return
type_text "MMMMMMMMMM"
key Return
wait_state editor_cursor "^3 1 focused$"
wait_state diagnostics '^[1-9]'  # the live check flags the two stray lines
idle 0.5
shot 1-typed
read -r lh <<< "$(echo "$grid" | awk '{ print int($4) }')"
read -r x1 y1 <<< "$(editor_xy 1 1 0)"
read -r x2 y2 <<< "$(editor_xy 2 1 0)"
read -r ex _ ew _ <<< "$(region editor)"
span=$((ex + ew - x1 - 20))
narrow=$("$TOOL" ink "$OUT/1-typed.png" "$x1" $((y1 - lh / 2 + 2)) "$span" $((lh - 4)))
wide=$("$TOOL" ink "$OUT/1-typed.png" "$x2" $((y2 - lh / 2 + 2)) "$span" $((lh - 4)))
echo "ink of the narrow line: $narrow, of the wide line: $wide"
read -r n0 n1 <<< "$narrow"
read -r w0 w1 <<< "$wide"
# Ten columns each: the lines end in the same column (an "i" is drawn centred in its
# column, an "M" fills it: a few pixels at each end).
cw=$(echo "$grid" | awk '{ print $3 }')
awk -v a="$n1" -v b="$w1" -v cw="$cw" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= cw * 0.6) }' ||
    fail "ten narrow characters end at x=$n1, ten wide ones at x=$w1: the columns are not equal (column $cw px)"

step "delete the two lines, click the g of geometry on line 17 and type Z"
key ctrl+Home shift+Down shift+Down Delete
wait_state diagnostics '^0'
wait_state editor_cursor "^1 1 focused$"
col=$(sed -n 17p "$SCENE" | awk '{ print index($0, "geometry") }')
read -r gx gy <<< "$(editor_xy 17 "$col" 0.2)"
click "$gx" "$gy"
wait_state editor_cursor "^17 $col focused$"
type_text "Z"
idle 0.5
# The live check names the word as it now is: the Z went where the user clicked.
wait_state diagnostics "unknown object 'constructive_solid_Zgeometry'" 5
shot 2-clicked

step "undo the Z; the saved file is the original"
key ctrl+z
wait_state diagnostics '^0'
key ctrl+Return
save
cmp -s "$SCENE" "$SCENES/default.txt" || fail "the saved text differs from the original: $(diff "$SCENES/default.txt" "$SCENE" | head)"
echo PASS
