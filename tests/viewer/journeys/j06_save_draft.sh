#!/bin/bash
# Journey: text edits, panel edits and Save mixed. The user changes line 6 to
# "radius 0.5abc" and does not apply it, selects the torus and tries to type 0.8 into
# "major", then saves (Ctrl+S), first cancelling, then saving the broken text anyway.
# Then the user fixes the line to "radius 0.5" (still not applied), types 0.8 into
# "major" and saves. Last, a new error typed and Ctrl+Q: Save, Save it anyway.
# Checks: while the text does not parse the panel refuses edits (so text and panels
# cannot disagree); saving asks first, and Cancel leaves the file as it was; "Save it
# anyway" writes the text as typed with the torus unchanged, and the title has no "*";
# with the text fixed, the panel edit goes into it and Save applies it: the file holds
# both changes and raytracer's picture of it is the picture on the screen; quitting
# with unsaved broken text, "Save it anyway" saves it and then quits.
# Usage: j06_save_draft.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

start_viewer "$SCENES/default.txt" --samples 4
major_in() { awk '$1 == "torus" { t = 1 } t { for (i = 1; i < NF; ++i) if ($i == "major") { print $(i + 1); exit } }' "$1"; }
major() { major_in "$SCENE"; }
open_item() {
    read -r tx ty tw th <<< "$(state tab_Objects)"
    click $((tx + tw / 2)) $((ty + th / 2))
    wait_state "outline_$1" "^[0-9]"
    read -r ox oy ow oh <<< "$(state "outline_$1")"
    [ -n "$ox" ] || fail "no outline row for $1"
    click $((ox + 30)) $((oy + oh / 2))
    wait_state selection "^$1$"
}
type_major() {
    wait_state field_major "^[0-9]"
    read -r fx fy fw fh <<< "$(state field_major)"
    xdotool mousemove $((fx + fw / 4)) $((fy + fh / 2)) keydown ctrl click 1 keyup ctrl
    idle 0.5
    [ "${2:-}" = blocked ] || wait_state typing "^major active$"
    type_text "$1"
    key Return
}

step "radius 0.5abc on line 6, not applied"
key ctrl+e
wait_state editor_grid "nowrap"
read -r x y <<< "$(editor_xy 6 13 0.9)"
click "$x" "$y"
wait_state editor_cursor "^6 [0-9]+ focused$"
key End BackSpace
type_text "0.5abc"
wait_state editor_cursor "^6 18 focused$"
wait_state diagnostics "^1 " 5

step "the torus's major cannot be changed meanwhile"
open_item object_3
wait_state edits "^blocked$"
type_major 0.8 blocked
idle 0.5
shot 1-blocked

step "Ctrl+S asks first; Cancel keeps the file"
key ctrl+s
wait_state popups "The scene text has errors"
key Escape
wait_state popups "^none$"
cmp -s "$SCENE" "$SCENES/default.txt" || fail "Cancel still wrote the file"

step "Ctrl+S, Save it anyway: the text as typed, the torus as it was"
key ctrl+s
wait_state popups "The scene text has errors"
read -r bx by bw bh <<< "$(state button_save_anyway)"
click $((bx + bw / 2)) $((by + bh / 2))
wait_state title '^default.txt - raytracer-view$'
grep -q '^    radius 0.5abc$' "$SCENE" || fail "the typed text was not saved"
[ "$(major)" = "$(major_in "$SCENES/default.txt")" ] ||
    fail "major in the file is $(major): a refused panel edit was saved"

step "fix the line (not applied), type 0.8 into major, save"
key ctrl+e
wait_state editor_cursor "focused$"
read -r x y <<< "$(editor_xy 6 17 0.9)"
click "$x" "$y"
wait_state editor_cursor "^6 [0-9]+ focused$"
key End BackSpace BackSpace BackSpace
wait_state editor_cursor "^6 15 focused$"
wait_state diagnostics "^0"
open_item object_3
type_major 0.8
idle 0.5
wait_state text "^unapplied"
save
grep -q '^    radius 0.5$' "$SCENE" || fail "the fixed line was not saved: $(sed -n 6p "$SCENE")"
[ "$(major)" = 0.8 ] || fail "major in the file is $(major), expected 0.8"
wait_state text "^applied$"
select_nothing
picture_agrees saved

step "an error typed again, then Ctrl+Q: Save, Save it anyway: the text is saved and the window closes"
key ctrl+e
wait_state editor_grid "." 10
read -r x y <<< "$(editor_xy 6 15 0.9)"
click "$x" "$y"
wait_state editor_cursor "^6 [0-9]+ focused$"
key End
type_text "x"
wait_state diagnostics "^1 " 5
key ctrl+q
wait_state popups "Unsaved changes"
click_item button_unsaved_save
wait_state popups "The scene text has errors"
click_item button_save_anyway
wait_until '! kill -0 "$VIEWER_PID" 2>/dev/null' 10 "the window to close after Save it anyway"
grep -q '^    radius 0.5x$' "$SCENE" || fail "the text was not saved: $(sed -n 6p "$SCENE")"
echo PASS
