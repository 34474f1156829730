#!/bin/bash
# Journey: undo that says what it undoes. The user moves sphere 2 with the handle's
# green arrow, then drags the radius field of sphere 1; presses Ctrl+Z, opens the Edit
# menu and its Undo history; presses Ctrl+Y; then picks "Move sphere 2" in the history
# and saves.
# Checks: Ctrl+Z and Ctrl+Y say which step they took back or did again; the Edit menu
# names the next undo and redo, and the history lists both steps by name; going back
# to before the move in the history gives the original file.
# Usage: j20_undo_names.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

step "open default.txt, move sphere 2 with the handle"
start_viewer "$SCENES/default.txt" --samples 4
click $((ix + iw * 66 / 100)) $((iy + ih * 35 / 100))
wait_state selection "^object_2$"
idle 0.3
hx=$(field handle 1) hy=$(field handle 2)
drag $((hx - 45)) "$hy" $((hx - 105)) "$hy"
wait_state message "^Moved by"

step "select sphere 1 (the glass ball) and drag its radius field"
click $((ix + iw * 37 / 100)) $((iy + ih * 55 / 100))
wait_state selection "^object_1$"
wait_state "field_radius" '^[0-9]'
read -r x y <<< "$(item_xy field_radius)"
drag "$x" "$y" $((x + 40)) "$y"
idle 0.5
shot 1-edited

step "Ctrl+Z says what it undid"
xdotool mousemove $((ix + iw + 50)) $((iy + 10))  # off the picture: the status bar shows messages
key ctrl+z
wait_state message "^Undid: Edit radius of sphere 1" 3

step "the Edit menu names the next undo and redo, its history both steps"
click_item "menu:Edit"
wait_state edit_menu "^Undo: Move sphere 2 \| Redo: Edit radius of sphere 1$" 3
hover_item "menu:Undo_history"
wait_state undo_history "^redo:Edit radius of sphere 1\|undo:Move sphere 2\|$" 3
idle 0.3
shot 2-history
key Escape
wait_state popups "^none$" 3

step "Ctrl+Y says what it redid"
key ctrl+y
wait_state message "^Redid: Edit radius of sphere 1" 3

step "back to before the move through the history; save"
click_item "menu:Edit"
hover_item "menu:Undo_history"
wait_state undo_history "^undo:Edit radius of sphere 1\|undo:Move sphere 2\|$" 3
click_item "menu:undo:2"
wait_state message "^Undid 2 steps, back to before Move sphere 2" 3
shot 3-back
save
cmp -s "$SCENE" "$SCENES/default.txt" || fail "back to before the first step, the file differs: $(diff "$SCENES/default.txt" "$SCENE" | head)"
echo PASS
