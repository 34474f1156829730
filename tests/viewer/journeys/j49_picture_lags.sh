#!/bin/bash
# Journey: the picture of a big scene lags the panels, and the status bar says so. The
# user opens a grid of 250,000 spheres with a sphere selected, deletes it (Del), undoes
# that (Ctrl+Z), then opens another grid of 202,500 spheres (Ctrl+O).
# Checks, frame by frame as the viewer drew them: while the panels show the edited (or
# newly opened) scene and the picture is still the render of the scene before (the
# film's render generation has not changed yet, or its new render has not finished),
# the status bar never says "settled" or "done", and it does say "updating the
# picture..."; then the picture catches up ("current") and the status bar settles.
# Usage: j49_picture_lags.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

step "make and open a grid of 250,000 spheres, sphere 125,001 selected"
bash "$HERE/../../../bench/make-grid.sh" 500 "$OUT/grid.txt"
bash "$HERE/../../../bench/make-grid.sh" 450 "$OUT/other.txt"
start_viewer "$OUT/grid.txt" --samples 1 --select "object 125001"
wait_state selection "^object_125001$" 10
wait_state status_bar "settled|done" 120
xdotool mousemove $((ix + iw / 2)) $((iy + ih / 2))
idle 0.5

generation() { state film | awk '{ print $NF }'; }
# frames_since LINE NEW_SIZE GEN: fails if a frame drawn after line LINE of the layout
# log showed NEW_SIZE objects in the panels, the film of render generation GEN (the
# scene before) and "settled" or "done" in the status bar; and unless one of them said
# "updating the picture...".
frames_since() {
    local from=$1 size=$2 gen=$3 what=$4 verdict
    verdict=$(tail -n +"$from" "$LAYOUT" | awk -v size="$size" -v gen="$gen" '
        $1 == "state" && $2 == "scene_size" { s = $3 }
        $1 == "state" && $2 == "film" { g = $NF }
        $1 == "state" && $2 == "status_bar" { st = $0 }
        $1 == "state" && $2 == "render" { r = $0 }
        $1 == "end-layout" {
            if (st ~ /updating the picture/) updating = 1
            # The old film, or a render that has not finished, under a status of "done".
            if (s == size && (g == gen || r !~ / done$/) && st ~ /settled|done/) { stale = st " (" r ")" }
        }
        END {
            if (stale != "") print "stale: " stale
            else if (!updating) print "silent"
            else print "ok"
        }')
    case "$verdict" in
        ok) echo "   the status bar said 'updating the picture...' while the picture lagged" ;;
        silent) fail "$what: the status bar never said 'updating the picture...'" ;;
        *) fail "$what: the panels showed the new scene over the old picture with the status bar saying it was finished ($verdict)" ;;
    esac
}
# after WHAT NEW_SIZE KEYS...: the keys pressed; then the picture catches up.
after() {
    local what=$1 size=$2 from gen
    shift 2
    step "$what"
    gen=$(generation)
    from=$(( $(wc -l < "$LAYOUT") + 1 ))
    "$@"
    wait_state scene_size "^$size objects" 60
    # The render of the new scene, then its end.
    wait_state film "generation ([0-9]+)$" 1
    wait_until '[ "$(generation)" != "$gen" ]' 120 "$what: a new render"
    wait_state status_bar "settled|done" 120
    frames_since "$from" "$size" "$gen" "$what"
    wait_state picture "^current$" 1
}

after "delete the selected sphere (Del)" 249999 key Delete
shot 1-deleted
after "undo the delete (Ctrl+Z)" 250000 key ctrl+z

open_other() {
    key ctrl+o
    wait_state popups "Open scene or model"
    wait_state browser_field "^active$"
    key ctrl+a
    type_text "$OUT/other.txt"
    wait_state browser "^open $OUT/other.txt$" 30
    key Return
}
after "open a grid of 202,500 spheres (Ctrl+O)" 202500 open_other
shot 2-opened
echo PASS
