#!/bin/bash
# Journey: the sidebar at 2x UI scale in a 1280x800 window. The user opens default.txt,
# sets the UI scale to 200 % (Ctrl+= four times), drags the sidebar's edge 230 pixels
# to the left, rests the pointer on the picture, hides the sidebar with Tab and shows
# it again, quits and starts the viewer again.
# Checks: at 2x the sidebar leaves the picture most of the window (it took 58 %);
# dragging its edge resizes it by what the pointer moved, and the render goes on
# (the picture frame's film does not depend on the window); the status bar stays one
# row (it wrapped to four rows at 640x400), cut with "..." but never inside a number
# ("RGB 0.107 0..."); Tab shows the picture
# alone across the whole width and brings the sidebar back at its width; the width is
# kept in settings.txt and the next start has it.
# Usage: j32_sidebar_ui_scale.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@" 1280x800

step "open default.txt at 2x UI scale"
start_viewer "$SCENES/default.txt" --samples 16 --aa-threshold off
for pct in 125 150 175 200; do
    key ctrl+equal  # one at a time: two presses within one frame count once
    wait_state message "^UI scale $pct%" 5
done
idle 1
read -r wx wy ww wh <<< "$(region window)"
read -r sx sy sw sh <<< "$(region sidebar)"
echo "window ${ww}x${wh}, sidebar $sw wide"
[ $((sw * 100)) -le $((ww * 45)) ] || fail "at 2x the sidebar takes $((sw * 100 / ww)) % of the window"
shot 1-scale-2x

step "drag the sidebar's edge 230 pixels to the left"
wait_state render "^16 done" 120
film=$(state film)
pointer_to "$sx" $((wh / 2))
xdotool mousedown 1
wait_state pointer " down$"
for i in $(seq 1 23); do
    pointer_to $((sx - i * 10)) $((wh / 2))
done
idle 0.5
shot 2-mid-drag
xdotool mouseup 1
idle 0.5
read -r _ _ sw2 _ <<< "$(region sidebar)"
echo "sidebar now $sw2 wide"
[ $((sw2 - sw - 230)) -le 2 ] && [ $((sw + 230 - sw2)) -le 2 ] || fail "dragged 230 pixels, the sidebar went from $sw to $sw2"
[ "$(field area 3)" = $((ww - sw2)) ] || fail "the picture's area is $(field area 3) wide beside a $sw2 sidebar"
[ "$(state film)" = "$film" ] || fail "resizing the sidebar restarted the render: '$(state film)', was '$film'"

step "rest the pointer on the picture: the readout in the narrower status bar, on one row"
status_h=$(field status 4)
# Numbers of every width (0.05, 0.625, 12.5 ...) at a few places across the picture.
read -r ix iy iw ih <<< "$(region image)"
last=none
for k in 1 2 3 4 5 6 7; do
    pointer_to $((ix + iw * k / 8)) $((iy + ih * (9 - k) / 10))
    wait_until '[ "$(state readout)" != "$last" ]' 3 "the readout of the pixel under the pointer"
    last=$(state readout)
    rows=$(state status_rows)
    echo "status bar: $rows"
    [ "$(field status 4)" = "$status_h" ] || fail "the status bar grew from $status_h to $(field status 4) pixels: $rows"
    echo "$rows" | grep -Eq '[0-9]\.?(\.\.\.)?$' && echo "$rows" | grep -q '\.\.\.$' && {
        shot 3-broken-number
        fail "the status bar is cut inside a number: $rows"
    }
    if echo "$rows" | grep -q 'RGB'; then
        echo "$rows" | grep -Eq 'RGB [0-9]+\.[0-9]+ [0-9]+\.[0-9]+ [0-9]+\.[0-9]+' ||
            fail "the readout's RGB values are not all shown: $rows"
    fi
done
shot 3-readout

step "Tab: the picture alone; Tab: the sidebar again"
key Tab
idle 0.5
[ "$(field sidebar 3)" = 0 ] && [ "$(field area 3)" = "$ww" ] ||
    fail "Tab should leave the picture the whole width: sidebar $(field sidebar 3), area $(field area 3)"
shot 4-picture-alone
key Tab
idle 0.5
[ "$(field sidebar 3)" = "$sw2" ] || fail "Tab brought the sidebar back $(field sidebar 3) wide, not $sw2"

step "quit and start again: the sidebar keeps its width"
quit_viewer
grep -q '^sidebar_share ' "$XDG_CONFIG_HOME/raytracer-view/settings.txt" ||
    fail "settings.txt does not keep the sidebar's width: $(cat "$XDG_CONFIG_HOME/raytracer-view/settings.txt")"
start_viewer "$SCENES/default.txt" --samples 16 --aa-threshold off
idle 1
[ "$(field sidebar 3)" = "$sw2" ] || fail "started again, the sidebar is $(field sidebar 3) wide, not $sw2"
shot 5-restarted
echo PASS
