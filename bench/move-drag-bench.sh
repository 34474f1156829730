#!/usr/bin/env bash
# Picture updates a second while an object is dragged with the move handle, against
# an orbit drag of the same length, under Xvfb: a 2 s drag at 30 pointer events a
# second (as bench/viewer-bench.sh takes the orbit figure), counted on screen by
# rtview-xframes. On the default scene and on bench/scenes/spheres-10k.txt (10,000
# objects: each frame's move refits the BVH), or on the scenes named in SCENES (the
# 1,000,000-sphere grid of bench/make-grid.sh 1000, say); the object dragged is the one
# left of the picture's middle (DRAG_EVENTS=each: a process per event, as before, whose
# loop takes ~40 % of two cores itself). Three drags each: an orbit, the move handle, and the
# red channel of the object's material colour in the panel (a material edit a frame);
# and the turn (Y, its z ring) and size (U, its middle box) handles. MODES picks some.
#   bench/move-drag-bench.sh [BIN_DIR] [DISPLAY_NUMBER]
#   SCENES="scenes/default.txt /tmp/grid1m.txt" RUNS=3 bench/move-drag-bench.sh
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
BIN=$(cd "${1:-$HERE/../build/bin}" && pwd)
DNUM=${2:-93}
RUNS=${RUNS:-3}
OUT=$(mktemp -d /tmp/move-drag-bench.XXXXXX)
NEED=(raytracer-view rtview-xframes)
# shellcheck source=bench/xvfb-session.sh
. "$HERE/xvfb-session.sh"
field() { awk -v n="$1" -v k="$2" '$1 == n { v = $(k + 1) } END { print v }' "$OUT/layout.txt"; }
# state KEY: the last value the viewer printed for probe KEY ("x y w h" for a widget).
state() { awk -v k="$1" '$1 == "state" && $2 == k { sub("^state " k " ?", ""); v = $0 } END { print v }' "$OUT/layout.txt"; }

# run SCENE MODE: one 2 s drag (MODE orbit, move, turn, size or colour); prints the pictures counted
# on screen and the pictures the viewer made.
run() {
    local scene=$1 mode=$2
    cp "$scene" "$OUT/scene.txt"
    # Each run starts as a first start: the last run was killed mid-edit, and its
    # recovery copy would otherwise be offered (and read) by this one.
    rm -rf "$XDG_STATE_HOME"
    "$BIN/raytracer-view" "$OUT/scene.txt" --size 1280x800 --print-layout -v > "$OUT/layout.txt" 2> "$OUT/viewer.err" &
    local vp=$!
    PIDS+=($vp)
    for _ in $(seq 1 1200); do grep -qs "first picture" "$OUT/viewer.err" && break; sleep 0.1; done
    sleep 1.5
    read -r ix iy iw ih <<< "$(field image 1) $(field image 2) $(field image 3) $(field image 4)"
    local x y
    if [ "$mode" != orbit ]; then
        # Select an object left of the middle, then grab the handle's view-plane square.
        for k in $(seq 0 9); do
            xdotool mousemove $((ix + iw * 37 / 100 + k * 3)) $((iy + ih * 55 / 100 + k * 2)) click 1
            # (Up to 5 s for the frame that shows the selection: the machine may be busy.)
            for _ in $(seq 1 50); do [ "$(field handle 3)" = object ] && break; sleep 0.1; done
            x=$(field handle 1) y=$(field handle 2)
            [ "$(field handle 3)" = object ] && break
        done
        [ "$x" != none ] || { echo "no handle" >&2; exit 1; }
    fi
    if [ "$mode" = turn ] || [ "$mode" = size ]; then
        # The turn handle (Y): grabbed on its z ring; the size handle (U): its middle box.
        xdotool key "$([ "$mode" = turn ] && echo y || echo u)"
        for _ in $(seq 1 50); do [ "$(state handle_mode)" = "$mode" ] && break; sleep 0.1; done
        [ "$(state handle_mode)" = "$mode" ] || { echo "no $mode handle" >&2; exit 1; }
        if [ "$mode" = turn ]; then read -r x y <<< "$(state turn_ring_z)"; fi
    fi
    if [ "$mode" = colour ]; then
        # The colour is below the sliders: scroll the properties (under the outline)
        # until it shows; its first number field is red.
        xdotool mousemove $(($(field outline 1) + $(field outline 3) / 2)) $(($(field outline 2) + $(field outline 4) + 150))
        for _ in $(seq 1 20); do
            [ -n "$(state field_material_colour)" ] && break
            xdotool click 5
            sleep 0.3
        done
        local cx cy cw
        read -r cx cy cw _ <<< "$(state field_material_colour)"
        [ -n "$cx" ] || { echo "no colour field" >&2; exit 1; }
        x=$((cx + cw / 8)) y=$((cy + 8))
    elif [ "$mode" = orbit ]; then
        x=$((ix + iw / 2)) y=$((iy + ih / 2))
    fi
    "$BIN/rtview-xframes" $((ix + iw / 4)) $((iy + ih / 4)) $((iw / 2)) $((ih / 2)) 10 2.0 > "$OUT/frames.txt" &
    local xf=$!
    local traced0
    traced0=$(grep -c "first image on screen" "$OUT/viewer.err" || true)
    drag "$x" "$y" $((x - 60)) $((y - 20)) 2
    wait "$xf"
    # The pictures the viewer made for the drag (its -v log: one line each), beside
    # those that changed the screen: a colour change of a sphere a pixel or two wide
    # in a coarse preview often changes nothing to count there.
    local traced
    traced=$(($(grep -c "first image on screen" "$OUT/viewer.err" || true) - traced0))
    kill "$vp" 2> /dev/null || true
    wait "$vp" 2> /dev/null || true
    echo "$(awk '/^changes/ { print $2 }' "$OUT/frames.txt") $traced"
}

echo "move-drag bench, $(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores, load average before: $(load)"
for scene in ${SCENES:-"$HERE/../scenes/default.txt" "$HERE/scenes/spheres-10k.txt"}; do
    for mode in ${MODES:-orbit move turn size colour}; do
        rates=() made=()
        for _ in $(seq 1 "$RUNS"); do
            read -r c m <<< "$(run "$scene" $mode)"
            rates+=("$(awk -v c="$c" 'BEGIN { printf "%.1f", c / 2.0 }')")
            made+=("$(awk -v c="$m" 'BEGIN { printf "%.1f", c / 2.0 }')")
        done
        echo "$(basename "$scene"), $mode drag: picture updates/s on screen ${rates[*]}; made by the viewer ${made[*]} (load $(load))"
    done
done
rm -rf "$OUT"
