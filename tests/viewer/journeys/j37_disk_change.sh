#!/bin/bash
# Journey: the scene file is changed by another program while the viewer shows it.
# With no unsaved edits the viewer reads the new file by itself (the mouse resting);
# saved with an error, the status line says where and the last good picture stays.
# With unsaved edits (a radius typed in the Objects tab) it asks instead: a banner
# offers "Reload from disk" and "Keep mine". Keep mine, then Ctrl+S: the file holds
# the user's edit. Changed on disk again: Reload from disk shows the file's text,
# unmodified, and Ctrl+Z brings the user's edit back.
# Checks: the titles (with or without "*"), the banner, the saved bytes against
# default.txt edited the same way, and the picture against raytracer's render of the
# file after each reload.
# Usage: j37_disk_change.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

ORIG=$SCENES/default.txt
# $1 with the first sphere's radius (line "    radius 1" of default.txt) set to $2.
with_radius() { awk -v r="$2" '$0 == "    radius 1" && !done { print "    radius " r; done = 1; next } { print }' "$1"; }
# Another program writes $2 over the scene file (a new file renamed into place, as
# editors save).
outside_write() {
    printf '%s\n' "$1" > "$SCENE.tmp"
    mv "$SCENE.tmp" "$SCENE"
}

start_viewer "$ORIG"

step "changed on disk with nothing unsaved: read again with the mouse resting"
outside_write "$(with_radius "$ORIG" 0.6)"
wait_state message "^Reloaded default.txt \(changed on disk\)" 10
wait_state title '^default.txt - raytracer-view$'
wait_state banner "^none$"
picture_agrees 1-reloaded
cp "$SCENE" "$OUT/disk1.txt"

step "saved by the other program half done: the error's place is said, the picture stays"
outside_write "$(with_radius "$ORIG" "0.6 oops")"
wait_state message "^error: default.txt:6:16: error: unknown key 'oops'" 10
wait_state message "the last good scene stays"
wait_state title '^default.txt - raytracer-view$'
cp "$OUT/disk1.txt" "$OUT/good.txt"
SCENE_SHOWN=$SCENE SCENE=$OUT/good.txt
picture_agrees 1-kept
SCENE=$SCENE_SHOWN
outside_write "$(with_radius "$ORIG" 0.6)"
wait_state message "^Reloaded default.txt \(changed on disk\)" 10
wait_state text "^applied$"

step "a radius typed for sphere 1, then the file changed on disk: the banner asks"
click $((ix + iw * 37 / 100)) $((iy + ih * 55 / 100))
wait_state selection "^object_1$"
click_item tab_Objects
type_value radius 1.4
wait_state title '^default.txt\* - raytracer-view$'
outside_write "$(with_radius "$ORIG" 0.8)"
wait_state banner "^conflict$" 10
wait_state message "changed on disk; you have unsaved edits"
idle 2
[ "$(state title)" = "default.txt* - raytracer-view" ] || fail "the unsaved edit was lost: $(state title)"
shot 2-conflict

step "Keep mine, Ctrl+S: the file holds the typed radius"
click_item button_disk_keep
wait_state banner "^none$"
save
with_radius "$ORIG" 1.4 > "$OUT/want-mine.txt"
cmp "$SCENE" "$OUT/want-mine.txt" || fail "the save is not the user's text: $(diff "$OUT/want-mine.txt" "$SCENE" | head)"

step "typed again and changed on disk again: Reload from disk, then Ctrl+Z"
type_value radius 1.2
wait_state title '^default.txt\* - raytracer-view$'
outside_write "$(with_radius "$ORIG" 0.5)"
wait_state banner "^conflict$" 10
click_item button_disk_reload
wait_state banner "^none$"
wait_state title '^default.txt - raytracer-view$'
wait_state message "^Reloaded default.txt \(Ctrl\+Z brings your edits back\)"
with_radius "$ORIG" 0.5 > "$OUT/want-disk.txt"
cmp "$SCENE" "$OUT/want-disk.txt" || fail "the file itself changed: $(diff "$OUT/want-disk.txt" "$SCENE" | head)"
select_nothing
picture_agrees 3-reloaded
key ctrl+z
wait_state message "^Undid: Reload from disk"
wait_state title '^default.txt\* - raytracer-view$'
save
with_radius "$ORIG" 1.2 > "$OUT/want-undone.txt"
cmp "$SCENE" "$OUT/want-undone.txt" || fail "after Ctrl+Z the save is not the user's text: $(diff "$OUT/want-undone.txt" "$SCENE" | head)"
shot 4-undone
quit_viewer
echo PASS
