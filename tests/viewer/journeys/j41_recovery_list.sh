#!/bin/bash
# Journey: what a killed session left is offered at the next start, whatever is opened.
# The user types an unapplied comment into s.txt, the viewer is killed (SIGKILL), and
# the user starts raytracer-view with no file.
# Checks: the start lists the kept copy (its file, with time and size) although another
# scene opened; "Open it" opens s.txt and offers its unsaved text; Restore brings the
# comment back into the editor.
# Usage: j41_recovery_list.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"
. "$(dirname "$0")/kill_lib.sh"

RECOVERY=$XDG_STATE_HOME/raytracer-view/recovery

step "type into s.txt, wait for the recovery copy, kill the viewer"
cp "$SCENES/default.txt" "$OUT/s.txt"
start_viewer "$OUT/s.txt" --samples 4
key ctrl+e
wait_state editor_grid "nowrap"
key ctrl+Home
type_text "// kept note"
key Return
wait_until 'grep -lq "^// kept note$" "$RECOVERY"/*.txt 2>/dev/null' 10 "a recovery copy of the typed text"
kill_viewer

step "start with no file: the copy of s.txt is listed"
(cd "$OUT" && exec "$BIN/raytracer-view" --size "$SCREEN" --print-layout --samples 4 > "$LAYOUT" 2> "$OUT/viewer.err") &
VIEWER_PID=$!
WID=$(timeout 30 xdotool search --sync --name "raytracer-view" | head -1) || fail "no window appeared"
wait_state load "^ready$" 30
wait_state orphans "^$OUT/s.txt$" 10
wait_state banner "^none$" 1
shot 1-listed

step "Open it: s.txt opens and its unsaved text is offered"
click_item button_open_orphan_1
wait_state title "^s.txt - raytracer-view$" 30
wait_state banner "^recovery$" 10
wait_state orphans "^none$" 1
click_item button_restore_recovered
wait_state banner "^none$" 5
wait_state text "^unapplied" 5
save
head -1 "$OUT/s.txt" | grep -q "^// kept note$" || fail "the restored text is not in s.txt: $(head -1 "$OUT/s.txt")"
echo PASS
