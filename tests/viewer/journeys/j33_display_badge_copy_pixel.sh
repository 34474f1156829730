#!/bin/bash
# Journey: the picture says when it is shown otherwise than saved, and a pixel's value
# can be copied. The user opens default.txt, rests the pointer on the picture, raises
# the exposure one stop (+), switches the soft tone curve on (T), resets the exposure
# (0) and the curve (T); then copies the hovered pixel's readout (Ctrl+C).
# Checks: while the display is not neutral a badge on the picture names what differs
# ("exposure +1.0", "soft curve"), drawn on the screen in the picture's corner, and it
# is gone once neutral again; Ctrl+C puts the readout the status bar shows on the
# clipboard, where another program reads it.
# Usage: j33_display_badge_copy_pixel.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

# Pixels of the badge's colour in the picture's bottom-left corner of screenshot $1.
badge_ink() {
    "$TOOL" near "$OUT/$1.png" "$ix" $((iy + ih - 4 * 20)) $((iw / 2)) $((4 * 20)) 255 215 120 30
}

step "open default.txt and rest the pointer on the picture"
start_viewer "$SCENES/default.txt" --samples 16 --aa-threshold off
wait_state render "^16 done" 120
xdotool mousemove $((ix + iw / 2)) $((iy + ih / 3))
idle 0.5
wait_state display_badge "^none$" 2
shot 1-neutral
echo "badge-coloured pixels, neutral: $(badge_ink 1-neutral)"
[ "$(badge_ink 1-neutral)" -lt 20 ] || fail "the neutral picture already shows badge-coloured text"

step "one stop up, then the soft curve: the badge says so"
key equal
wait_state display_badge "^exposure \+1\.0$" 3
key t
wait_state display_badge "^exposure \+1\.0  soft curve$" 3
idle 0.5
shot 2-badge
echo "badge-coloured pixels with the badge: $(badge_ink 2-badge)"
[ "$(badge_ink 2-badge)" -ge 50 ] || fail "no badge drawn on the picture ($(badge_ink 2-badge) pixels of its colour)"

step "exposure back to 0 and the clip curve: no badge"
key 0
wait_state display_badge "^soft curve$" 3
key t
wait_state display_badge "^none$" 3
idle 0.5
shot 3-neutral-again
[ "$(badge_ink 3-neutral-again)" -lt 20 ] || fail "the badge stays on the neutral picture"

step "Ctrl+C over the picture copies the pixel's readout"
xdotool mousemove $((ix + iw / 3)) $((iy + ih * 2 / 3))
idle 0.5
wait_state readout "^x [0-9]+ y [0-9]+ .*RGB" 3
readout=$(state readout)
key ctrl+c
wait_state message "^Copied to the clipboard: " 3
[ "$(state message)" = "Copied to the clipboard: $readout" ] ||
    fail "copied '$(state message)' while the readout was '$readout'"
# Read back as another program would (Tk), else as the viewer reads its own clipboard.
if python3 -c 'import tkinter' 2>/dev/null; then
    pasted=$(python3 -c 'import tkinter; r = tkinter.Tk(); r.withdraw(); print(r.clipboard_get())') ||
        fail "another program finds nothing on the clipboard"
else
    pasted=$(state clipboard)
fi
echo "pasted: $pasted"
[ "$pasted" = "$readout" ] || fail "the clipboard holds '$pasted', not the readout '$readout'"
echo PASS
