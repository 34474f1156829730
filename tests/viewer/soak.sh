#!/usr/bin/env bash
# Memory soak of the real viewer window (not run by CI: it takes minutes). Under Xvfb
# it orbits and dollies the camera ROUNDS times (each restarts the render) and prints
# the viewer's resident and peak memory at the start, after 10 rounds and at the end.
#   xvfb-run -a -s "-screen 0 1280x800x24" tests/viewer/soak.sh [BIN_DIR] [ROUNDS]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${1:-$here/../../build/bin}
rounds=${2:-60}
state=$(mktemp -d)
XDG_STATE_HOME=$state "$bin/raytracer-view" "$here/../../scenes/showcase.txt" --size 1280x800 --print-layout \
    > "$state/layout.txt" &
pid=$!
trap 'kill $pid 2>/dev/null; rm -rf "$state"' EXIT
fail() { echo "soak: $*" >&2; exit 1; }
# shellcheck source=wait_until.sh
source "$here/wait_until.sh"
wait_until 'grep -q "^state load ready$" "$state/layout.txt"' 60 "the scene to load"
mem() { grep -E "VmRSS|VmHWM" "/proc/$pid/status" | tr -s ' \t\n' ' '; echo "($1)"; }
mem start
for i in $(seq 1 "$rounds"); do
    xdotool mousemove 300 300 mousedown 1 mousemove 360 320 mousemove 420 340 mouseup 1
    # Each view renders for a while before the next restarts it: the pace of the soak,
    # not a wait for anything.
    xdotool mousemove 400 400 click 4
    sleep 1.2
    xdotool mousemove 400 400 click 5
    sleep 1.2
    [ "$i" = 10 ] && mem "after 10 rounds"
done
mem "end, $rounds rounds"
