#!/bin/bash
# Journey: two viewers on one file. Viewer A opens s.txt and types a comment into its
# text (not applied, not saved) and keeps its recovery copy; viewer B then opens the
# same s.txt. Later A is killed (SIGKILL).
# Checks: B does not take A's copy for an earlier session's (no recovery banner, no
# "Discard it" that could delete it) and says that A (its pid) has the file open; A's
# copy is still on disk and still A's text. Once A is killed, B takes the file over
# and offers A's unsaved text, and Restore puts it into B's editor.
# Usage: j40_two_viewers.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"
. "$(dirname "$0")/kill_lib.sh"

RECOVERY=$XDG_STATE_HOME/raytracer-view/recovery
copy_of_a() { find "$RECOVERY" -name '*.txt' 2>/dev/null | head -1; }

step "viewer A: type an unapplied comment into s.txt, wait for its recovery copy"
cp "$SCENES/default.txt" "$OUT/s.txt"
start_viewer "$OUT/s.txt" --samples 4
A_PID=$VIEWER_PID
A_LAYOUT=$LAYOUT
key ctrl+e
wait_state editor_grid "nowrap"
key ctrl+Home
type_text "// A's note"
key Return
wait_state text "^unapplied$" 5
wait_until '[ -n "$(copy_of_a)" ] && grep -q "^// A'"'"'s note$" "$(copy_of_a)"' 10 "viewer A's recovery copy"
COPY=$(copy_of_a)
wait_state held_elsewhere "^0$" 1

step "viewer B on the same file: no recovery offer, it names A"
LAYOUT=$OUT/layout-b.txt
(cd "$OUT" && exec "$BIN/raytracer-view" "$OUT/s.txt" --size "$SCREEN" --print-layout --samples 4 > "$LAYOUT" 2> "$OUT/viewer-b.err") &
B_PID=$!
trap 'kill $B_PID 2>/dev/null || true; journey_cleanup' EXIT
wait_state load "^ready$" 60
wait_state held_elsewhere "^$A_PID$" 10
idle 2
wait_state banner "^none$" 1
wait_state held_elsewhere "^$A_PID$" 1
[ -f "$COPY" ] && grep -q "^// A's note$" "$COPY" || fail "A's recovery copy is gone or changed after B opened the file"
shot 1-b-names-a

step "A is killed: B takes the file over and offers A's text"
kill -KILL "$A_PID"
wait "$A_PID" 2>/dev/null || true
VIEWER_PID=$B_PID
wait_state held_elsewhere "^0$" 10
wait_state banner "^recovery$" 10
shot 2-b-offers
click_item button_restore_recovered
wait_state banner "^none$" 5
wait_state text "^unapplied" 5
head -c 100000 "$COPY" | grep -q "^// A's note$" || fail "A's copy went before it was saved"
echo PASS
