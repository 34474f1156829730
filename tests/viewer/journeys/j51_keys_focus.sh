#!/bin/bash
# Journey: keys go to what was last clicked, with the Text tab in front. The user
# shows the Text tab and, with the pointer on the picture, presses W W W A A Q F R;
# clicks into the text and types, then clicks the picture and presses W; rests the
# pointer on the text (no click) and presses Ctrl+F, types "sphere", Enter twice,
# Escape; presses
# Ctrl+G and types 1.
# Checks: the picture's keys never reach the text (it stays as applied, with no caret:
# not focused) until the text is clicked; a click on the picture takes the keys from
# the text again; Ctrl+F and Ctrl+G work with the Text tab in front whether or not the
# text was clicked, and what follows goes into their field (the 1 for Go to line does
# not zoom the picture to 1:1); Find says which match of how many ("2 of 5").
# Usage: j51_keys_focus.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

start_viewer "$SCENES/default.txt" --samples 4
text0=$(cat "$SCENE")

step "the Text tab in front, the pointer on the picture: W W W A A Q F R"
click_item tab_Text
wait_state editor_grid "."
xdotool mousemove $((ix + iw / 2)) $((iy + ih / 2))
idle 0.3
key w w w a a q f r
idle 1
shot 1-picture-keys
[ "$(state text)" = applied ] || fail "the picture's keys changed the text: $(state text)"
state editor_cursor | grep -q focused && fail "the text took the keys without a click: $(state editor_cursor)"

step "a click into the text: it takes the keys; a click on the picture: they leave it"
read -r x y <<< "$(editor_xy 1 1)"
click "$x" "$y"
wait_state editor_cursor "focused$" 5
key End
type_text " x"
wait_state text "^unapplied" 5
shot 2-text-focused
key ctrl+z ctrl+z
wait_state text "^applied" 5
select_nothing
wait_state editor_cursor "^[0-9]+ [0-9]+$" 5
key w
idle 1
[ "$(state text)" = applied ] || fail "W after a click on the picture went into the text: $(state text)"

step "the pointer on the text, no click: Ctrl+F, a word; Ctrl+G, a line number"
read -r x y <<< "$(editor_xy 3 3)"
xdotool mousemove "$x" "$y"
idle 0.3
key ctrl+f
wait_state editor_bar "^find" 5
type_text "sphere"
wait_state editor_bar "^find sphere$" 5
step "Enter finds the next match and counts them all: 'k of N'"
n=$(grep -oi sphere "$SCENE" | wc -l)
key Return
wait_state editor_bar "^find sphere \\([0-9]+ of $n\\)$" 5
k1=$(state editor_bar | sed -E 's/.*\(([0-9]+) of.*/\1/')
key Return
wait_state editor_bar "^find sphere \\($(( k1 % n + 1 )) of $n\\)$" 5
shot 3-find
key Escape
key ctrl+g
wait_state editor_bar "^goto" 5
type_text "1"
wait_state editor_bar "^goto 1$" 5
idle 0.5
[ "$(state zoom)" = fit ] || fail "the 1 for Go to line zoomed the picture: $(state zoom)"
[ "$(state text)" = applied ] || fail "the keys changed the text: $(state text)"
[ "$(cat "$SCENE")" = "$text0" ] || fail "the file changed"
echo PASS
