# Sourced by the journeys that kill the viewer (j60-j69), after lib.sh.
#   select_outline ITEM     select ITEM (object_2, light_1...) in the Objects tab's outline
#   wait_changed KEY OLD    wait (no input) until state KEY is no longer OLD
#   kill_viewer             SIGKILL the viewer (no handler runs) and wait for it to end
#   kill_while_writing DIR KEYS  press KEYS, SIGKILL the viewer once it opens a new
#                           file in DIR (a save under way)
#   file_untouched ORIGINAL $SCENE has ORIGINAL's bytes, and its folder nothing else
#   restore_and_save        start again on $SCENE, wait for the recovery banner, click
#                           Restore, save (Ctrl+S), and wait until the title is clean

# An X client of our own for the whole journey: when the viewer, the last client, is
# killed, Xvfb would reset the server, and an xdotool call meanwhile finds no display.
xprop -root -spy > /dev/null 2>&1 &

select_outline() {
    local tx ty tw th
    read -r tx ty tw th <<< "$(state tab_Objects)"
    click $((tx + tw / 2)) $((ty + th / 2))
    click_item "outline_$1"
    wait_state selection "^$1$"
    idle 0.5
}

wait_changed() {
    local k=$1 was=$2
    wait_until '[ "$(state "$k")" != "$was" ]' 10 "'$k' to change from '$was'"
}

kill_viewer() {
    kill -KILL "$VIEWER_PID"
    wait "$VIEWER_PID" 2>/dev/null || true
    VIEWER_PID=
}

# Presses KEYS, then SIGKILLs the viewer as soon as it opens a new file in DIR (a save
# under way); fails if none is seen within a minute. Polled in one process (a `find`
# per poll is too slow to see a save of 20 MB) over the viewer's /proc/PID/fd links
# (an unnamed new file reads "DIR/#INODE (deleted)"); the files it had open before
# the keys (its output, the layout) are not the save.
kill_while_writing() {
    python3 - "$VIEWER_PID" "$1" "$2" << 'PY' || fail "no save was seen in progress"
import os, signal, subprocess, sys, time
pid, folder, keys = sys.argv[1], sys.argv[2].rstrip("/") + "/", sys.argv[3]
def open_files():
    out = set()
    for fd in os.listdir(f"/proc/{pid}/fd"):
        try:
            out.add(os.readlink(f"/proc/{pid}/fd/{fd}"))
        except OSError:
            pass
    return out
before = open_files()
subprocess.Popen(["xdotool", "key", keys])
end = time.monotonic() + 60
while time.monotonic() < end:
    try:
        new = [f for f in open_files() - before if f.startswith(folder)]
    except FileNotFoundError:
        sys.exit(1)
    if new:
        os.kill(int(pid), signal.SIGKILL)
        print("killed while writing", new[0])
        sys.exit(0)
sys.exit(1)
PY
    wait "$VIEWER_PID" 2>/dev/null || true
    VIEWER_PID=
}

file_untouched() {
    cmp -s "$SCENE" "$1" || fail "the scene file changed on disk"
    local others
    others=$(find "$(dirname "$SCENE")" -maxdepth 1 -name ".$(basename "$SCENE").*")
    [ -z "$others" ] || fail "left beside the scene: $others"
}

restore_and_save() {
    start_viewer "$SCENE" --samples 4
    wait_state banner "^recovery$" 10
    click_item button_restore_recovered
    wait_state banner "^none$"
    wait_state text "^unapplied"
    save
}
