#!/usr/bin/env bash
# Scaling of raytracer-mpi over 1, 2 and 4 ranks on this machine, against raytracer,
# on bench/scenes/things-like.txt; prints markdown tables (see the MPI section of bench/README.md).
#
#   bench/mpi.sh [OPTIONS]
#
#   -r, --runs N        runs per measurement (default 3); the median is reported
#   -b, --build DIR     build folder with bin/raytracer and bin/raytracer-mpi
#                       (default: build-mpi, else build)
#   -S, --scene FILE    scene (default bench/scenes/things-like.txt)
#   -W, --width N       picture width (default: the scene's)
#   -H, --height N      picture height (default: the scene's)
#   -n, --samples N     samples per pixel (default 1)
#   -T, --no-tiles      skip the tile-size sweep
#   -p, --priority      measure in a session of its own whose CPU weight is raised
#                       (autogroup nice -10; needs root and Linux autogroups), so
#                       that other jobs on a shared machine disturb the figures less
#   -q, --quick         160x90, 1 run: checks that the script works
#   -h, --help          this text
#
# Series: raytracer with 1 and all threads; raytracer-mpi on 1 rank x 1 thread, on
# 1, 2, 4 ranks with threads per rank = cores / ranks (at least 1), on 2 and 4 ranks
# with the default threads (all cores in every rank), and 1 rank under mpirun's
# default binding; then tiles of 16, 32, 64 on 2 ranks x 1 thread. Ranks run with
# --bind-to none except in that one row. Every picture is compared with raytracer's
# (cmp): a timing of a wrong picture is void.
set -euo pipefail

HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/.." && pwd)
RUNS=3 BUILD= SCENE= W= H= SAMPLES=1 TILES=1 QUICK=0 PRIORITY=0
ARGS=("$@")

usage() { sed -n '2,25p' "$0" | sed 's/^# \{0,1\}//'; }
need_value() { [ $# -ge 2 ] || { echo "mpi.sh: $1 needs a value" >&2; exit 2; }; }
while [ $# -gt 0 ]; do
    case $1 in
        -r|--runs) need_value "$@"; RUNS=$2; shift ;;
        -b|--build) need_value "$@"; BUILD=$2; shift ;;
        -S|--scene) need_value "$@"; SCENE=$2; shift ;;
        -W|--width) need_value "$@"; W=$2; shift ;;
        -H|--height) need_value "$@"; H=$2; shift ;;
        -n|--samples) need_value "$@"; SAMPLES=$2; shift ;;
        -T|--no-tiles) TILES=0 ;;
        -p|--priority) PRIORITY=1 ;;
        -q|--quick) QUICK=1 ;;
        -h|--help) usage; exit 0 ;;
        *) echo "mpi.sh: unknown argument '$1'" >&2; usage >&2; exit 2 ;;
    esac
    shift
done
[[ $RUNS =~ ^[1-9][0-9]*$ ]] || { echo "mpi.sh: --runs must be a positive integer" >&2; exit 2; }
# With autogroups the scheduler shares the CPUs between sessions first, whatever the
# processes' nice values: in a busy session of its own with a higher weight, the
# benchmark gets the cores it asks for. (setsid makes the new session; the child
# raises its weight and runs the measurements.)
if [ $PRIORITY = 1 ] && [ -z "${RT_MPI_BENCH_SESSION:-}" ]; then
    [ -w /proc/self/autogroup ] || { echo "mpi.sh: --priority needs root and /proc/self/autogroup" >&2; exit 2; }
    RT_MPI_BENCH_SESSION=1 exec setsid --wait "$0" "${ARGS[@]}"
fi
PRIO_NOTE=
if [ -n "${RT_MPI_BENCH_SESSION:-}" ]; then
    echo -10 > /proc/self/autogroup
    PRIO_NOTE="; own session, $(cat /proc/self/autogroup | sed 's/^[^ ]* //')"
fi
if [ -z "$BUILD" ]; then
    BUILD=$ROOT/build-mpi
    [ -x "$BUILD/bin/raytracer-mpi" ] || BUILD=$ROOT/build
fi
RT=$BUILD/bin/raytracer RTMPI=$BUILD/bin/raytracer-mpi
for b in "$RT" "$RTMPI"; do
    [ -x "$b" ] || { echo "mpi.sh: no $b (configure with -DRAYTRACER_MPI=ON and build, or pass -b)" >&2; exit 2; }
done
if [ -z "$SCENE" ]; then
    SCENE=$HERE/scenes/things-like.txt
    [ -f "$SCENE" ] || SCENE=/work/shared/bench/things-like.txt
fi
[ -f "$SCENE" ] || { echo "mpi.sh: no scene $SCENE" >&2; exit 2; }
if [ $QUICK = 1 ]; then RUNS=1 W=160 H=90; fi
SIZE=()
[ -z "$W" ] || SIZE+=(--width "$W")
[ -z "$H" ] || SIZE+=(--height "$H")

# Open MPI: allow root (CI) and more ranks than cores (the 4-rank runs).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
MPIRUN=(mpirun)
if [[ $(mpirun --version 2>&1 || true) == *"Open MPI"* ]]; then MPIRUN+=(--oversubscribe); fi
CORES=$(nproc)

OUT=$(mktemp -d "${TMPDIR:-/tmp}/rt-mpi-bench.XXXXXX")
trap 'rm -rf "$OUT"' EXIT

median() { printf '%s\n' "$@" | sort -g | awk '{ v[NR] = $1 } END {
    if (NR % 2) printf "%.3f\n", v[(NR + 1) / 2]; else printf "%.3f\n", (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (b == 0) print "n/a"; else printf "%.2f\n", a / b }'; }

# One run: wall and CPU seconds (user + sys of the whole process tree, mpirun's
# children included) into $OUT/time, the program's --stats into $OUT/log.
timed() {
    local TIMEFORMAT='%R %U %S'
    { time "$@" > /dev/null 2> "$OUT/log"; } 2> "$OUT/time" || { cat "$OUT/log" >&2; echo "mpi.sh: failed: $*" >&2; exit 1; }
}
# Median figures of RUNS runs of a command; the picture must equal the reference.
# Prints: wall cpu render_seconds Mrays_per_s MiB_received
measure() {
    local walls=() cpus=() renders=() rates=() mib=0
    for _ in $(seq "$RUNS"); do
        timed "$@"
        read -r wall user sys < "$OUT/time"
        walls+=("$wall")
        cpus+=("$(awk -v u="$user" -v s="$sys" 'BEGIN { print u + s }')")
        renders+=("$(sed -n 's/.*render \([0-9.]*\) s.*/\1/p' "$OUT/log")")
        rates+=("$(sed -n 's/.*(\([0-9.]*\) M rays\/s).*/\1/p' "$OUT/log")")
        mib=$(sed -n 's/.*received \([0-9.]*\) MiB.*/\1/p' "$OUT/log")
        cmp -s "$OUT/ref.ppm" "$OUT/pic.ppm" || { echo "mpi.sh: picture differs from raytracer's: $*" >&2; exit 1; }
        rm -f "$OUT/pic.ppm"
    done
    echo "$(median "${walls[@]}") $(median "${cpus[@]}") $(median "${renders[@]}") $(median "${rates[@]}") ${mib:-0}"
}

"$RT" "$SCENE" "$OUT/ref.ppm" --quiet "${SIZE[@]}" --samples "$SAMPLES"
read -r _ PW PH _ < <(head -c 32 "$OUT/ref.ppm" | LC_ALL=C tr -d '\000' | LC_ALL=C tr '\n' ' '; echo)

echo "Machine: $(lscpu 2>/dev/null | sed -n 's/^Model name: *//p' | head -1), $CORES CPUs;" \
     "$(date -u '+%Y-%m-%d %H:%M UTC'); load before: $(cut -d' ' -f1-3 /proc/loadavg)$PRIO_NOTE"
echo "Scene: $(basename "$SCENE") at ${PW}x$PH, $SAMPLES sample(s) per pixel; median of $RUNS runs;" \
     "$(mpirun --version 2>&1 | head -1)"
START=$( { TIMEFORMAT='%R s wall, %U s user + %S s sys'; time "${MPIRUN[@]}" -np 2 true > /dev/null 2>&1; } 2>&1 )
echo "mpirun -np 2 true (job start-up and tear-down, included in the wall and CPU columns): $START"
echo
echo "| program | ranks x threads | wall (s) | CPU (s) | render (s) | M rays/s | render speed-up | tile data received |"
echo "|---|---|---|---|---|---|---|---|"

row() {  # LABEL CONFIG FIGURES...
    local label=$1 config=$2 wall=$3 cpu=$4 render=$5 rate=$6 mib=$7
    [[ $label == raytracer-mpi* ]] && mib="$mib MiB" || mib=-
    echo "| $label | $config | $wall | $cpu | $render | $rate | $(ratio "$BASE" "$render")x | $mib |"
}

set -- $(measure "$RT" "$SCENE" "$OUT/pic.ppm" --quiet --stats "${SIZE[@]}" --samples "$SAMPLES" --threads 1)
BASE=$3  # everything is compared with one thread of raytracer
row raytracer "1 x 1" "$@"
set -- $(measure "$RT" "$SCENE" "$OUT/pic.ppm" --quiet --stats "${SIZE[@]}" --samples "$SAMPLES" --threads "$CORES")
row raytracer "1 x $CORES" "$@"

mpi() {  # RANKS THREADS|default BINDING [EXTRA...]
    local np=$1 t=$2 bind=$3
    shift 3
    local topt=() bopt=()
    [ "$t" = default ] || topt=(--threads "$t")
    [ "$bind" = default ] || bopt=(--bind-to "$bind")
    measure "${MPIRUN[@]}" "${bopt[@]}" -np "$np" "$RTMPI" "$SCENE" "$OUT/pic.ppm" --quiet --stats "${SIZE[@]}" \
        --samples "$SAMPLES" "${topt[@]}" "$@"
}
# Unbound like raytracer, so that a rank's threads may use every core (Open MPI binds
# each rank to one core when it starts 2 or fewer; see the last row).
set -- $(mpi 1 1 none); row raytracer-mpi "1 x 1" "$@"
for np in 1 2 4; do
    t=$(( CORES / np )); [ $t -ge 1 ] || t=1
    set -- $(mpi "$np" "$t" none); row "raytracer-mpi, threads = cores" "$np x $t" "$@"
done
for np in 2 4; do
    set -- $(mpi "$np" default none); row "raytracer-mpi, default threads" "$np x $CORES" "$@"
done
set -- $(mpi 1 default default); row "raytracer-mpi, mpirun's default binding" "1 x 1 (bound to a core)" "$@"

if [ $TILES = 1 ]; then
    echo
    echo "| tile | tiles | ranks x threads | wall (s) | render (s) | M rays/s | tile data received |"
    echo "|---|---|---|---|---|---|---|"
    for tile in 16 32 64; do
        n=$(( ((PW + tile - 1) / tile) * ((PH + tile - 1) / tile) ))
        set -- $(mpi 2 1 none --tile "$tile")
        echo "| ${tile}x$tile | $n | 2 x 1 | $1 | $3 | $4 | $5 MiB |"
    done
fi
echo
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
