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
