#!/bin/bash
# Journey: the viewer is killed (SIGKILL) while it saves. The scene is big (about 21 MB,
# mostly notes), so that writing it takes a moment; the user types a new radius for the
# second sphere, and more than a second later presses Ctrl+S, and the viewer is killed
# as soon as it opens a new file in the scene's folder (seen in /proc: the save under
# way). The user starts it again on the same file.
# Checks: the scene file is either the old one or the complete new one, byte for byte,
# and the folder holds nothing it did not hold before (no partial file under any name);
# if the old one, the new start offers the unsaved edit, and Restore then Save write it.
# Usage: j63_kill_save.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"
. "$(dirname "$0")/kill_lib.sh"

BIG=$OUT/big.txt
{
    cat "$SCENES/default.txt"
    awk 'BEGIN { for (i = 0; i < 260000; ++i) printf "// note %07d: kept so that saving takes a moment, 80 bytes a line.\n", i }'
} > "$BIG"
cp "$BIG" "$OUT/original.txt"
echo "scene of $(stat -c %s "$BIG") bytes"

step "type 0.77 into the radius of sphere 2"
start_viewer "$BIG" --samples 1
[ "$SCENE" = "$BIG" ] || fail "the viewer edits $SCENE, not $BIG"
select_outline object_2
type_value radius 0.77
wait_state value_radius "^0.77$"
wait_state title '^big.txt\* - raytracer-view$'
# The recovery copy holds the edit before the save starts. (The viewer writes a copy
# about a second after a change; of 18 MB, on a machine whose processors are busy, on
# a thread below the window's priority, the write itself can take longer than that:
# the journey waits for the copy, not for a fixed time.)
wait_until 'grep -rqsF "radius 0.77" "$XDG_STATE_HOME/raytracer-view/recovery"' 30 "the recovery copy to hold the edit"

step "Ctrl+S, and the viewer is killed while it writes the file"
files=$(ls -A "$OUT")
kill_while_writing "$OUT" ctrl+s

step "the file is the old one or the new one, whole, and nothing was left beside it"
[ "$(ls -A "$OUT")" = "$files" ] || fail "the folder held $files, now $(ls -A "$OUT")"
if cmp -s "$BIG" "$OUT/original.txt"; then
    echo "the old file"
    step "start again: the unsaved edit is offered; restore it and save"
    restore_and_save
else
    echo "the new file"
    cmp -s <(sed 11d "$BIG") <(sed 11d "$OUT/original.txt") || fail "the new file is not the old one with one line changed"
    step "start again: nothing is offered (the file has it all)"
    start_viewer "$BIG" --samples 1
    idle 1
    wait_state banner "^none$" 1
fi
[ "$(sed -n 11p "$BIG")" = "    radius 0.77" ] || fail "the radius in the file is '$(sed -n 11p "$BIG")'"
echo PASS
