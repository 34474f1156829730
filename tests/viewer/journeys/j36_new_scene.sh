#!/bin/bash
# Journey: a scene written from scratch. The user has typed into default.txt and asks
# for a new scene (Ctrl+N): the viewer asks about the unsaved text (Cancel keeps it;
# Discard goes on), then shows the new scene's text ready for typing. The user types a
# line, applies it, saves (Ctrl+S asks for a name: it was never saved) and quits.
# Checks: Cancel keeps the typed text and its title; the new scene is untitled.txt,
# unsaved, its text focused; the saved file holds the typed line above a scene that
# `raytracer --check` accepts, and the picture shown is raytracer's render of it; the
# Help > Scene format shows the format's blocks and closes with Esc; Edit > Add > torus
# stands it on the floor beside the sphere (not in front of it, hiding it); the window
# then closes without asking.
# Usage: j36_new_scene.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

step "type into default.txt, then Ctrl+N: asked first; Cancel keeps the text"
start_viewer "$SCENES/default.txt"
key ctrl+e
wait_state editor_grid "nowrap"
key ctrl+Home
type_text "// kept"
wait_state title '^default.txt\* - raytracer-view$'
key Escape ctrl+n
wait_state popups "Unsaved changes"
click_item button_unsaved_cancel
wait_state popups "^none$"
wait_state title '^default.txt\* - raytracer-view$'

step "Ctrl+N again, Discard changes: the new scene's text, focused"
key ctrl+n
wait_state popups "Unsaved changes"
click_item button_unsaved_discard
wait_state title '^untitled.txt - raytracer-view$'
wait_state editor_cursor "^1 1 focused$"
wait_state render "done" 30

step "type a line, apply, Ctrl+S: Save As names the file"
type_text "// mine"
key Return ctrl+Return
wait_state title '^untitled.txt\* - raytracer-view$'
wait_state text "applied"
key ctrl+s
wait_state popups "Save scene as"
wait_state browser_field "^active$"
key ctrl+a
type_text "$OUT/mine.txt"
key Return
wait_state title '^mine.txt - raytracer-view$'
SCENE=$OUT/mine.txt
[ "$(head -1 "$SCENE")" = "// mine" ] || fail "the typed line is not the saved file's first: $(head -1 "$SCENE")"
"$BIN/raytracer" --check "$SCENE" > "$OUT/check.txt" 2>&1 || fail "raytracer --check refuses the saved scene: $(cat "$OUT/check.txt")"
grep -q "1 object, 1 plane, 1 light" "$OUT/check.txt" || fail "the new scene is not a sphere, a floor and a lamp: $(cat "$OUT/check.txt")"
select_nothing
picture_agrees new

step "Help > Scene format: the blocks to copy from; Esc closes it"
click_item "menu:Help"
click_item "menu:Scene_format"
wait_state popups "Scene format"
shot format
key Escape
wait_state popups "^none$"

step "Edit > Add > torus: it stands on the floor beside the sphere, not in front of it"
click_item "menu:Edit"
hover_item "menu:Add_in_front"
click_item "menu:torus"
wait_state message "^Added a torus"
save
# The torus's middle (position) against the sphere's (5 0 1, radius 1): on the floor
# (z = its minor radius) and at least a torus's width (major + minor) from the sphere.
read -r tx ty tz minor <<< "$(awk '/torus \{/ { t = 1 } t && $1 == "position" { p = $2 " " $3 " " $4 } t && $1 == "minor" { print p, $2; exit }' "$SCENE")"
[ -n "$minor" ] || fail "no torus in the saved scene: $(cat "$SCENE")"
awk -v x="$tx" -v y="$ty" -v z="$tz" -v m="$minor" 'BEGIN {
    d = sqrt((x - 5) ^ 2 + y ^ 2); exit !(z == m && d >= 2 + m) }' ||
    fail "the torus at $tx $ty $tz (minor $minor) is not on the floor beside the sphere"
wait_state render "done" 30
shot torus

step "Ctrl+Q closes without asking (saved)"
quit_viewer
echo PASS
