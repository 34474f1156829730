#!/bin/bash
# Journey: auto-indent in a tab-indented scene. The user clicks at the end of
# `thing {` in the Text tab, presses Enter, types a sphere block line by line (Enter
# after `sphere {` and after its keys, then `}`), applies (Ctrl+Enter) and saves.
# Checks: the new lines are indented with tabs as the file is, one level inside
# `thing {` and two inside `sphere {`; the typed `}` went back one level; the saved
# file parses (`raytracer --check`) with one sphere more.
# Usage: j66_auto_indent.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

step "a copy of default.txt indented with tabs"
sed 's/  /\t/g' "$SCENES/default.txt" > "$OUT/tabs.txt"
[ "$(sed -n 2p "$OUT/tabs.txt")" = "thing {" ] || fail "line 2 is not 'thing {'"
start_viewer "$OUT/tabs.txt" --samples 4
click_item tab_Text
wait_state editor_grid '^[0-9]'

step "Enter at the end of 'thing {', then a sphere block typed line by line"
read -r x y <<< "$(editor_xy 2 30)"
click "$x" "$y"
wait_state editor_cursor "^2 8 focused$" 3
key Return
type_text "sphere {"
key Return
type_text "position 3 2 1 radius 0.4"
key Return
type_text "}"
wait_state editor_cursor "^5 3 focused$" 3
shot 1-typed
key ctrl+Return
wait_state title '^tabs.txt\* - raytracer-view$'
save

step "the block is indented with tabs, and parses"
sed -n 2,6p "$SCENE" | cat -A
[ "$(sed -n 3p "$SCENE")" = "$(printf '\tsphere {')" ] || fail "line 3: '$(sed -n 3p "$SCENE")'"
[ "$(sed -n 4p "$SCENE")" = "$(printf '\t\tposition 3 2 1 radius 0.4')" ] || fail "line 4: '$(sed -n 4p "$SCENE")'"
[ "$(sed -n 5p "$SCENE")" = "$(printf '\t}')" ] || fail "line 5: '$(sed -n 5p "$SCENE")'"
[ "$(sed -n 6p "$SCENE")" = "$(printf '\tsphere {')" ] || fail "the old first sphere is not line 6"
"$BIN/raytracer" --check "$SCENE" > "$OUT/check.txt" 2>&1 || fail "the saved file does not parse: $(cat "$OUT/check.txt")"
[ "$(grep -c "^$(printf '\t')sphere {" "$SCENE")" = 3 ] || fail "not three spheres in thing"
echo PASS
