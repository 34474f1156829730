#!/bin/bash
# The turn and size handles in the real raytracer-view window under Xvfb, as a user
# would use them with the mouse and keys, on the default scene's tetrahedron:
#  1. Y switches to the turn handle; its z ring dragged a quarter round with Shift held
#     turns the tetrahedron by exactly 90 degrees about z through its middle: the saved
#     block keeps its four vertices and gains `rotation 0 0 90` and the translate that
#     keeps the middle (10.75 -3.1 0.9) where it was, (7.65 -13.85 0);
#  2. U switches to the size handle; its middle box dragged right by a handle's length
#     with Shift held doubles it: `scale 2`;
#  3. Ctrl+Z takes the sizing back: the text is that of step 1, byte for byte;
#  4. saved, the window's picture equals `raytracer`'s render of the saved file.
# Screenshots (the rings and the boxes mid-drag) are kept in OUT_DIR to look at.
# Usage: xvfb_turn_test.sh BIN_DIR OUT_DIR
set -euo pipefail
# shellcheck source=xvfb_start.sh
. "$(dirname "$0")/xvfb_start.sh" "$@"

SCENE=$OUT/scene.txt
rm -f "$OUT"/*.png "$OUT"/*.ppm "$OUT"/layout.txt
cp "$(dirname "$0")/../../scenes/default.txt" "$SCENE"

STABLE_PAUSE=0.3
STABLE_TRIES=120

mode_is() { [ "$(state handle_mode)" = "$1" ]; }
has_state() { [ -n "$(state "$1")" ]; }

# Saves the edit just made, once the title shows it ("*"), and checks the file parses.
save() {
    wait_for "the edit in the title" eval '[[ "$(title)" == *"*"* ]]'
    xdotool key ctrl+s
    wait_for "the save" eval '[[ "$(title)" != *"*"* ]]'
    "$BIN/raytracer" --check "$SCENE" > /dev/null || fail "the saved scene does not parse"
}

# The tetrahedron's block of the saved text (from its name to its closing brace).
tetra_block() { awk '/^[[:space:]]*tetrahedron[[:space:]]*\{/ { on = 1 } on { print } on && /^[[:space:]]*\}/ { exit }' "$SCENE"; }

# Drags from (x, y) round the point (cx, cy) by `deg` degrees counter-clockwise on the
# screen, in `n` steps, with Shift held (snapping).
drag_round() {
    local x=$1 y=$2 cx=$3 cy=$4 deg=$5 n=$6 i px py
    xdotool keydown shift
    pointer_to "$x" "$y"
    xdotool mousedown 1
    wait_for "the button to be down" eval '[[ "$(state pointer)" == *down ]]'
    for i in $(seq 1 "$n"); do
        read -r px py <<< "$(awk -v x="$x" -v y="$y" -v cx="$cx" -v cy="$cy" -v a="$deg" -v i="$i" -v n="$n" 'BEGIN {
            t = a * i / n * 3.14159265358979 / 180; dx = x - cx; dy = y - cy
            # counter-clockwise on a screen whose y grows down
            printf "%d %d\n", cx + dx * cos(t) + dy * sin(t), cy - dx * sin(t) + dy * cos(t) }')"
        pointer_to "$px" "$py"
        [ "$i" = $((n / 2)) ] && shot 1-mid-turn
    done
    xdotool mouseup 1
    xdotool keyup shift
}

step "start the viewer with the tetrahedron selected"
cd "$OUT"
"$BIN/raytracer-view" "$SCENE" --size 1280x800 --samples 1 --select "object 5" --print-layout > "$LAYOUT" 2> "$OUT/viewer.err" &
VIEWER_PID=$!
WID=$(timeout 30 xdotool search --sync --name 'scene.txt' | head -1) || fail "no window appeared"
wait_for "the scene to load" eval '[[ "$(title)" != "(loading)"* ]]'
wait_for "the layout" grep -q end-layout "$LAYOUT"
wait_for "the handle" eval '[ "$(field handle 3)" = object ]'
IMAGE=$(region image)
read -r ix iy iw ih <<< "$IMAGE"
hx=$(field handle 1) hy=$(field handle 2)
echo "image $IMAGE, handle at $hx $hy"
cp "$SCENE" "$OUT/text-0.txt"

step "Y: the turn handle; its z ring a quarter round with Shift"
xdotool mousemove $((ix + 20)) $((iy + ih - 20))
xdotool key y
wait_for "the turn handle" mode_is turn
wait_for "the rings" has_state turn_ring_z
input_seen
shot 1-rings
read -r rx ry <<< "$(state turn_ring_z)"
echo "z ring at $rx $ry"
drag_round "$rx" "$ry" "$hx" "$hy" 90 12
wait_for "the turn's message" eval '[[ "$(state message)" == Turned* ]]'
echo "$(state message)"
shot 1-turned
save
cp "$SCENE" "$OUT/text-1.txt"
tetra_block > "$OUT/block-1.txt"
grep -q 'vect1 10 -4 0' "$OUT/block-1.txt" || fail "the vertices changed: $(cat "$OUT/block-1.txt")"
grep -Eq 'rotation 0 0 90([^0-9.]|$)' "$OUT/block-1.txt" || fail "no 'rotation 0 0 90' in: $(cat "$OUT/block-1.txt")"
grep -Eq 'translate 7.65 -13.85 0([^0-9.]|$)' "$OUT/block-1.txt" || fail "not the translate that keeps the middle: $(cat "$OUT/block-1.txt")"
changed=$(diff "$OUT/text-0.txt" "$OUT/text-1.txt" | grep -c '^[<>]' || true)
[ "$changed" -ge 1 ] && [ "$changed" -le 8 ] || fail "the turn changed $changed lines of the text"

step "U: the size handle; its middle box right by a handle's length with Shift"
xdotool key u
wait_for "the size handle" mode_is size
wait_for "the boxes" eval 'has_state size_box_x || has_state size_box_y'
input_seen
shot 2-boxes
box=$(state size_box_y)
[ -n "$box" ] || box=$(state size_box_x)
read -r bx by <<< "$box"
len=$(awk -v x="$bx" -v y="$by" -v hx="$hx" -v hy="$hy" 'BEGIN { printf "%d\n", sqrt((x - hx) ^ 2 + (y - hy) ^ 2) + 0.5 }')
echo "handle length $len"
xdotool keydown shift
pointer_to "$hx" "$hy"
xdotool mousedown 1
wait_for "the button to be down" eval '[[ "$(state pointer)" == *down ]]'
for i in $(seq 1 10); do
    pointer_to $((hx + len * i / 10)) "$hy"
    [ "$i" = 5 ] && shot 2-mid-size
done
xdotool mouseup 1
xdotool keyup shift
wait_for "the size's message" eval '[[ "$(state message)" == Sized* ]]'
echo "$(state message)"
save
tetra_block > "$OUT/block-2.txt"
grep -Eq 'scale 2([^0-9.]|$)' "$OUT/block-2.txt" || fail "no 'scale 2' in: $(cat "$OUT/block-2.txt")"
grep -q 'rotation 0 0 90' "$OUT/block-2.txt" || fail "the rotation went: $(cat "$OUT/block-2.txt")"

step "Ctrl+Z takes the sizing back"
xdotool key ctrl+z
save
cmp -s "$SCENE" "$OUT/text-1.txt" || fail "undo did not give back the turned text: $(diff "$OUT/text-1.txt" "$SCENE" | head)"

step "the picture equals raytracer's render of the saved file"
xdotool mousemove $((ix + iw / 2)) $((iy + 12)) click 1
wait_for "the selection to clear" eval '[ "$(field handle 1)" = none ]'
wait_stable 3-clean
"$BIN/raytracer" --quiet --width "$(field film 1)" --height "$(field film 2)" "$SCENE" "$OUT/3-ref.ppm" ||
    fail "raytracer could not render the saved text"
"$TOOL" match-scaled "$OUT/3-clean.png" $IMAGE "$OUT/3-ref.ppm" ||
    fail "the picture differs from a render of the saved text"
echo "PASS"
