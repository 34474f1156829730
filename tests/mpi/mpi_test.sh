#!/usr/bin/env bash
# Checks of raytracer-mpi on this one machine, run by ctest (tests/mpi/CMakeLists.txt)
# or by hand. Each mode starts a small MPI job; all finish in seconds.
#
#   mpi_test.sh identical NP SCENE [OPTIONS...] [-- MPI_OPTIONS...]
#                                                raytracer-mpi on NP ranks gives the
#                                                same PPM bytes as raytracer; options
#                                                after -- go to raytracer-mpi only
#   mpi_test.sh parse-error                      one error line, every rank non-zero,
#                                                no output
#   mpi_test.sh crash                            a rank aborting mid-render fails the
#                                                job and leaves OUT untouched
#   mpi_test.sh print-scene                      --print-scene prints what raytracer
#                                                prints, defaults of block-less shapes too
#
# Environment (defaults for a build in build/): RT_BIN (raytracer), RT_MPI_BIN
# (raytracer-mpi), MPIEXEC (mpiexec), RT_SOURCE_DIR (the repository).
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/../.." && pwd)
RT_SOURCE_DIR=${RT_SOURCE_DIR:-$ROOT}
RT_BIN=${RT_BIN:-$ROOT/build/bin/raytracer}
RT_MPI_BIN=${RT_MPI_BIN:-$ROOT/build/bin/raytracer-mpi}
MPIEXEC=${MPIEXEC:-mpiexec}
# No display for the job: hwloc's GL component opens any X display it finds, and when
# that server goes away (a viewer test's Xvfb ending meanwhile) Xlib ends the process
# ("X connection to :0 broken").
unset DISPLAY
export HWLOC_COMPONENTS=-gl

fail() { echo "FAIL: $*" >&2; exit 1; }

[ -x "$RT_MPI_BIN" ] || fail "no raytracer-mpi at $RT_MPI_BIN"
# Open MPI refuses root (even for --version) and more ranks than cores unless told
# otherwise; CI runs as root on a 2-core machine. Other MPIs ignore these variables.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
MPI_FLAGS=()
version=$("$MPIEXEC" --version 2>&1 || true)
if [[ $version == *"Open MPI"* || $version == *OpenRTE* ]]; then  # mpirun / mpiexec
    MPI_FLAGS+=(--oversubscribe)
fi
# In a sanitizer build: Open MPI never frees some of its own memory, much of it from
# plugins it has unloaded by exit (so no suppression can name them); LeakSanitizer
# would fail every run. Memory errors and undefined behaviour are still caught.
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
# A stuck job must fail the test, not hang it.
mpirun_np() { local np=$1; shift; timeout 120 "$MPIEXEC" "${MPI_FLAGS[@]}" -np "$np" "$@"; }

TMP=$(mktemp -d)
# Each job's Open MPI session directory in a folder of this test's own: two jobs started
# at once (ctest -j2) raced to make the shared /tmp/ompi.HOST.UID ("mkdir ... File
# exists", orte_init failed), once in some 400 runs.
SESSION=$(mktemp -d)
trap 'rm -rf "$TMP" "$SESSION"' EXIT
export TMPDIR=$SESSION

mode=${1:-}
shift || true
case $mode in
identical)
    [ $# -ge 2 ] || fail "usage: mpi_test.sh identical NP SCENE [OPTIONS...]"
    np=$1 scene=$RT_SOURCE_DIR/$2
    shift 2
    common=() mpi_only=()
    while [ $# -gt 0 ] && [ "$1" != -- ]; do common+=("$1"); shift; done
    [ $# -eq 0 ] || { shift; mpi_only=("$@"); }
    set -- "${common[@]}"
    [ -x "$RT_BIN" ] || fail "no raytracer at $RT_BIN"
    ext=${OUT_EXT:-ppm}  # pfm or exr: the films' floats compared
    "$RT_BIN" "$scene" "$TMP/single.$ext" --quiet "$@" || fail "raytracer failed"
    mpirun_np "$np" "$RT_MPI_BIN" "$scene" "$TMP/mpi.$ext" --quiet --stats "$@" "${mpi_only[@]}" 2> "$TMP/log" ||
        { cat "$TMP/log" >&2; fail "raytracer-mpi failed"; }
    cat "$TMP/log"
    cmp "$TMP/single.$ext" "$TMP/mpi.$ext" || fail "$* on $np ranks: the pictures differ"
    echo "ok: $(basename "$scene") $* ${mpi_only[*]} on $np ranks is bit-identical ($(stat -c %s "$TMP/mpi.$ext") bytes, .$ext)"
    ;;
parse-error)
    # One error: a word where a number belongs.
    sed 's/radius 1.2/radius one/' "$RT_SOURCE_DIR/scenes/sphere.txt" > "$TMP/bad.txt"
    status=0
    mpirun_np 3 "$RT_MPI_BIN" "$TMP/bad.txt" "$TMP/out.ppm" > "$TMP/log" 2>&1 || status=$?
    cat "$TMP/log"
    [ "$status" -ne 0 ] || fail "a parse error gave exit status 0"
    [ "$status" -ne 124 ] || fail "the job hung"
    n=$(grep -c ': error:' "$TMP/log" || true)
    [ "$n" -eq 1 ] || fail "expected 1 error line, got $n"
    grep -q "^$TMP/bad.txt:7:12: error: " "$TMP/log" || fail "the error line is not FILE:LINE:COL: error: MESSAGE"
    [ ! -e "$TMP/out.ppm" ] || fail "a picture was written"
    echo "ok: one error line, exit status $status, nothing written"
    ;;
crash)
    # Rank 1 aborts after sending its first tile. 20 tiles of 32x32, and rank 0 hands
    # each worker 3 at the start: the others rank 1 held are lost, so the render
    # cannot complete, and only mpirun ending the job keeps the test from hanging.
    echo untouched > "$TMP/out.ppm"
    ulimit -c 0  # no core file from the abort
    status=0
    RAYTRACER_MPI_TEST_CRASH_RANK=1 mpirun_np 3 "$RT_MPI_BIN" "$RT_SOURCE_DIR/scenes/showcase.txt" "$TMP/out.ppm" \
        --width 160 --height 120 --samples 2 --quiet > "$TMP/log" 2>&1 || status=$?
    grep -v '^\[.*\] \[ *[0-9]*\] ' "$TMP/log" || true  # the output, without the backtrace
    [ "$status" -ne 0 ] || fail "the job succeeded although rank 1 died"
    [ "$status" -ne 124 ] || fail "the job hung after rank 1 died"
    grep -q 'aborting on purpose' "$TMP/log" || fail "rank 1 did not reach its abort"
    [ "$(cat "$TMP/out.ppm")" = untouched ] || fail "OUT was overwritten"
    [ "$(ls "$TMP" | grep -vc -e '^out.ppm$' -e '^log$')" -eq 0 ] || fail "temporary files left: $(ls "$TMP")"
    echo "ok: exit status $status, OUT untouched"
    ;;
print-scene)
    # A sphere and a plane without a material block: both get the block-less default
    # (translusans 0, where a written block defaults to 1), written out in full.
    cat > "$TMP/scene.txt" <<'EOF'
thing {
  sphere { material { colour 0.9 0.2 0.15 } position 6 0 1.2 radius 1.2 }
  sphere { position 4.5 1.9 0.5 radius 0.5 }
}
special_thing { plane { point 1 0 0 0  point 2 1 0 0  point 3 0 1 0  point 4 0 0 2 } }
light { lamp { colour 60 56 52 position 3 3 6 } }
camera { position 0 0 2 centre 6 0 0.8 up 6 0 1.8 angle_x 60 angle_y 45 }
picture_size { x_max 48 y_max 36 }
end
EOF
    [ -x "$RT_BIN" ] || fail "no raytracer at $RT_BIN"
    "$RT_BIN" --print-scene "$TMP/scene.txt" > "$TMP/single.txt" || fail "raytracer failed"
    mpirun_np 2 "$RT_MPI_BIN" --print-scene "$TMP/scene.txt" > "$TMP/mpi.txt" || fail "raytracer-mpi failed"
    cat "$TMP/mpi.txt"
    n=$(grep -c '^ *material { ' "$TMP/mpi.txt" || true)
    [ "$n" -eq 3 ] || fail "expected a material block for each of the 3 shapes, got $n"
    n=$(grep -c '^ *material { .* translusans 0 ' "$TMP/mpi.txt" || true)
    [ "$n" -eq 2 ] || fail "expected the block-less default (translusans 0) on 2 shapes, got $n"
    cmp "$TMP/single.txt" "$TMP/mpi.txt" || fail "raytracer-mpi and raytracer print different scenes"
    echo "ok: raytracer-mpi --print-scene prints what raytracer prints"
    ;;
*)
    sed -n '2,20p' "$0" | sed 's/^# \{0,1\}//' >&2
    exit 2
    ;;
esac
