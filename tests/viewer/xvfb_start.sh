# Sourced by the Xvfb window tests (xvfb_test.sh, xvfb_picture_test.sh,
# xvfb_move_test.sh) with their arguments BIN_DIR OUT_DIR: sets BIN and OUT (absolute,
# OUT created), runs the calling test again inside its own X server (xvfb-run), and
# there gives it the helpers below.
BIN=$(cd "$1" && pwd)
OUT=$2
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)

if [ "${RTVIEW_XVFB_INNER:-}" != 1 ]; then
    export RTVIEW_XVFB_INNER=1
    # RTVIEW_XVFB_DISPLAY=N picks the display number (machines shared by several runs).
    if [ -n "${RTVIEW_XVFB_DISPLAY:-}" ]; then
        exec xvfb-run -n "$RTVIEW_XVFB_DISPLAY" -s "-screen 0 1280x800x24" "$0" "$BIN" "$OUT"
    fi
    exec xvfb-run -a -s "-screen 0 1280x800x24" "$0" "$BIN" "$OUT"
fi

HERE=$(cd "$(dirname "$0")" && pwd)
TOOL=$BIN/rtview-imgtool
export MESA_SHADER_CACHE_DISABLE=true
export XDG_CONFIG_HOME=$OUT/config
export XDG_STATE_HOME=$OUT/state   # recovery copies of this run only
# In sanitizer builds: X11, GLFW and Mesa are not instrumented, so LeakSanitizer can
# neither unwind nor attribute their allocations; leaks in our code are checked by the
# unit tests and the headless test. Address and UB checks stay on.
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=0}"
export TSAN_OPTIONS="${TSAN_OPTIONS:-suppressions=$HERE/tsan.supp}"

# The viewer the test starts (VIEWER_PID) is stopped however the test ends.
VIEWER_PID=
cleanup() { [ -n "$VIEWER_PID" ] && kill "$VIEWER_PID" 2>/dev/null || true; }
trap cleanup EXIT
# A failure keeps a screenshot and shows what the viewer printed (its stdout, when the
# test keeps it in viewer.out, and its stderr in viewer.err).
fail() {
    echo "FAIL: $*" >&2
    import -window root "$OUT/failure.png" 2>/dev/null || true
    if [ -s "$OUT/viewer.out" ]; then
        echo "--- viewer stdout (last lines):" >&2
        tail -n 20 "$OUT/viewer.out" >&2 || true
    fi
    echo "--- viewer stderr:" >&2
    cat "$OUT/viewer.err" >&2 || true
    exit 1
}
step() { echo "== $*"; }
shot() { import -window root "$OUT/$1.png"; }
title() { xdotool getwindowname "$WID"; }
# shellcheck source=wait_until.sh
source "$HERE/wait_until.sh"
# wait_for WHAT COMMAND...: wait_until COMMAND succeeds (within 60 s), or fails saying
# it waited in vain for WHAT.
wait_for() {
    local what=$1 _wf_cmd
    shift
    _wf_cmd=("$@")
    wait_until '"${_wf_cmd[@]}"' 60 "$what"
}
title_is() { [[ "$(title)" == "$1" ]]; }
# The last value of a --print-layout line (the viewer prints the layout again when it
# changes) in $LAYOUT: field NAME K is its K-th number, region NAME all four.
LAYOUT=$OUT/layout.txt
field() { awk -v n="$1" -v k="$2" '$1 == n { v = $(k + 1) } END { print v }' "$LAYOUT"; }
region() { echo "$(field "$1" 1) $(field "$1" 2) $(field "$1" 3) $(field "$1" 4)"; }
# The last value of a "state KEY VALUE" line (what the last frame that changed it showed).
state() { awk -v k="$1" '$1 == "state" && $2 == k { sub("^state " k " ?", ""); v = $0 } END { print v }' "$LAYOUT"; }
# pointer_to X Y: moves the pointer to (X, Y) and waits for a frame that saw it there.
pointer_to() {
    local px=$1 py=$2
    xdotool mousemove "$px" "$py"
    wait_until '[[ "$(state pointer)" =~ ^"$px $py"( |$) ]]' 10 "a frame with the pointer at $px $py"
}
# input_seen: waits until the viewer has taken every input event sent so far: X
# delivers them in order, so a frame that saw the pointer move a pixel away and back
# saw them too.
input_seen() {
    local X Y SCREEN WINDOW
    eval "$(xdotool getmouselocation --shell)"
    pointer_to $((X + 1)) "$Y"
    pointer_to "$X" "$Y"
}
# quit_viewer: Ctrl+Q, and waits for the process to end.
quit_viewer() {
    xdotool key ctrl+q
    wait_until '! kill -0 "$VIEWER_PID" 2>/dev/null' 10 "the window to close on Ctrl+Q"
    wait "$VIEWER_PID" 2>/dev/null || true
    VIEWER_PID=
}

# wait_stable NAME: screenshots (NAME.png) until the image region ($IMAGE) shows a
# picture and stops changing (the render has converged); a black region that "stays
# the same" is not a picture. Every $STABLE_PAUSE seconds, at most $STABLE_TRIES times.
STABLE_PAUSE=0.5
STABLE_TRIES=240
wait_stable() {
    local name=$1 prev="$OUT/.stable-prev.png" d
    shot "$name"
    for _ in $(seq 1 "$STABLE_TRIES"); do
        # The time over which the picture must not change: the wait itself is what
        # "settled" means here (a bounded poll).
        sleep "$STABLE_PAUSE"
        cp "$OUT/$name.png" "$prev"
        shot "$name"
        d=$("$TOOL" diff "$prev" "$OUT/$name.png" $IMAGE)
        [ "$d" = "0.000000" ] && [ "$("$TOOL" colours "$OUT/$name.png" $IMAGE)" -gt 1000 ] && return 0
    done
    fail "the image never settled ($name)"
}
