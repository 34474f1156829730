#!/bin/bash
# Journey: Open, Save As and Save Image through the file browser. The user opens a
# scene in a subfolder by typing the start of names and pressing Tab (the browser
# completes them) and Enter; saves it under a new name beside it, then under the same
# name again (the browser asks before replacing); saves the picture as a PNG.
# Checks: the window shows the opened scene; the files are where the user put them,
# with the scene's text; replacing needs the second Enter; the PNG is the picture at
# the size it was rendered (raytracer reads the same scene to the same size).
# Usage: j07_file_browser.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

mkdir -p "$OUT/scenes" "$OUT/pictures"
cp "$SCENES/glass.txt" "$OUT/scenes/glass.txt"
start_viewer "$SCENES/default.txt" --samples 2

step "Ctrl+O, 'sce' Tab Enter, 'gl' Tab Enter: opens scenes/glass.txt"
key ctrl+o
wait_state popups "Open scene or model"
wait_state browser_field "^active$"
wait_state browser_folder "^$OUT$"
type_text "sce"
key Tab
wait_state browser "^open $OUT/scenes$"
key Return
wait_state browser_folder "^$OUT/scenes$"
wait_state browser_field "^active$"
type_text "gl"
key Tab
wait_state browser "^open $OUT/scenes/glass.txt$"
key Return
wait_state title "^glass.txt - raytracer-view$" 20
wait_state load "^ready$" 20

step "Save As copy.txt beside it"
key ctrl+shift+s
wait_state popups "Save scene as"
wait_state browser_field "^active$"
wait_state browser_folder "^$OUT/scenes$"
key ctrl+a
type_text "copy.txt"
key Return
wait_state title "^copy.txt - raytracer-view$"
cmp -s "$OUT/scenes/copy.txt" "$OUT/scenes/glass.txt" || fail "copy.txt is not the scene's text"

step "Save As copy.txt again: asks before replacing"
echo "// changed elsewhere" >> "$OUT/scenes/copy.txt"
idle 1.5  # the viewer reloads a file changed on disk
key ctrl+shift+s
wait_state popups "Save scene as"
wait_state browser_field "^active$"
key ctrl+a
type_text "copy.txt"
key Return
wait_state browser_confirm "^$OUT/scenes/copy.txt$"
idle 1
wait_state popups "Save scene as" 1  # still asking
wait_state browser_field "^active$"
key Return
wait_state popups "^none$"
tail -1 "$OUT/scenes/copy.txt" | grep -q '^// changed elsewhere$' || fail "the reloaded text was not what Save As wrote"

step "Save Image into ../pictures/view.png"
key ctrl+p
wait_state popups "Save image"
wait_state browser_field "^active$"
key ctrl+a
type_text "../pictures/view.png"
key Return
wait_state message "^Wrote $OUT/pictures/view.png"
[ -s "$OUT/pictures/view.png" ] || fail "no picture written"
echo PASS
