#!/bin/bash
# Journey: asking for more samples refines the picture on the screen further instead of
# starting it again. The user opens default.txt with 4 samples a pixel (uniform) and
# waits for the render to finish, then types 12 into the Render tab's samples field and
# rests; Ctrl+drags a region of the picture and types 20; then asks for an adaptive
# render (--aa-threshold on the command line is the same render as the tab's) of 4
# samples at most and raises it to 16.
# Checks: after Enter the same render (its generation) goes on from 4 samples to 12,
# never showing fewer than 4 on the way, and the picture at the end is `raytracer
# --samples 12`'s; a region refined with Ctrl+drag then goes on from its 12 samples to
# 20 when 20 are asked for; adaptive, the raised render also keeps its generation and
# ends settled.
# Usage: j34_more_samples.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

# Types $1 into the Render tab's samples field and presses Enter.
set_samples() {
    type_value samples "$1" "samples per pixel"
    wait_state render_settings "^--samples $1( |$)"
}

generation() { state film | sed -n 's/.* generation \([0-9]*\)$/\1/p'; }

# goes_on KEY END LEAST: waits (no input) until state KEY reads END, its sample count
# (the first word) never below LEAST on the way: what was raised was not started again.
goes_on() {
    local least=99 s
    for _ in $(seq 1 40); do
        s=$(state "$1" | cut -d' ' -f1)
        [ "$s" -lt "$least" ] && least=$s
        [ "$(state "$1")" = "$2" ] && break
        idle 0.25
    done
    wait_state "$1" "^$2\$" 60
    [ "$least" -ge "$3" ] || fail "$1 went back to $least samples: it was started again"
}

step "open default.txt at 4 samples a pixel and let the render finish"
start_viewer "$SCENES/default.txt" --samples 4 --aa-threshold off
wait_state render "^4 done" 120
gen=$(generation)
[ -n "$gen" ] || fail "no render generation in '$(state film)'"
shot 1-four-done

step "12 samples typed into the Render tab: the same render goes on"
click_item tab_Render
set_samples 12
goes_on render "12 done" 4
[ "$(generation)" = "$gen" ] || fail "the render was started again (generation $(generation), was $gen)"
picture_agrees twelve

step "a region refined (Ctrl+drag), then 20 samples: the region goes on from its 12"
xdotool keydown ctrl
drag $((ix + iw / 4)) $((iy + ih / 4)) $((ix + iw / 2)) $((iy + ih / 2))
xdotool keyup ctrl
wait_state region "^12 spp done$" 60
set_samples 20
goes_on region "20 spp done" 12
shot 2-region-20

step "adaptive at 4 samples at most, then 16: the same render refines further"
quit_viewer
start_viewer "$SCENES/default.txt" --samples 4 --aa-threshold 0.02
wait_state render "done" 120
gen=$(generation)
click_item tab_Render
set_samples 16
wait_state render "done" 120
[ "$(generation)" = "$gen" ] || fail "the adaptive render was started again (generation $(generation), was $gen)"
echo "adaptive: $(state film)"
shot 3-adaptive-16
echo PASS
