#!/bin/sh
# `raytracer-view --headless SCENE --render OUT --samples N [--aa-threshold T]` writes
# exactly the file that `raytracer --samples N [--aa-threshold T] SCENE OUT` writes (the
# same renderer and settings), as PPM and as PNG; a scene with errors or a bad output
# name leaves OUT untouched.
# Usage: render_test.sh BIN_DIR SCENES_DIR OUT_DIR
set -eu
BIN=$1
SCENES=$2
OUT=$3
mkdir -p "$OUT"
export MESA_SHADER_CACHE_DISABLE=true
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$(cd "$(dirname "$0")" && pwd)/lsan.supp}"
unset DISPLAY || true

fail() { echo "FAIL: $*" >&2; exit 1; }

# The window binary execs its headless sibling; test through it when it was built.
VIEW=$BIN/raytracer-view
[ -x "$VIEW" ] || VIEW=$BIN/raytracer-view-headless
HEADLESS_FLAG=--headless
[ "$VIEW" = "$BIN/raytracer-view" ] || HEADLESS_FLAG=

# (The last case with adaptive anti-aliasing: the same threshold, the same bytes.)
for case in glass.ppm glass.png csg-nested.ppm showcase.ppm:0.1; do
    aa=
    case $case in *:*) aa="--aa-threshold ${case#*:}"; case=${case%:*} ;; esac
    scene=${case%.*}
    ext=${case##*.}
    {
        ref=$OUT/$scene-raytracer.$ext
        got=$OUT/$scene-view.$ext
        rm -f "$ref" "$got"
        # shellcheck disable=SC2086  # aa and HEADLESS_FLAG are empty or words
        "$BIN/raytracer" --quiet --samples 4 $aa "$SCENES/$scene.txt" "$ref" || fail "raytracer failed on $scene"
        # shellcheck disable=SC2086
        "$VIEW" $HEADLESS_FLAG "$SCENES/$scene.txt" --render "$got" --samples 4 $aa \
            || fail "raytracer-view --render failed on $scene"
        cmp "$ref" "$got" || fail "$scene.$ext $aa: --render differs from raytracer's file"
        echo "$scene.$ext $aa: identical ($(wc -c < "$got") bytes)"
    }
done

# Errors: exit status as raytracer's, the existing file kept.
keep=$OUT/keep.ppm
printf 'P6\n1 1\n255\nabc' > "$keep"
printf 'thing { sphere { radius } }\nend\n' > "$OUT/bad.txt"
set +e
"$BIN/raytracer-view-headless" "$OUT/bad.txt" --render "$keep" --samples 4 2> "$OUT/bad.err"
status=$?
set -e
[ "$status" = 1 ] || fail "a scene with errors: exit status $status, expected 1"
grep -q "bad.txt:1:" "$OUT/bad.err" || fail "a scene with errors: no file:line: message"
[ "$(cat "$keep")" = "$(printf 'P6\n1 1\n255\nabc')" ] || fail "a scene with errors changed the existing output"
set +e
"$BIN/raytracer-view-headless" "$SCENES/glass.txt" --render "$OUT/out.jpg" 2> /dev/null
status=$?
set -e
[ "$status" = 2 ] || fail "a .jpg output: exit status $status, expected 2"
[ ! -e "$OUT/out.jpg" ] || fail "a .jpg output was written"
echo "render test: ok"
