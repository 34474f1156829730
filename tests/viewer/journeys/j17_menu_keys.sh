#!/bin/bash
# Journey: keys while a menu is open. The user opens the File menu and presses Escape;
# right-clicks the picture and presses Escape; opens the View menu and presses Ctrl+R.
# Checks: Escape closes each menu (and nothing else happens: nothing is selected or
# cancelled); Ctrl+R closes the menu and opens the Render to file dialog.
# Usage: j17_menu_keys.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

step "open default.txt; File menu, then Escape"
start_viewer "$SCENES/default.txt" --samples 4
wait_state render "done" 60
click_item "menu:File"
wait_state popups "^##Menu" 3
shot 1-file-menu
key Escape
wait_state popups "^none$" 3

step "the picture's menu, then Escape"
click $((ix + iw / 2)) $((iy + ih * 85 / 100)) 3
wait_state "menu:Add_here" '^[0-9]' 3
shot 2-image-menu
sel=$(state selection)
key Escape
wait_state popups "^none$" 3
[ "$(state selection)" = "$sel" ] || fail "Escape changed the selection from '$sel' to '$(state selection)'"

step "View menu, then Ctrl+R"
click_item "menu:View"
wait_state popups "^##Menu" 3
key ctrl+r
wait_state render_dialog "^setup" 3
idle 0.5
shot 3-render-dialog
[[ "$(state popups)" != *"##Menu"* ]] || fail "the View menu stayed open under the dialog: $(state popups)"
key Escape
wait_state popups "^none$" 3
echo PASS
