#!/bin/bash
# Journey: adding a plane on the floor. The user right-clicks the chess floor behind
# the objects, picks "Add here" > "plane" and saves.
# Checks: the saved text has a second plane; the new plane is seen: a good part of the
# picture changed (a plane lying in the floor shows nothing); opened afresh, the saved
# file's picture equals `raytracer`'s render of it.
# Usage: j12_add_plane.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

planes() { grep -c '^[[:space:]]*\(chess_\)\?plane[[:space:]]*{' "$SCENE" || true; }

step "open default.txt and wait for the picture"
start_viewer "$SCENES/default.txt" --samples 4
picture_agrees 0-start

step "right-click the floor behind the objects: Add here > plane"
click $((ix + iw * 90 / 100)) $((iy + ih * 34 / 100)) 3
hover_item "menu:Add_here"
click_item "menu:plane"
wait_state selection "^plane_2$" 5
wait_state message "^Added a plane"
save
[ "$(planes)" = 2 ] || fail "expected two planes in the saved text, found $(planes)"
grep -A5 '^ *plane {' "$SCENE" || true

step "the new plane is in the picture"
wait_state render "done" 60
wait_stable 1-added
changed=$("$TOOL" diff "$OUT/0-start-shown.png" "$OUT/1-added.png" $IMAGE)
echo "fraction of the picture changed: $changed"
awk -v f="$changed" 'BEGIN { exit !(f > 0.1) }' || fail "only $changed of the picture changed: the new plane is not seen"

step "opened again, the saved file's picture is raytracer's"
quit_viewer
start_viewer "$SCENE" --samples 4
picture_agrees 2-reopened
echo PASS
