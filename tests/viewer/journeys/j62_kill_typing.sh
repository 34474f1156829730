#!/bin/bash
# Journey: the viewer is killed (SIGKILL) while the user types. The user types a line at
# the top of the scene text, pauses for more than a second, types another and the
# viewer is killed at once. The user starts it again on the same file.
# Checks: the file on disk is untouched and nothing else is left beside it; the new
# start offers the unsaved text, and Restore then Save keep the first line (typed more
# than a second before the kill: at most the last second of work may be lost).
# Usage: j62_kill_typing.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"
. "$(dirname "$0")/kill_lib.sh"

step "type a line into the scene text, pause, type another, and the viewer is killed"
start_viewer "$SCENES/default.txt" --samples 4
key ctrl+e
wait_state editor_grid "nowrap"
key ctrl+Home
type_text "// typed before the pause"
key Return
wait_state editor_cursor "^2 1 focused$"
idle 1.5
type_text "// typed just before the kill"
kill_viewer

step "the file is as it was, with nothing beside it"
file_untouched "$SCENES/default.txt"

step "start again: the unsaved text is offered; restore it and save"
restore_and_save
[ "$(head -1 "$SCENE")" = "// typed before the pause" ] ||
    fail "the line typed more than a second before the kill was lost: $(head -2 "$SCENE")"
# Line 2: what reached the copy of the second line (a prefix of it, maybe empty), then
# the original first line; the rest as it was.
second="// typed just before the kill"
line2=$(sed -n 2p "$SCENE") orig1=$(head -1 "$SCENES/default.txt")
typed=${line2%"$orig1"}
[ "$typed$orig1" = "$line2" ] && [ "${second#"$typed"}" != "$second" -o -z "$typed" ] ||
    fail "line 2 is '$line2': not a prefix of the second line and the original first line"
cmp -s <(tail -n +3 "$SCENE") <(tail -n +2 "$SCENES/default.txt") || fail "the rest of the text is not the original's"
echo "kept of the second line: '$typed'"
echo PASS
