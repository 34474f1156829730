#!/bin/bash
# Journey: frames that repaint only what changed look exactly like frames painted
# whole. Under Xvfb the viewer paints with Mesa's software rasteriser, so a frame
# repaints and shows only the boxes where it differs from the last one (the status
# bar's numbers, the picture's new rows); RAYTRACER_VIEW_DAMAGE=check makes it read
# every such frame back, paint it whole and compare. The user rests the pointer on the
# picture while it renders, opens the File menu and closes it, orbits the view, hovers
# the panel's buttons, types a filter into the outline, opens Ctrl+O, types a path and
# closes it, and quits.
# Checks: the frames were partial (the verbose start line says so), many were checked,
# and not one differed from the whole frame by a byte.
# Usage: j68_partial_frames.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"
export RAYTRACER_VIEW_DAMAGE=check

step "open default.txt and rest the pointer on the picture while it renders"
start_viewer "$SCENES/default.txt" --samples 64 --verbose
grep -q "frames paint and show only what changed" "$OUT/viewer.err" ||
    fail "the frames are not partial: $(grep renderer "$OUT/viewer.err")"
xdotool mousemove $((ix + iw / 3)) $((iy + ih / 2))
wait_state render "running" 30
idle 1.5

step "the File menu, then Escape"
click_item "menu:File"
wait_state popups "^##Menu" 3
idle 0.3
key Escape
wait_state popups "^none$" 3

step "orbit the view, then hover the sidebar's tabs"
drag $((ix + iw / 2)) $((iy + ih / 2)) $((ix + iw / 2 + 120)) $((iy + ih / 2 + 30))
idle 0.5
hover_item tab_Text
idle 0.3
hover_item tab_Render
idle 0.3

step "a filter typed into the outline"
click_item field_outline_filter
type_text "sph"
idle 0.5
key ctrl+a BackSpace
idle 0.3

step "Ctrl+O, a path typed, Escape"
key ctrl+o
wait_state browser_field "^active$" 10
key ctrl+a
type_text "/tmp/partial-frames"
idle 0.5
key Escape
wait_state popups "^none$" 3
idle 1
shot 1-last

step "quit: every partial frame was the whole frame"
quit_viewer
line=$(grep "partial frames checked" "$OUT/viewer.err") || fail "no count of the frames checked"
echo "$line"
grep "differs from the whole frame" "$OUT/viewer.err" | head -5 >&2 || true
read -r checked differed <<< "$(echo "$line" | awk '{ print $2, $6 }')"
[ "$checked" -ge 30 ] || fail "only $checked partial frames were checked"
[ "$differed" -eq 0 ] || fail "$differed partial frames differed from whole ones"
echo PASS
