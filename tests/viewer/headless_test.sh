#!/bin/sh
# Headless screenshot test of raytracer-view (OSMesa; needs no X display):
#  - the image region of the screenshot equals a `raytracer` render of the same
#    view (same samples), within a small tolerance: by default the scene's picture at
#    its picture_size, shown letterboxed at that aspect (the letterbox left out; the
#    render drawn at the region's size as the texture is, with linear filtering), and
#    with --fit window the camera fitted to the whole area, at the area's size;
#  - the panel region is drawn (not the background colour) and the whole image is not
#    uniform; repeated with --orbit so the camera maths is on the path too.
# Usage: headless_test.sh BIN_DIR OUT_DIR   (screenshots stay in OUT_DIR to look at)
set -eu
BIN=$1
OUT=$2
TOOL=$BIN/rtview-imgtool
mkdir -p "$OUT"
export MESA_SHADER_CACHE_DISABLE=true
export XDG_CONFIG_HOME="$OUT/config"
# In sanitizer builds: Mesa's own lifetime allocations are not ours to fix.
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$(cd "$(dirname "$0")" && pwd)/lsan.supp}"
export TSAN_OPTIONS="${TSAN_OPTIONS:-suppressions=$(cd "$(dirname "$0")" && pwd)/tsan.supp}"
unset DISPLAY || true   # prove that no X server is needed

fail() { echo "FAIL: $*" >&2; exit 1; }

# field NAME N FILE: the N-th number of the layout line NAME.
field() { awk -v n="$1" -v k="$2" '$1 == n { print $(k + 1); exit }' "$3"; }

check_case() {
    name=$1; shift
    shot=$OUT/$name.png
    # Through `raytracer-view --headless` so the exec of the sibling binary is tested too.
    "$BIN/raytracer-view" --headless --screenshot "$shot" --size 960x600 --samples 2 \
        --view-scene "$OUT/$name-view.txt" --print-layout "$@" > "$OUT/$name-layout.txt" \
        || fail "$name: raytracer-view --headless exited with $?"
    [ -s "$shot" ] || fail "$name: no screenshot"
    L=$OUT/$name-layout.txt
    ix=$(field image 1 "$L"); iy=$(field image 2 "$L"); iw=$(field image 3 "$L"); ih=$(field image 4 "$L")
    sx=$(field sidebar 1 "$L"); sy=$(field sidebar 2 "$L"); sw=$(field sidebar 3 "$L"); sh=$(field sidebar 4 "$L")
    "$BIN/raytracer" --samples 2 "$OUT/$name-view.txt" "$OUT/$name-ref.ppm" \
        || fail "$name: raytracer could not render the view scene"
    echo "$name: image region $iw x $ih at $ix,$iy, film $(field film 1 "$L") x $(field film 2 "$L")"
    "$TOOL" match-scaled "$shot" "$ix" "$iy" "$iw" "$ih" "$OUT/$name-ref.ppm" \
        || fail "$name: the image region differs from the raytracer render"
    # Panels: the clear colour is (0.10, 0.10, 0.11) = 26 26 28; ImGui's window
    # background is darker, and text and widgets add many more colours.
    bg=$("$TOOL" near "$shot" "$sx" "$sy" "$sw" "$sh" 26 26 28 1)
    total=$((sw * sh))
    [ "$bg" -lt $((total / 10)) ] || fail "$name: the sidebar is mostly background ($bg of $total pixels)"
    pc=$("$TOOL" colours "$shot" "$sx" "$sy" "$sw" "$sh")
    [ "$pc" -ge 20 ] || fail "$name: the sidebar has only $pc colours (no widgets or text?)"
    all=$("$TOOL" colours "$shot" 0 0 960 600)
    [ "$all" -ge 500 ] || fail "$name: the screenshot has only $all colours"
    echo "$name: ok (sidebar $pc colours, screenshot $all colours)"
}

check_case default
check_case orbit --orbit 35 --select "object 2"
# (With a CSG operand selected: its fields are drawn from the schema.)
check_case window --fit window --select "object 4 right"
# The picture frame keeps the scene's aspect; fill-window mode takes the whole area.
aspect_ok=$(awk -v w="$(field image 3 "$OUT/default-layout.txt")" -v h="$(field image 4 "$OUT/default-layout.txt")" \
    'BEGIN { r = w / h; exit !(r > 640 / 480 - 0.01 && r < 640 / 480 + 0.01) }' && echo yes || echo no)
[ "$aspect_ok" = yes ] || fail "the default image region is not at the scene's 640x480 aspect"
# ... and renders the scene's picture at its picture_size, whatever the window's size.
[ "$(field film 1 "$OUT/default-layout.txt") $(field film 2 "$OUT/default-layout.txt")" = "640 480" ] ||
    fail "the picture frame renders a $(field film 1 "$OUT/default-layout.txt")x$(field film 2 "$OUT/default-layout.txt") film, not picture_size 640x480"
[ "$(field image 3 "$OUT/window-layout.txt")" -gt "$(field image 3 "$OUT/default-layout.txt")" ] || \
    [ "$(field image 4 "$OUT/window-layout.txt")" -gt "$(field image 4 "$OUT/default-layout.txt")" ] || \
    fail "fill-window mode does not use more of the area"
# The orbit must really have moved the camera.
cmp -s "$OUT/default-view.txt" "$OUT/orbit-view.txt" && fail "--orbit did not change the camera"
# Errors: a broken scene exits with status 1 and a compiler-style message.
printf 'thing { sphere { radius x } }\nend\n' > "$OUT/broken.txt"
if "$BIN/raytracer-view" --headless "$OUT/broken.txt" --screenshot "$OUT/broken.png" 2> "$OUT/broken.err"; then
    fail "a broken scene should fail"
fi
grep -q "broken.txt:1:25: error" "$OUT/broken.err" || fail "unexpected message: $(cat "$OUT/broken.err")"
echo "headless test passed; screenshots in $OUT"
