#!/bin/bash
# Journey: a Save As that cannot be written. The user opens a model (a new, unsaved
# scene), saves it as a file in a folder that does not exist, then corrects the path;
# later opens Save As again.
# Checks: Save As starts in the model's folder (not the working folder); the failure
# names the path and the reason, in the dialog and the status bar; the dialog stays
# open with the path as typed; the corrected path saves; the next Save As starts in
# the scene's folder again.
# Usage: j42_save_errors.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

MODELS=$(cd "$HERE/../../models" && pwd)
mkdir -p "$OUT/models" "$OUT/work"
cp "$MODELS/cube.obj" "$OUT/models/cube.obj"

step "raytracer-view on a model, started from another folder"
(cd "$OUT/work" && exec "$BIN/raytracer-view" ../models/cube.obj --size "$SCREEN" --print-layout --samples 4 \
    > "$LAYOUT" 2> "$OUT/viewer.err") &
VIEWER_PID=$!
WID=$(timeout 30 xdotool search --sync --name "cube" | head -1) || fail "no window appeared"
wait_state title "^cube.txt - raytracer-view$" 30
wait_state load "^ready$" 60

step "Save As starts in the model's folder"
key ctrl+shift+s
wait_state popups "Save scene as"
wait_state browser_field "^active$"
wait_state browser_folder "^$OUT/models$" 2

step "a folder that does not exist: the dialog stays, naming the path and why"
bad=$OUT/no/such/folder/cube.txt
key ctrl+a
type_text "$bad"
# (Typed keys may wait in the queue on a loaded machine: the whole path first.)
wait_state browser "^save $bad$" 30
key Return
wait_state browser_message "^Cannot save $bad: No such file or directory$" 30
idle 0.5
wait_state popups "Save scene as" 1
wait_state browser "^save $bad$" 1
wait_state status_bar "Cannot save $bad: No such file or directory" 1
shot 1-save-refused

step "the path corrected: saved"
key ctrl+a
type_text "$OUT/models/cube.txt"
wait_state browser "^save $OUT/models/cube.txt$" 30
key Return
wait_state popups "^none$" 30
wait_state title "^cube.txt - raytracer-view$" 5
[ -s "$OUT/models/cube.txt" ] || fail "cube.txt was not written"

step "the next Save As starts in the scene's folder"
key ctrl+shift+s
wait_state popups "Save scene as"
wait_state browser_folder "^$OUT/models$" 2
key Escape
wait_state popups "^none$" 5
echo PASS
