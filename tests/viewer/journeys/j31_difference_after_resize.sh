#!/bin/bash
# Journey: the difference view after a window resize. The user opens default.txt with
# the Render tab, waits for the render, keeps a snapshot (K), makes the window smaller,
# rests, and shows the difference with the snapshot (B twice). Then the same in
# "fill the window" mode, where a resize changes the picture itself.
# Checks: in the picture frame, nothing changed in the scene or the view, so the
# difference view reports 0 pixels differing (the picture is still the scene's 640x480,
# not resampled); its scale slider shows the factor the legend uses ("x 8" both, not
# the exponent "x 3"); filling the window, the resized picture is another picture and
# the view says the sizes differ instead of counting pixels of a resampled snapshot.
# Usage: j31_difference_after_resize.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

# keep, resize, compare: K, the window made 1100x700, B twice (split, then difference).
snapshot_resize_difference() {
    xdotool mousemove 5 5  # on the menu bar: the picture's keys work, no readout
    key k
    wait_state message "^Kept snapshot 1" 5
    xdotool windowsize "$WID" 1100 700
    # (Under load the window manager's resize and the next frame may take a while.)
    wait_until '[ "$(field window 3) $(field window 4)" = "1100 700" ]' 20 "the window resized to 1100x700"
    idle 1
    wait_state render "^16 done" 120
    key b
    wait_state message "^Compare: snapshot" 5
    key b
    wait_state message "^Compare: difference" 5
    idle 1
}

step "picture frame: snapshot, resize, difference"
start_viewer "$SCENES/default.txt" --samples 16 --aa-threshold off --tab render
wait_state render "^16 done" 120
film=$(state film)
snapshot_resize_difference
[ "$(state film)" = "$film" ] || fail "the resize changed the picture: '$(state film)', was '$film'"
wait_state difference "^\|A - B\| x [0-9]+ .* 0 pixels differ$" 5
shot 1-difference
legend=$(state difference)
echo "legend: $legend; slider: $(state difference_scale)"
factor=$(echo "$legend" | awk '{ print $5 }')
[ "$(state difference_scale)" = "x $factor" ] ||
    fail "the scale slider shows '$(state difference_scale)' while the difference is scaled x $factor"

step "fill the window: snapshot, resize, difference"
quit_viewer
start_viewer "$SCENES/default.txt" --samples 16 --aa-threshold off --tab render --fit window
wait_state render "^16 done" 120
snapshot_resize_difference
wait_state difference "^sizes differ: The snapshot is [0-9]+x[0-9]+, the picture [0-9]+x[0-9]+" 5
echo "$(state difference)"
shot 2-sizes-differ
echo PASS
