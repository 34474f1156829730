#!/bin/bash
# Editing the scene in the picture of the real raytracer-view window under Xvfb, as a
# user would with the mouse and keys:
#  1. right click on the floor, "Add here" > "sphere": the saved text has one more
#     sphere, and it is selected (outlined, with the move handle on it);
#  2. dragging the handle's y arrow moves the sphere: only its block of the text
#     changes (the y coordinate grows: +y is to the left in this view), and the
#     handle follows; a screenshot is taken mid-drag;
#  3. Ctrl+D duplicates it, Delete deletes one, Ctrl+Z brings it back: the sphere
#     count of the saved text follows, and undo restores the text byte for byte.
# After each step the picture (the selection cleared, the render settled) equals a
# `raytracer` render of the saved text at the film's size: text and picture agree.
# Screenshots are kept in OUT_DIR to look at.
# Usage: xvfb_move_test.sh BIN_DIR OUT_DIR
set -euo pipefail
# shellcheck source=xvfb_start.sh
. "$(dirname "$0")/xvfb_start.sh" "$@"

SCENE=$OUT/scene.txt
rm -f "$OUT"/*.png "$OUT"/*.ppm "$OUT"/layout.txt
cp "$(dirname "$0")/../../scenes/default.txt" "$SCENE"

spheres() { grep -c '^[[:space:]]*sphere[[:space:]]*{' "$SCENE" || true; }

STABLE_PAUSE=0.3
STABLE_TRIES=120

# Waits until the layout's handle line is $1 ("none") or not ("some").
handle_is() {
    local h
    h=$(field handle 1)
    if [ "$1" = none ]; then [ "$h" = none ]; else [ -n "$h" ] && [ "$h" != none ]; fi
}
wait_handle() {
    local want=$1
    wait_until 'handle_is "$want"' 5 "the handle line to be $want"
}
edited() { [[ "$(title)" == *"*"* ]]; }

# Saves the edit just made. It waits for the edit to show first (the title's "*"): on
# a busy machine a frame can take longer than the pause after a key, and a title
# without "*" would then be the last save's, not this one's.
save() {
    wait_until edited 30 "the edit to show in the title"
    xdotool key ctrl+s
    wait_until '! edited' 30 "Ctrl+S to save (the title without its '*')"
    "$BIN/raytracer" --check "$SCENE" > /dev/null || fail "the saved scene does not parse"
}

# The picture equals raytracer's render of the saved text. The selection is cleared
# first (a click on the empty sky), so no outline or handle is over it.
agree() {
    local name=$1
    xdotool mousemove $((ix + iw / 2)) $((iy + 12)) click 1
    wait_handle none
    wait_stable "$name-clean"
    # The film is the scene's picture at its picture_size, drawn fitted into the image.
    "$BIN/raytracer" --quiet --width "$(field film 1)" --height "$(field film 2)" "$SCENE" "$OUT/$name-ref.ppm" ||
        fail "$name: raytracer could not render the saved text"
    "$TOOL" match-scaled "$OUT/$name-clean.png" $IMAGE "$OUT/$name-ref.ppm" ||
        fail "$name: the picture differs from a render of the saved text"
}

# Selects what is under (x, y) and waits for the handle.
select_at() {
    xdotool mousemove "$1" "$2" click 1
    wait_handle some
}

step "start the viewer"
cd "$OUT"
"$BIN/raytracer-view" "$SCENE" --size 1280x800 --samples 1 --print-layout > "$OUT/layout.txt" 2> "$OUT/viewer.err" &
VIEWER_PID=$!
WID=$(timeout 30 xdotool search --sync --name 'scene.txt' | head -1) || fail "no window appeared"
wait_until '[[ "$(title)" != "(loading)"* ]]' 30 "the scene to load"
wait_until '[[ "$(state load)" == ready ]]' 10 "a frame that shows the loaded scene"
IMAGE=$(region image)
read -r ix iy iw ih <<< "$IMAGE"
echo "image $IMAGE"
wait_stable 0-start
n0=$(spheres)

step "add a sphere on the floor from the right-click menu"
px=$((ix + iw * 48 / 100)) py=$((iy + ih * 80 / 100))
xdotool mousemove $px $py click 3
wait_until '[[ "$(state popups)" != none ]]' 10 "the context menu to open"
# The menu opens at the pointer; "Add here" is its first row, its submenu opens to
# the right with "sphere" first.
pointer_to $((px + 30)) $((py + 12))
wait_until '[[ "$(state popups)" == *"|"* ]]' 10 "the Add here submenu to open"
shot 1-menu
pointer_to $((px + 120)) $((py + 12))
pointer_to $((px + 190)) $((py + 12))
shot 1-submenu
xdotool click 1
wait_handle some
input_seen
shot 1-added
save
n1=$(spheres)
[ "$n1" = $((n0 + 1)) ] || fail "expected $((n0 + 1)) spheres in the text after adding, found $n1"
cp "$SCENE" "$OUT/text-1.txt"
hx=$(field handle 1) hy=$(field handle 2)
echo "handle at $hx $hy"
agree 1-added

step "drag the sphere by the handle's y arrow"
select_at "$hx" "$hy"
# The y arrow points left in this view (the camera looks along +x, z up): grabbed
# halfway along it and pulled 150 pixels further left, a frame at a time.
gx=$((hx - 45)) gy=$hy
pointer_to $gx $gy
xdotool mousedown 1
wait_until '[[ "$(state pointer)" == *down ]]' 10 "the button to be down"
for i in $(seq 1 30); do
    pointer_to $((gx - i * 5)) $gy
    [ "$i" = 15 ] && shot 2-mid-drag
done
xdotool mouseup 1
wait_until '[[ "$(state pointer)" != *down ]]' 10 "the button to be up"
shot 2-dragged
save
cp "$SCENE" "$OUT/text-2.txt"
hx2=$(field handle 1) hy2=$(field handle 2)
echo "handle now at $hx2 $hy2"
[ "$hx2" -lt $((hx - 100)) ] || fail "the handle did not follow the drag ($hx -> $hx2)"
# Only the sphere's block changed, and its y grew.
changed=$(diff "$OUT/text-1.txt" "$OUT/text-2.txt" | grep -c '^[<>]' || true)
[ "$changed" -ge 1 ] && [ "$changed" -le 12 ] || fail "the drag changed $changed lines of the text"
diff "$OUT/text-1.txt" "$OUT/text-2.txt" > "$OUT/drag.diff" || true
y1=$(grep '^>' "$OUT/drag.diff" | awk '$2 == "position" { print $4; exit }')
y0=$(grep '^<' "$OUT/drag.diff" | awk '$2 == "position" { print $4; exit }')
[ -n "$y1" ] && [ -n "$y0" ] || fail "no position line in the drag's change: $(cat "$OUT/drag.diff")"
awk -v a="$y0" -v b="$y1" 'BEGIN { exit !(b > a) }' || fail "y went from $y0 to $y1, expected it to grow"
[ "$(spheres)" = "$n1" ] || fail "the drag changed the number of spheres"
agree 2-dragged

step "Ctrl+D duplicates the sphere"
select_at "$hx2" "$hy2"
xdotool key ctrl+d
wait_until edited 30 "Ctrl+D to show in the title"
shot 3-duplicated
save
cp "$SCENE" "$OUT/text-3.txt"
[ "$(spheres)" = $((n1 + 1)) ] || fail "expected $((n1 + 1)) spheres after Ctrl+D, found $(spheres)"
agree 3-duplicated

step "Delete deletes one"
select_at "$hx2" "$hy2"
xdotool key Delete
wait_until edited 30 "Delete to show in the title"
shot 4-deleted
save
[ "$(spheres)" = "$n1" ] || fail "expected $n1 spheres after Delete, found $(spheres)"
agree 4-deleted

step "Ctrl+Z brings it back, the text byte for byte"
xdotool key ctrl+z
save
cmp -s "$SCENE" "$OUT/text-3.txt" || fail "undo did not restore the text: $(diff "$OUT/text-3.txt" "$SCENE" | head)"
agree 5-undone
echo "PASS"
