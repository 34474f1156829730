#!/bin/bash
# Journey: several snapshots. The user keeps three snapshots (K), then presses
# Shift+B four times.
# Checks: K numbers them 1, 2, 3; Shift+B compares side by side with the newest but
# one, then the oldest, then the newest again, saying which ("snapshot 2 of 3"), and
# the split's label names the snapshot shown.
# Usage: j52_snapshots.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

start_viewer "$SCENES/default.txt" --samples 4
wait_state render "done" 60
xdotool mousemove $((ix + iw / 2)) $((iy + ih / 2))
for k in 1 2 3; do
    key k
    wait_state message "^Kept snapshot $k" 5
done
for k in 2 1 3 2; do
    key shift+b
    wait_state message "^Comparing with snapshot $k of 3" 5
done
shot 1-snapshot-2
echo PASS
