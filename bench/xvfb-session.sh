# Sourced by the window benchmarks (viewer-bench.sh, move-drag-bench.sh) once BIN, DNUM
# and OUT are set: checks the programs they name in NEED, starts an Xvfb server on
# display DNUM (1280x800) with the viewer's settings kept in OUT, and kills it and every
# process added to PIDS on exit. load() prints the load average beside the figures.
for t in "${NEED[@]}"; do
    [ -x "$BIN/$t" ] || { echo "missing $BIN/$t (build it first)" >&2; exit 2; }
done
for t in Xvfb xdotool; do command -v $t > /dev/null || { echo "missing $t" >&2; exit 2; }; done
export DISPLAY=:$DNUM MESA_SHADER_CACHE_DISABLE=true
export XDG_CONFIG_HOME=$OUT/config XDG_STATE_HOME=$OUT/state
PIDS=()
cleanup() { for p in "${PIDS[@]}"; do kill "$p" 2> /dev/null || true; done; }
trap cleanup EXIT
Xvfb ":$DNUM" -screen 0 "${XVFB_SCREEN:-1920x1080x24}" -nolisten tcp > /dev/null 2>&1 &
PIDS+=($!)
sleep 1
load() { cut -d' ' -f1-3 /proc/loadavg; }
# drag X Y X0 Y0 DX: presses the left button at X Y, then moves the pointer 60 times at
# 30 events a second, to X0 + i * DX, Y0 + i / 2 for i = 1..60, and releases it. The
# events come from one xdotool process (a hand on a mouse costs the machine next to
# nothing); DRAG_EVENTS=each starts an xdotool, a date, an awk and a sleep per event
# instead (that loop takes ~40 % of two cores itself: its figures are lower).
drag() {
    local x=$1 y=$2 x0=$3 y0=$4 dx=$5 i t0 moves=()
    xdotool mousemove "$x" "$y" mousedown 1
    if [ "${DRAG_EVENTS:-one}" = each ]; then
        t0=$(date +%s.%N)
        for i in $(seq 1 60); do
            xdotool mousemove $((x0 + i * dx)) $((y0 + i / 2))
            # 30 events a second, whatever xdotool itself took
            sleep "$(awk -v t0="$t0" -v i="$i" -v now="$(date +%s.%N)" 'BEGIN { d = t0 + i / 30 - now; printf "%.4f\n", (d > 0 ? d : 0) }')"
        done
    else
        for i in $(seq 1 60); do moves+=(mousemove $((x0 + i * dx)) $((y0 + i / 2)) sleep 0.0333); done
        xdotool "${moves[@]}"
    fi
    xdotool mouseup 1
}
