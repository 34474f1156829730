#!/bin/bash
# Journey: moving two things at once. The user clicks the glass sphere, Shift+clicks the
# brown one, drags the one move handle between them (its view-plane square), undoes,
# redoes and saves.
# Checks: the panel says "2 things selected" and the handle moves both; one Ctrl+Z
# puts both back (the saved text is the original, byte for byte) and names the one
# step "Move 2 things"; after Ctrl+Y the saved text has both spheres moved by the same
# amount and nothing else changed; Esc selects nothing; the picture equals
# `raytracer`'s render of the saved file.
# Usage: j64_shift_click_move.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

step "open default.txt; where the two spheres are (their handles, from the outline)"
start_viewer "$SCENES/default.txt" --samples 4
sphere_handles
echo "spheres at $x1 $y1 and $x2 $y2"

step "click the glass sphere, Shift+click the brown one"
# (Off their centres: clear of a handle's arrows.)
click $((x1 + 30)) $((y1 + 45))
wait_state selection "^object_1$"
xdotool mousemove $((x2 + 40)) $((y2 + 50)) keydown shift click 1 keyup shift
wait_state group "^2 things selected: 2 objects$"
wait_state selection "^object_2$"
[ "$(field handle 3)" = group ] || fail "no handle for the two: $(field handle 1) $(field handle 2) $(field handle 3)"
read -r hx hy <<< "$(field handle 1) $(field handle 2)"
shot 1-two-selected

step "drag the handle's square 100 pixels right: both move"
drag "$hx" "$hy" $((hx + 100)) "$hy"
wait_state message "^Moved by "
shot 2-moved
key ctrl+z
wait_state message "^Undid: Move 2 things"
save
cmp -s "$SCENES/default.txt" "$SCENE" || fail "one undo did not put both back: $(diff "$SCENES/default.txt" "$SCENE")"
key ctrl+y
wait_state message "^Redid: Move 2 things"
save

step "the saved text: both spheres moved by the same amount, nothing else"
diff "$SCENES/default.txt" "$SCENE" > "$OUT/move.diff" || true
cat "$OUT/move.diff"
[ "$(grep -c '^>' "$OUT/move.diff")" = 2 ] || fail "not exactly the two spheres' lines changed"
read -r a1 b1 c1 <<< "$(awk 'NR == 5 { print $2, $3, $4 }' "$SCENE")"
read -r a2 b2 c2 <<< "$(awk 'NR == 10 { print $2, $3, $4 }' "$SCENE")"
awk -v a1="$a1" -v b1="$b1" -v c1="$c1" -v a2="$a2" -v b2="$b2" -v c2="$c2" 'BEGIN {
    d = (a1 - 5) - (a2 - 7.5); e = (b1 - 0.9) - (b2 + 1.6); f = (c1 - 1) - (c2 - 1.3)
    moved = (a1 - 5) ^ 2 + (b1 - 0.9) ^ 2 + (c1 - 1) ^ 2
    exit !(d * d + e * e + f * f < 1e-18 && moved > 0.01) }' ||
    fail "the spheres did not move by the same amount: $a1 $b1 $c1 (from 5 0.9 1), $a2 $b2 $c2 (from 7.5 -1.6 1.3)"

step "Esc selects nothing; the picture is raytracer's render of the saved text"
key Escape
wait_state selection "^none$"
picture_agrees 3-saved
echo PASS
