# Sourced by the user-journey tests (tests/viewer/journeys/j*.sh) with their
# arguments BIN_DIR OUT_DIR [SCREEN]: the real raytracer-view window in an X server of
# its own (Xvfb, a free display number, so journeys may run side by side), with the
# fonts scripts/setup.sh installs, driven by real input events (xdotool).
#
# What a journey checks is what a user would: the saved file's bytes, `raytracer`'s
# picture of it, the screen, and what the last drawn frame showed in words (the
# viewer's --print-layout output: its "state KEY VALUE" lines come from probe.h and are
# written only by frames actually drawn, so a state that never reaches the screen never
# reaches the journey either).
#
# Journeys rest the mouse and wait with no input at all (`idle`): nothing may wait
# for an input event. Helpers:
#   start_viewer SCENE [ARGS...]   start the window on a scene file (a copy in $OUT)
#   state KEY                      the last drawn frame's value of KEY
#   wait_state KEY REGEX [SECS]    wait (no input) until it matches; fail if it never does
#   wait_until CONDITION SECS [WHAT]  wait until the shell text CONDITION holds, or fail
#                                  (../wait_until.sh): the one way a journey waits
#   idle SECS                      no input at all for SECS
#   field NAME K / region NAME     the layout's rectangles (as the older Xvfb tests)
#   click X Y [BUTTON], key KEYS..., type TEXT, shot NAME
#   editor_xy LINE COL [FRACTION]  screen point of a character of the scene text
#   select_nothing                 click the picture's empty corner, wait for no selection
#   item_xy / click_item / hover_item KEY   a probed item's (probe_item) centre; click it;
#                                  rest the pointer on it (a submenu opens on hover)
#   drag X0 Y0 X1 Y1 [BUTTON], scroll_to KEY X Y, region_mid NAME
#   pointer_to X Y                 move the pointer, wait for a frame that saw it there
#   input_seen                     wait until the viewer took every input sent so far
#   type_value FIELD TEXT [NAME]   Ctrl+click a panel field, type TEXT, Enter
#   picture_agrees NAME            the picture equals `raytracer`'s render of $SCENE
set -euo pipefail

BIN=$(cd "$1" && pwd)
OUT=$2
SCREEN=${3:-1280x800}
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
# A journey starts from an empty folder (files of an earlier run would change what
# it meets: a Save As would be asked to replace).
case "$OUT" in /|"$HOME"|/tmp|/root) echo "refusing to empty $OUT" >&2; exit 2 ;; esac
find "$OUT" -mindepth 1 -delete
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
SCENES=$(cd "$HERE/../../../scenes" && pwd)
TOOL=$BIN/rtview-imgtool
export MESA_SHADER_CACHE_DISABLE=true
export XDG_CONFIG_HOME=$OUT/config XDG_STATE_HOME=$OUT/state
# Sanitizer builds: X11, GLFW and Mesa are not instrumented (see xvfb_start.sh).
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=0}"
export TSAN_OPTIONS="${TSAN_OPTIONS:-suppressions=$HERE/../tsan.supp}"

XVFB_PID= VIEWER_PID=
journey_cleanup() {
    [ -n "$VIEWER_PID" ] && kill "$VIEWER_PID" 2>/dev/null || true
    [ -n "$XVFB_PID" ] && kill "$XVFB_PID" 2>/dev/null || true
}
trap journey_cleanup EXIT

fail() {
    echo "FAIL: $*" >&2
    import -window root "$OUT/failure.png" 2>/dev/null || true
    if [ -s "$OUT/layout.txt" ]; then
        echo "--- what the last frame showed:" >&2
        last_frame | grep '^state' >&2 || true
    fi
    echo "--- viewer stderr:" >&2
    tail -n 30 "$OUT/viewer.err" >&2 2>/dev/null || true
    exit 1
}
step() { echo "== $*"; }
# shellcheck source=../wait_until.sh
source "$HERE/../wait_until.sh"

# The X server, on the first free display number. Its key autorepeat waits a minute:
# on a busy machine xdotool may hold a key for longer than the usual 660 ms between
# its press and release, and the server would type the character twice.
exec 5> "$OUT/.display"
Xvfb -displayfd 5 -screen 0 "${SCREEN}x24" -nolisten tcp -ardelay 60000 > "$OUT/xvfb.log" 2>&1 &
XVFB_PID=$!
exec 5>&-
wait_until '[ -s "$OUT/.display" ]' 5 "Xvfb to start (its log: $OUT/xvfb.log)"
export DISPLAY=":$(head -1 "$OUT/.display")"

# The fonts setup.sh installs (fonts-dejavu-core): journeys run with them, as users do.
for f in DejaVuSans.ttf DejaVuSansMono.ttf; do
    [ -f "/usr/share/fonts/truetype/dejavu/$f" ] || fail "$f is missing: run scripts/setup.sh (fonts-dejavu-core)"
done

shot() { import -window root "$OUT/$1.png"; }
title() { xdotool getwindowname "$WID"; }
click() { xdotool mousemove "$1" "$2" click "${3:-1}"; }
key() { xdotool key --delay 40 "$@"; }
type_text() { xdotool type --delay 30 "$1"; }
# No input at all for $1 seconds: the mouse rests wherever it is. The rest itself is
# what a journey checks (nothing may change, or wait for input, meanwhile), so it is a
# fixed time on purpose.
idle() { sleep "$1"; }

LAYOUT=$OUT/layout.txt
# The last complete frame's lines.
last_frame() {
    awk '$1 == "end-layout" { done = block; block = ""; next } { block = block $0 "\n" } END { printf "%s", done }' "$LAYOUT"
}
field() { last_frame | awk -v n="$1" -v k="$2" '$1 == n { v = $(k + 1) } END { print v }'; }
region() { echo "$(field "$1" 1) $(field "$1" 2) $(field "$1" 3) $(field "$1" 4)"; }
state() { last_frame | awk -v k="$1" '$1 == "state" && $2 == k { sub("^state " k " ?", ""); v = $0 } END { print v }'; }
# Waits, with no input, until state $1 matches the extended regex $2 (within $3 s).
state_matches() { state "$1" | grep -Eq -- "$2"; }
wait_state() {
    local k=$1 re=$2 secs=${3:-10}
    wait_until 'state_matches "$k" "$re"' "$secs" "'$k' to match /$re/"
}

# start_viewer SCENE [ARGS...]: the window on a copy of SCENE in $OUT ($SCENE; SCENE
# itself if it is there already), its layout in $LAYOUT; returns once the scene is
# loaded and a frame shows it.
# quit_viewer: Ctrl+Q, and waits for the process to end.
start_viewer() {
    local src=$1
    shift
    SCENE=$OUT/$(basename "$src")
    [ "$src" -ef "$SCENE" ] || cp "$src" "$SCENE"
    (cd "$OUT" && exec "$BIN/raytracer-view" "$SCENE" --size "$SCREEN" --print-layout "$@" > "$LAYOUT" 2> "$OUT/viewer.err") &
    VIEWER_PID=$!
    WID=$(timeout 30 xdotool search --sync --name "$(basename "$SCENE")" | head -1) || fail "no window appeared"
    wait_state title "^$(basename "$SCENE")" 30
    wait_state load "^(ready|no scene)$" 60
    image_region
}

# open_model FILE TITLE [ARGS...]: the window on FILE (a model, relative to $OUT), which
# opens as a new scene TITLE; returns once it is loaded and rendered.
open_model() {
    local file=$1 title=$2
    shift 2
    (cd "$OUT" && exec "$BIN/raytracer-view" "$file" --size "$SCREEN" --print-layout "$@" > "$LAYOUT" 2> "$OUT/viewer.err") &
    VIEWER_PID=$!
    WID=$(timeout 30 xdotool search --sync --name "${title%.txt}" | head -1) || fail "no window appeared"
    wait_state title "^$title - raytracer-view$" 30
    wait_state load "^ready$" 60
    image_region
    wait_state render "done" 60
}

# $IMAGE ("x y w h") and ix iy iw ih: where the last frame drew the picture.
image_region() {
    IMAGE=$(region image)
    read -r ix iy iw ih <<< "$IMAGE"
}

quit_viewer() {
    key ctrl+q
    wait_until '! kill -0 "$VIEWER_PID" 2>/dev/null' 10 "the viewer to quit on Ctrl+Q"
    wait "$VIEWER_PID" 2>/dev/null || true
    VIEWER_PID=
}

# editor_xy LINE COL [FRACTION]: the screen point FRACTION (default 0.25) across the
# character at 1-based LINE and COL of the scene text, by the grid the editor draws.
editor_xy() {
    local line=$1 col=$2 frac=${3:-0.25} grid
    grid=$(state editor_grid)
    [ -n "$grid" ] || fail "the editor is not shown"
    awk -v g="$grid" -v l="$line" -v c="$col" -v f="$frac" 'BEGIN {
        split(g, a, " "); printf "%d %d\n", a[1] + (c - 1 + f) * a[3], a[2] + (l - 1 + 0.5) * a[4] }'
}

# Waits until the image region stops changing and shows a picture (NAME.png).
wait_stable() {
    local name=$1 prev="$OUT/.stable-prev.png" d
    shot "$name"
    for _ in $(seq 1 120); do
        # The time over which the picture must not change: the wait itself is what
        # "settled" means here (a bounded poll).
        sleep 0.3
        cp "$OUT/$name.png" "$prev"
        shot "$name"
        d=$("$TOOL" diff "$prev" "$OUT/$name.png" $IMAGE)
        [ "$d" = "0.000000" ] && [ "$("$TOOL" colours "$OUT/$name.png" $IMAGE)" -gt 1000 ] && return 0
    done
    fail "the image never settled ($name)"
}

# Clicks on the picture's top left corner (the sky, in the scenes journeys use) and
# waits until nothing is selected.
select_nothing() {
    image_region
    click $((ix + 5)) $((iy + 5))
    wait_state selection "^none$"
}

# The picture on the screen equals `raytracer`'s render of the saved $SCENE at the
# film's size (in the picture frame, picture_size), drawn at the image's size as the
# viewer's texture is (nothing selected, the render settled, not zoomed).
picture_agrees() {
    local name=$1
    image_region
    wait_state selection "^none$" 10
    wait_state render "done" 60
    IMAGE=$(region image)
    wait_stable "$name-shown"
    # The render's own settings (its samples, adaptive or not: raytracer's options).
    # shellcheck disable=SC2046
    "$BIN/raytracer" --quiet $(state render_settings) --width "$(field film 1)" \
        --height "$(field film 2)" "$SCENE" "$OUT/$name-ref.ppm" || fail "$name: raytracer could not render the saved text"
    "$TOOL" match-scaled "$OUT/$name-shown.png" $IMAGE "$OUT/$name-ref.ppm" ||
        fail "$name: the picture differs from raytracer's render of the saved text"
}

# Ctrl+S, then waits for the title to lose its "*".
save() {
    key ctrl+s
    wait_state title '^[^*]* - raytracer-view$' 10
}

# item_xy KEY: the centre of a rectangle the last frame drew under state KEY (probe_item:
# menu rows "menu:NAME" (spaces in NAME are _), outline rows "outline_object_4_left",
# fields "field_NAME").
item_xy() {
    local r
    r=$(state "$1")
    [ -n "$r" ] || fail "'$1' is not on the screen"
    echo "$r" | awk '{ printf "%d %d\n", $1 + $3 / 2, $2 + $4 / 2 }'
}
# click_item KEY: waits until KEY is on the screen, then clicks its centre.
click_item() {
    local x y
    wait_state "$1" '^-?[0-9]+ -?[0-9]+ [0-9]+ [0-9]+$' 5
    read -r x y <<< "$(item_xy "$1")"
    click "$x" "$y"
}
# type_value FIELD TEXT [NAME]: Ctrl+clicks the panel field probed as field_FIELD, waits
# until it takes the keyboard (as the field NAME, default FIELD), types TEXT, presses Enter.
type_value() {
    local x y w h
    wait_state "field_$1" '^-?[0-9]+ -?[0-9]+ [0-9]+ [0-9]+$' 10
    read -r x y w h <<< "$(state "field_$1")"
    xdotool mousemove $((x + w / 4)) $((y + h / 2)) keydown ctrl click 1 keyup ctrl
    wait_state typing "^${3:-$1} active$"
    type_text "$2"
    key Return
}
# pointer_to X Y: moves the pointer to (X, Y) and waits for a frame that saw it there
# (state pointer: "X Y", then " ui" over a panel, " down" with a button held).
pointer_to() {
    xdotool mousemove "$1" "$2"
    wait_state pointer "^$1 $2( |\$)"
}
# input_seen: waits until the viewer has taken every input event sent so far (a key
# held, a button): X delivers them in order, so a frame that saw the pointer move a
# pixel away and back saw them too.
input_seen() {
    local X Y SCREEN WINDOW
    eval "$(xdotool getmouselocation --shell)"
    pointer_to $((X + 1)) "$Y"
    pointer_to "$X" "$Y"
}
# drag X0 Y0 X1 Y1 [BUTTON]: presses at (X0, Y0), moves to (X1, Y1) in 20 steps, each
# seen by a frame of its own, releases.
drag() {
    local x0=$1 y0=$2 x1=$3 y1=$4 b=${5:-1} i
    pointer_to "$x0" "$y0"
    xdotool mousedown "$b"
    wait_state pointer " down\$"
    for i in $(seq 1 20); do
        pointer_to $((x0 + (x1 - x0) * i / 20)) $((y0 + (y1 - y0) * i / 20))
    done
    xdotool mouseup "$b"
}
# The number of layouts the viewer printed: a frame that changed anything adds one.
layouts() { grep -c '^end-layout$' "$LAYOUT"; }
# scroll_to KEY X Y: scrolls the wheel at (X, Y) (over the outline, the properties...)
# a notch at a time, each seen by a frame, until the item KEY is on the screen.
scroll_to() {
    local key=$1 i n
    pointer_to "$2" "$3"
    for i in $(seq 1 20); do
        [ -n "$(state "$key")" ] && return 0
        wheel_down "looking for '$key'"
    done
    fail "scrolling at $2 $3 never showed '$key'"
}
# wheel_down [WHY]: one notch of the wheel down where the pointer is, and waits for the
# frame that scrolled.
wheel_down() {
    local n
    n=$(layouts)
    xdotool click 5
    wait_until '[ "$(layouts)" -gt "$n" ]' 5 "the wheel to scroll ${1:-}"
}
# The middle of the layout's REGION: "x y".
region_mid() { region "$1" | awk '{ printf "%d %d\n", $1 + $3 / 2, $2 + $4 / 2 }'; }
# hover_item KEY: waits until KEY is on the screen and rests the pointer on it (a
# submenu opens on hover; a click would close it again).
hover_item() {
    local x y
    wait_state "$1" '^-?[0-9]+ -?[0-9]+ [0-9]+ [0-9]+$' 5
    read -r x y <<< "$(item_xy "$1")"
    xdotool mousemove "$x" "$y"
}

# The move handles of the default scene's two spheres (objects 1 and 2), read by
# selecting each from the outline: sets x1 y1 x2 y2 and leaves nothing selected.
sphere_handles() {
    click_item outline_object_1
    wait_state selection "^object_1$"
    read -r x1 y1 <<< "$(field handle 1) $(field handle 2)"
    click_item outline_object_2
    wait_state selection "^object_2$"
    read -r x2 y2 <<< "$(field handle 1) $(field handle 2)"
    key Escape
    wait_state selection "^none$"
}
