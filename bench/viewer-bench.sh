#!/usr/bin/env bash
# raytracer-view against the targets of its "live view" round, under Xvfb:
#   1. picture updates a second during a 2 s drag at 30 pointer events a second on the
#      default scene (1280x800 window), quiet and with two busy processes, and the
#      longest time the image area stood still (counted on screen by rtview-xframes);
#   2. on a 1,000,000-sphere grid: the viewer's first picture against `raytracer`'s
#      whole run, the window's first frame, RSS growth over 10 wheel notches, the last
#      notch's time to a new picture, peak RSS against `raytracer`'s, and whether
#      navigating marked the document modified.
# The machine's load is printed with the figures: timings on a shared machine mean
# little without it.
#   bench/viewer-bench.sh [BIN_DIR] [DISPLAY_NUMBER] [GRID_FILE]
#   (defaults: build/bin, 92, /tmp/grid1m.txt, made with bench/make-grid.sh 1000)
# DRAG_SCENE=FILE drags (orbits) on FILE instead of the default scene (issue 27: the
# 1M-triangle mesh of bench/make-mesh.sh); DRAG_ONLY=1 stops after the drags;
# VIEW_SIZE=WxH sizes the window (1715x818 gives a 1280x720 image area beside the
# sidebar; the X screen is XVFB_SCREEN, 1920x1080x24). The drag's events come from one
# xdotool process; DRAG_EVENTS=each starts an xdotool, a date, an awk and a sleep per
# event instead (that loop takes ~40 % of two cores itself: its figures are lower).
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
BIN=$(cd "${1:-$HERE/../build/bin}" && pwd)
DNUM=${2:-92}
GRID=${3:-/tmp/grid1m.txt}
RUNS=${RUNS:-3}
OUT=$(mktemp -d /tmp/viewer-bench.XXXXXX)
NEED=(raytracer raytracer-view rtview-xframes)
# shellcheck source=bench/xvfb-session.sh
. "$HERE/xvfb-session.sh"
[ "${DRAG_ONLY:-0}" = 1 ] || [ -s "$GRID" ] || "$HERE/make-grid.sh" 1000 "$GRID"

# start_viewer SCENE LOG: starts the viewer with --verbose, waits for its first picture.
start_viewer() {
    "$BIN/raytracer-view" "$1" --size "${VIEW_SIZE:-1280x800}" ${VIEW_ARGS:-} --print-layout -v > "$OUT/layout.txt" 2> "$2" &
    VP=$!
    PIDS+=($VP)
    for _ in $(seq 1 1200); do grep -q "first picture" "$2" && break; sleep 0.1; done
    grep -q "first picture" "$2" || { echo "no picture from the viewer" >&2; exit 1; }
    sleep 1
    read -r IX IY IW IH <<< "$(awk '$1 == "image" { v = $2 " " $3 " " $4 " " $5 } END { print v }' "$OUT/layout.txt")"
    CX=$((IX + IW / 2)); CY=$((IY + IH / 2))
}
stop_viewer() {
    xdotool key ctrl+q
    for _ in $(seq 1 50); do kill -0 "$VP" 2> /dev/null || return 0; sleep 0.1; done
    kill "$VP" 2> /dev/null || true
}

# drag_run BUSY: one 2 s drag; prints "changes max_gap_ms median_block image_size".
drag_run() {
    local busy=$1 bp=()
    start_viewer "${DRAG_SCENE:-$HERE/../scenes/default.txt}" "$OUT/drag.err"
    if [ "$busy" = 1 ]; then
        yes > /dev/null & bp+=($!)
        yes > /dev/null & bp+=($!)
        sleep 0.5
    fi
    # The middle of the image area: every new picture of the orbit changes it, and
    # sampling a quarter of the area keeps the counting from loading the X server.
    "$BIN/rtview-xframes" $((IX + IW / 4)) $((IY + IH / 4)) $((IW / 2)) $((IH / 2)) 10 2.0 > "$OUT/frames.txt" &
    local xf=$!
    drag "$CX" "$CY" $((CX - 90)) "$CY" 3
    wait "$xf"
    for p in "${bp[@]}"; do kill "$p"; done
    stop_viewer
    # The preview's block size, from the viewer's own log of each view change.
    local block
    block=$(sed -n 's/.*(preview[^)]*, block \([0-9]*\)).*/\1/p' "$OUT/drag.err" | sort -n |
        awk '{ v[NR] = $1 } END { print (NR ? v[int((NR + 1) / 2)] : "none") }')
    echo "$(awk '/^changes/ { print $2, $6 }' "$OUT/frames.txt") $block ${IW}x${IH}"
}

echo "raytracer-view bench, $(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores, load average before: $(load)"
echo
for busy in 0 1; do
    rates=() gaps=() blocks=()
    for _ in $(seq 1 "$RUNS"); do
        read -r c g b IMAGE_SIZE <<< "$(drag_run $busy)"
        rates+=("$(awk -v c="$c" 'BEGIN { printf "%.1f", c / 2.0 }')")
        gaps+=("$g")
        blocks+=("$b")
    done
    label=$([ "$busy" = 1 ] && echo "two busy processes" || echo "no extra load")
    echo "drag, $(basename "${DRAG_SCENE:-default.txt}"), window ${VIEW_SIZE:-1280x800} (image ${IMAGE_SIZE}), $label: picture updates/s ${rates[*]}; longest still gap ms ${gaps[*]};" \
        "median preview block ${blocks[*]} on $(nproc) threads (load $(load))"
done
[ "${DRAG_ONLY:-0}" = 1 ] && { rm -rf "$OUT"; exit 0; }

echo
/usr/bin/time -f "%e %M" "$BIN/raytracer" "$GRID" "$OUT/grid.ppm" 2> "$OUT/cli.time" > /dev/null
read -r CLI_S CLI_KB <<< "$(tail -1 "$OUT/cli.time")"
echo "raytracer on $(basename "$GRID"): ${CLI_S} s whole run, peak RSS $((CLI_KB / 1024)) MB (load $(load))"

start_viewer "$GRID" "$OUT/big.err"
FIRST_FRAME=$(awk '/first frame drawn at/ { print $(NF - 1) }' "$OUT/big.err")
FIRST_PICTURE=$(awk '/first picture on screen at/ { print $(NF - 1) }' "$OUT/big.err")
RSS0=$(awk '/VmRSS/ { print $2 }' /proc/$VP/status)
for _ in $(seq 1 9); do
    xdotool mousemove $CX $CY click 4
    sleep 0.8
done
# The last notch, timed from outside: from the click to the first change on screen.
"$BIN/rtview-xframes" $((IX + IW / 4)) $((IY + IH / 4)) $((IW / 2)) $((IH / 2)) 5 1.5 > "$OUT/notch.txt" &
XF=$!
sleep 0.3
T_CLICK=$(date +%s.%N)
xdotool mousemove $CX $CY click 4
wait "$XF"
LAST_NOTCH=$(awk -v tc="$T_CLICK" '/^start/ { s = $2 } / change / && !done { t = s + $1; if (t > tc) { printf "%.0f", (t - tc) * 1000; done = 1 } }
    END { if (!done) print "none" }' "$OUT/notch.txt")
sleep 1.5
RSS1=$(awk '/VmRSS/ { print $2 }' /proc/$VP/status)
HWM=$(awk '/VmHWM/ { print $2 }' /proc/$VP/status)
TITLE=$(xdotool search --name 'grid' getwindowname 2> /dev/null | head -1)
stop_viewer
echo "viewer on $(basename "$GRID"): first frame drawn at ${FIRST_FRAME} s, first picture at ${FIRST_PICTURE} s (load $(load))"
echo
printf '%-58s %-14s %s\n' "measure" "result" "target"
printf '%-58s %-14s %s\n' "1M grid: viewer's first picture / raytracer's whole run" \
    "$(awk -v a="$FIRST_PICTURE" -v b="$CLI_S" 'BEGIN { printf "%.2fx", a / b }')" "<= 1.5x"
printf '%-58s %-14s %s\n' "1M grid: RSS growth after 10 wheel notches" "$(((RSS1 - RSS0) / 1024)) MB" "<= 64 MB"
printf '%-58s %-14s %s\n' "1M grid: last wheel notch -> new picture" "${LAST_NOTCH} ms" "<= 300 ms"
printf '%-58s %-14s %s\n' "window painted after start (1M grid)" "${FIRST_FRAME} s" "<= 0.5 s"
printf '%-58s %-14s %s\n' "viewer peak RSS / raytracer peak RSS, 1M grid" \
    "$(awk -v a="$HWM" -v b="$CLI_KB" 'BEGIN { printf "%.2fx", a / b }') ($((HWM / 1024)) MB)" "<= 1.5x"
printf '%-58s %-14s %s\n' "'*' in the title after navigating" \
    "$(case "$TITLE" in *'*'*) echo yes ;; *) echo no ;; esac)" "no"
rm -rf "$OUT"
