#!/bin/bash
# Journey: opening a file that is not a scene. With the default scene shown the user
# opens 50 MB of random bytes; another program writes random bytes over the open scene
# file; the user opens random bytes with no NUL among them, then a scene with an
# ordinary error (a misspelt key).
# Checks: the binary files are refused with a message naming the file and why; the
# title, the scene (its objects, the picture) and the text stay as they were, and
# nothing is marked as changed. The scene with an error opens as text with its error
# listed, but neither the title ("*") nor the Text tab call it changes of the user's
# until the user types into it.
# Usage: j38_open_not_text.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

head -c 50000000 /dev/urandom > "$OUT/random.bin"
# Bytes with no NUL: the UTF-8 check alone refuses them.
head -c 2000000 /dev/urandom | tr -d '\000' > "$OUT/noise.txt"
sed 's/radius/radious/' "$SCENES/default.txt" > "$OUT/typo.txt"

start_viewer "$SCENES/default.txt" --samples 4
wait_state render "done" 60
objects=$(state scene_size)
[ "$objects" != none ] && [ -n "$objects" ] || fail "no scene shown"

open_file() {
    key ctrl+o
    wait_state popups "Open scene or model"
    wait_state browser_field "^active$"
    key ctrl+a
    type_text "$1"
    # (Typed keys may wait in the queue on a loaded machine: the whole path first.)
    wait_state browser "^open $1$" 30
    key Return
    wait_state popups "^none$" 30
}
unchanged() {
    wait_state title "^default.txt - raytracer-view$" 1
    wait_state text "^applied$" 1
    wait_state diagnostics "^0$" 1
    [ "$(state scene_size)" = "$objects" ] || fail "the scene changed: $(state scene_size), was $objects"
    [ "$(state editor_bytes)" = "$(stat -c %s "$SCENES/default.txt")" ] ||
        fail "the editor holds $(state editor_bytes) bytes, not the scene's $(stat -c %s "$SCENES/default.txt")"
}

step "50 MB of random bytes: refused, the scene stays"
open_file "$OUT/random.bin"
wait_state status_bar "Cannot open $OUT/random.bin: not a scene text: a NUL byte at byte" 30
unchanged
wait_state render "done" 30
shot 1-binary-refused

step "the scene file overwritten on disk with random bytes: not read in, the scene stays"
head -c 100000 /dev/urandom > "$SCENE"
wait_state status_bar "$SCENE changed on disk and is not a scene text: a NUL byte at byte [0-9]+ \(a binary file\?\); the scene and its text stay" 30
unchanged

step "random bytes with no NUL: refused as not UTF-8 text"
open_file "$OUT/noise.txt"
wait_state status_bar "Cannot open $OUT/noise.txt: not a scene text: [0-9]+ of its [0-9]+ bytes are not UTF-8" 30
unchanged

step "a scene with an error: opens as text, not as changes of the user's"
open_file "$OUT/typo.txt"
wait_state title "^typo.txt - raytracer-view$" 30
wait_state diagnostics "^[1-9]" 1
wait_state text "^no scene$" 1
click_item tab_Text
wait_state text_tab "errors" 5
idle 0.5
wait_state title "^typo.txt - raytracer-view$" 1
shot 2-errors-untouched

step "typed into, it is the user's changes"
read -r x y <<< "$(editor_xy 1 1)"
click "$x" "$y"
type_text "x"
wait_state text "^unapplied$" 5
wait_state title '^typo.txt\* - raytracer-view$' 5
echo PASS
