# Sourced by the Xvfb window tests (xvfb_test.sh, xvfb_picture_test.sh,
# xvfb_move_test.sh) with their arguments BIN_DIR OUT_DIR: sets BIN and OUT (absolute,
# OUT created) and runs the calling test again inside its own X server (xvfb-run).
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
