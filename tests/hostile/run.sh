#!/usr/bin/env bash
# Hostile cases for raytracer and raytracer-view-headless: odd encodings and line
# endings, scene extremes, special files, output edge cases, signals at random moments,
# option values and viewer cases. Every case must end in a clear error or a correct
# picture, stop within a second of a signal, and lose nothing: an existing OUT stays
# byte-identical unless the run succeeded, and no temporary file (.NAME.XXXXXX) is
# left behind.
#   tests/hostile/run.sh BIN_DIR [WORK_DIR]
# Environment: HOSTILE_FILTER=REGEX runs only the matching cases; HOSTILE_RENDER=0 skips
# the slow in-renderer cases (deep glass and mirror trees, thousands of lamps,
# --time-limit accuracy). Cases that need root (to act as another user) are skipped
# otherwise.
# Against a sanitizer build (tests/hostile/run.sh build-asan/bin, about 200 s) any
# AddressSanitizer or UndefinedBehaviorSanitizer report fails the case.
set -uo pipefail

BIN=$(cd "${1:?usage: run.sh BIN_DIR [WORK_DIR]}" && pwd)
RT=$BIN/raytracer
VIEW=$BIN/raytracer-view-headless
WORK=${2:-$(mktemp -d /tmp/rt-hostile-XXXXXX)}
mkdir -p "$WORK"
WORK=$(cd "$WORK" && pwd)
chmod 755 "$WORK"
FILTER=${HOSTILE_FILTER:-}
RENDER_FIXES=${HOSTILE_RENDER:-1}
ROOT=0; [ "$(id -u)" = 0 ] && ROOT=1
# A sanitizer build (scripts/sanitize.sh) can run the cases too: Mesa's own leaks are
# suppressed as in the viewer's tests, and the memory-limit cases are skipped there
# (AddressSanitizer cannot start under `ulimit -v`).
SANITIZED=0
ldd "$RT" 2> /dev/null | grep -qE 'libasan|libtsan' && SANITIZED=1
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$(cd "$(dirname "$0")/../viewer" && pwd)/lsan.supp}

pass=0 fail=0 skip=0
failed=()

# --- helpers ---------------------------------------------------------------------

# A case's folder, fresh, with a small good scene in it and a "precious" old OUT.
D=
SCENE_OK='thing { sphere { position 5 0 1  radius 1  material { colour 0.9 0.2 0.15 } } }
special_thing { plane { material { colour 0.6 0.6 0.6 } } }
light { lamp { position 2 3 6  colour 50 50 50  size 0.2 } }
camera { position 0 0 2  centre 5 0 1  up 5 0 2  angle_x 60  angle_y 46.8 }
picture_size { x_max 16 y_max 12 }
end'
newdir() {
    D=$WORK/$1
    rm -rf "$D"
    mkdir -p "$D"
    chmod 755 "$D"
    printf '%s\n' "$SCENE_OK" > "$D/ok.txt"
    printf 'precious\n' > "$D/old.ppm"
}

# Runs a command in $D with a time limit; sets RC, ERR (stderr), OUT_TEXT (stdout), SECS.
run() {
    local limit=$1; shift
    local t0 t1
    t0=$(date +%s.%N)
    (cd "$D" && timeout -k 2 "$limit" "$@" > "$WORK/.out" 2> "$WORK/.err" < /dev/null)
    RC=$?
    t1=$(date +%s.%N)
    SECS=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.2f", b - a }')
    ERR=$(tr -d '\000' < "$WORK/.err")
    OUT_TEXT=$(head -c 4096 "$WORK/.out" | tr -d '\000')
}

# Starts a command in $D in the background (PID), for signal cases.
start() {
    (cd "$D" && exec "$@" > "$WORK/.out" 2> "$WORK/.err" < /dev/null) &
    PID=$!
}
# Sends signals to PID after `delay`, then waits at most `limit` s; RC and SECS (the
# time from the first signal to the end).
signal_after() {
    local delay=$1 limit=$2; shift 2
    sleep "$delay"
    local t0 t1 s
    t0=$(date +%s.%N)
    for s in "$@"; do kill -s "$s" "$PID" 2> /dev/null; sleep 0.01; done
    local waited=0
    while kill -0 "$PID" 2> /dev/null && [ "$waited" -lt $((limit * 100)) ]; do sleep 0.01; waited=$((waited + 1)); done
    if kill -0 "$PID" 2> /dev/null; then kill -9 "$PID"; fi
    wait "$PID"
    RC=$?
    t1=$(date +%s.%N)
    SECS=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.2f", b - a }')
    ERR=$(tr -d '\000' < "$WORK/.err")
}

# Problems found by the checks of the current case (empty: it passed).
PROBLEMS=
# Until the run started with start() fills its temporary file for old.ppm (or ends;
# at most 30 s).
wait_for_temp_file() {
    local n=0
    until find "$D" -name '.old.ppm.*' -size +0 2> /dev/null | grep -q . || ! kill -0 "$PID" 2> /dev/null || [ $n -ge 6000 ]; do sleep 0.005; n=$((n + 1)); done
}
problem() { PROBLEMS+="$*; "; }
temps_left() { find "$D" -name '.*' -regextype posix-extended -regex '.*/\..*\.[A-Za-z0-9]{6}$' 2> /dev/null | head -3; }
# The standard checks after any run: no temporary file, old.ppm intact unless allowed.
clean_checks() {
    local t
    t=$(temps_left)
    [ -z "$t" ] || problem "temporary file left: $t"
    if [ "${1:-}" != replaced ] && [ -e "$D/old.ppm" ] && [ "$(cat "$D/old.ppm" 2> /dev/null)" != precious ]; then
        problem "old.ppm changed"
    fi
}
want_rc() { [ "$RC" = "$1" ] || problem "exit status $RC, expected $1"; }
want_err() { grep -qiE -- "$1" <<< "$ERR" || problem "stderr lacks /$1/: $(head -c 300 <<< "$ERR")"; }
want_fast() { awk -v s="$SECS" -v l="$1" 'BEGIN { exit !(s <= l) }' || problem "took $SECS s (limit $1 s)"; }
# stderr must be printable UTF-8: no control bytes but tabs and newlines (a terminal
# would act on them), no invalid sequences (Latin-1 or binary input echoed raw).
want_clean_text() {
    if LC_ALL=C grep -qP '[\x00-\x08\x0b-\x1f\x7f]|\xc2[\x80-\x9f]' "$WORK/.err"; then problem "control bytes in stderr"; fi
    iconv -f UTF-8 -t UTF-8 < "$WORK/.err" > /dev/null 2>&1 || problem "stderr is not valid UTF-8"
}
# A binary PPM of W x H.
want_ppm() {
    local f=$D/$1 w=$2 h=$3
    [ -f "$f" ] || { problem "$1 not written"; return; }
    local head
    head=$(head -c 20 "$f" | tr '\n\0' '  ' | cut -d' ' -f1-4)
    [ "$head" = "P6 $w $h 255" ] || problem "$1 header '$head', expected 'P6 $w $h 255'"
    local size
    size=$(stat -c %s "$f")
    [ "$size" -ge $((w * h * 3)) ] || problem "$1 is truncated ($size bytes)"
}

# case NAME KIND: runs the body (the function case_NAME) unless filtered or skipped.
declare -a ORDER=()
def() { ORDER+=("$1"); }
run_case() {
    local name=$1
    [ -n "$FILTER" ] && ! grep -qE -- "$FILTER" <<< "$name" && return
    PROBLEMS=
    SKIPPED=
    : > "$WORK/.err"
    local t0
    t0=$(date +%s%N)
    SECS=
    "case_$name"
    # Whatever the case expected, a sanitizer's report is a failure.
    if grep -qE 'Sanitizer|runtime error:' "$WORK/.err" 2> /dev/null; then problem "sanitizer report: $(grep -m1 -E 'Sanitizer|runtime error:' "$WORK/.err")"; fi
    SECS="${SECS:-0} s (case $(( ($(date +%s%N) - t0) / 1000000 )) ms)"
    if [ -n "$SKIPPED" ]; then
        skip=$((skip + 1)); printf 'skip  %-44s %s\n' "$name" "$SKIPPED"
    elif [ -z "$PROBLEMS" ]; then
        pass=$((pass + 1)); printf 'ok    %-44s %s\n' "$name" "${SECS:-0}"
    else
        fail=$((fail + 1)); failed+=("$name"); printf 'FAIL  %-44s %s\n' "$name" "$PROBLEMS"
    fi
}
need_root() { [ "$ROOT" = 1 ] || SKIPPED="(needs root to act as another user)"; }
need_render_fixes() { [ "$RENDER_FIXES" = 1 ] || SKIPPED="(render cases off: HOSTILE_RENDER=0)"; }
need_no_sanitizer() { [ "$SANITIZED" = 0 ] || SKIPPED="(a sanitizer build cannot run under ulimit -v)"; }
need_viewer() { [ -x "$VIEW" ] || SKIPPED="(no raytracer-view-headless)"; }
AS_NOBODY=(setpriv --reuid=65534 --regid=65534 --clear-groups)

# Scene builders.
lamps_scene() {  # N lamps in a grid over a plane
    local n=$1
    echo 'special_thing { plane { material { colour 0.6 0.6 0.6 } } }'
    awk -v n="$n" 'BEGIN { for (i = 0; i < n; i++) printf "light { lamp { position %d %d %d colour 0.01 0.01 0.01 size 0.05 } }\n", 5 + i % 50, (i / 50) % 50 - 25, 3 + int(i / 2500) }'
    echo 'camera { position 0 0 2  centre 5 0 1  up 5 0 2  angle_x 60  angle_y 46.8 }'
    echo 'picture_size { x_max 16 y_max 12 }'
    echo end
}
mirror_box_scene() {  # a glass ball inside a box of mirrors
    cat <<'EOF'
thing {
  sphere { position 0 0 0 radius 1 material { refraction 0.9 reflection 0.1 scattering 0 refractive_index 1.5 colour 1 1 1 } }
  sphere { position 0.5 0.5 0.5 radius 0.3 material { refraction 0.5 reflection 0.5 scattering 0 refractive_index 1.3 colour 1 1 1 } }
}
special_thing {
  plane { point 1 0 0 -3 point 2 1 0 -3 point 3 0 1 -3 point 4 0 0 0 material { reflection 0.95 scattering 0.05 colour 1 1 1 } }
  plane { point 1 0 0 3 point 2 1 0 3 point 3 0 1 3 point 4 0 0 0 material { reflection 0.95 scattering 0.05 colour 1 1 1 } }
  plane { point 1 -3 0 0 point 2 -3 1 0 point 3 -3 0 1 point 4 0 0 0 material { reflection 0.95 scattering 0.05 colour 1 1 1 } }
  plane { point 1 3 0 0 point 2 3 1 0 point 3 3 0 1 point 4 0 0 0 material { reflection 0.95 scattering 0.05 colour 1 1 1 } }
  plane { point 1 0 -3 0 point 2 1 -3 0 point 3 0 -3 1 point 4 0 0 0 material { reflection 0.95 scattering 0.05 colour 1 1 1 } }
  plane { point 1 0 3 0 point 2 1 3 0 point 3 0 3 1 point 4 0 0 0 material { reflection 0.95 scattering 0.05 colour 1 1 1 } }
}
light { lamp { position 1.5 1.5 2 colour 5 5 5 size 0.1 } }
camera { position -2 -2 -1 centre 0 0 0 up 0 0 1 angle_x 60 angle_y 45 }
picture_size { x_max 16 y_max 12 }
end
EOF
}
endless_box_scene() {  # the same box with perfect mirrors: no ray ever weighs less, so it never ends
    mirror_box_scene | sed 's/reflection 0.95 scattering 0.05/reflection 1 scattering 0/'
}
spheres_scene() {  # N spheres, all at one point (coincident) or in a row
    local n=$1 same=${2:-0}
    echo 'thing {'
    awk -v n="$n" -v same="$same" 'BEGIN { for (i = 0; i < n; i++) printf "  sphere { position %s 0 1 radius 0.4 material { colour 0.8 0.8 0.8 } }\n", same ? 5 : 5 + i * 0.001 }'
    echo '}'
    echo 'light { lamp { position 2 3 6  colour 50 50 50  size 0.2 } }'
    echo 'camera { position 0 0 2  centre 5 0 1  up 5 0 2  angle_x 60  angle_y 46.8 }'
    echo 'picture_size { x_max 16 y_max 12 }'
    echo end
}
empty_scene() {  # nothing to hit: renders fast at any size
    printf '%s\n' 'light { spotlight { position 2 3 6 colour 50 50 50 } }' \
        'camera { position 0 0 2  centre 5 0 1  up 5 0 2  angle_x 60  angle_y 46.8 }' \
        "picture_size { x_max $1 y_max $2 }" end
}
plane_only_scene() {  # renders fast at any size
    local w=$1 h=$2
    printf '%s\n' 'special_thing { plane { material { colour 0.6 0.6 0.6 } } }' \
        'light { spotlight { position 2 3 6 colour 50 50 50 } }' \
        'camera { position 0 0 2  centre 5 0 1  up 5 0 2  angle_x 60  angle_y 46.8 }' \
        "picture_size { x_max $w y_max $h }" end
}

# --- encodings and line endings ---------------------------------------------------

def utf16le_bom; case_utf16le_bom() { newdir "$FUNCNAME"; printf '\xff\xfe' > "$D/s.txt"; printf '%s\n' "$SCENE_OK" | iconv -f UTF-8 -t UTF-16LE >> "$D/s.txt"
    run 10 "$RT" s.txt old.ppm; want_rc 1; want_err 's.txt:1:1: error: .*UTF-16'; want_clean_text; clean_checks; }
def utf16be_bom; case_utf16be_bom() { newdir "$FUNCNAME"; printf '\xfe\xff' > "$D/s.txt"; printf '%s\n' "$SCENE_OK" | iconv -f UTF-8 -t UTF-16BE >> "$D/s.txt"
    run 10 "$RT" s.txt old.ppm; want_rc 1; want_err 'UTF-16'; want_clean_text; clean_checks; }
def utf16le_nobom; case_utf16le_nobom() { newdir "$FUNCNAME"; printf '%s\n' "$SCENE_OK" | iconv -f UTF-8 -t UTF-16LE > "$D/s.txt"
    run 10 "$RT" s.txt old.ppm; want_rc 1; want_err 'UTF-16'; want_clean_text; clean_checks; }
def utf16be_nobom; case_utf16be_nobom() { newdir "$FUNCNAME"; printf '%s\n' "$SCENE_OK" | iconv -f UTF-8 -t UTF-16BE > "$D/s.txt"
    run 10 "$RT" s.txt old.ppm; want_rc 1; want_err 'UTF-16'; want_clean_text; clean_checks; }
def utf32_bom; case_utf32_bom() { newdir "$FUNCNAME"; printf '%s\n' "$SCENE_OK" | iconv -f UTF-8 -t UTF-32 > "$D/s.txt"
    run 10 "$RT" --check s.txt; want_rc 1; want_err 'UTF-32|UTF-16'; want_clean_text; clean_checks; }
def utf8_bom; case_utf8_bom() { newdir "$FUNCNAME"; { printf '\xef\xbb\xbf'; printf '%s\n' "$SCENE_OK"; } > "$D/s.txt"
    run 10 "$RT" s.txt new.ppm; [ "$RC" = 0 ] && want_ppm new.ppm 16 12 || { want_rc 1; want_err 's.txt:1:1: error'; }; want_clean_text; clean_checks; }
def latin1_comment; case_latin1_comment() { newdir "$FUNCNAME"; { printf '// caf\xe9 cr\xe8me\n'; printf '%s\n' "$SCENE_OK"; } > "$D/s.txt"
    run 10 "$RT" s.txt new.ppm; want_rc 0; want_ppm new.ppm 16 12; want_clean_text; clean_checks; }
def latin1_key; case_latin1_key() { newdir "$FUNCNAME"; { printf 'thing { sph\xe8re { } }\n'; printf '%s\n' "$SCENE_OK"; } > "$D/s.txt"
    run 10 "$RT" s.txt old.ppm; want_rc 1; want_err 's.txt:1:9: error: .*\\xe8'; want_clean_text; clean_checks; }
def ansi_escape_key; case_ansi_escape_key() { newdir "$FUNCNAME"; printf 'thing { \x1b[2J\x1b]0;owned\x07 { } }\nend\n' > "$D/s.txt"
    run 10 "$RT" --check s.txt; want_rc 1; want_err 'error'; want_clean_text; clean_checks; }
def c1_controls; case_c1_controls() { newdir "$FUNCNAME"; printf 'thing { x\xc2\x9b31m { } }\nend\n' > "$D/s.txt"
    run 10 "$RT" --check s.txt; want_rc 1; want_clean_text; clean_checks; }
def nul_bytes; case_nul_bytes() { newdir "$FUNCNAME"; { printf 'thing {\0\0 sphere'; printf '%s\n' "$SCENE_OK"; } > "$D/s.txt"
    run 10 "$RT" s.txt old.ppm; want_rc 1; want_err 's.txt:1:[0-9]+: error'; want_clean_text; clean_checks; }
def binary_garbage; case_binary_garbage() { newdir "$FUNCNAME"; head -c 65536 /dev/urandom > "$D/s.txt"
    run 10 "$RT" s.txt old.ppm; [ "$RC" = 1 ] || [ "$RC" = 1 ] || problem "exit $RC"; want_rc 1; want_clean_text; clean_checks
    local lines; lines=$(grep -c 'error' <<< "$ERR"); [ "$lines" -le 22 ] || problem "$lines error lines (cap 20)"; }
def crlf; case_crlf() { newdir "$FUNCNAME"; printf '%s\n' "$SCENE_OK" | sed 's/$/\r/' > "$D/s.txt"
    run 10 "$RT" s.txt new.ppm; want_rc 0; want_ppm new.ppm 16 12; clean_checks; }
def crlf_error_line; case_crlf_error_line() { newdir "$FUNCNAME"; printf 'thing {\r\n sphere {\r\n radius x } }\r\nend\r\n' > "$D/s.txt"
    run 10 "$RT" --check s.txt; want_rc 1; want_err 's.txt:3:'; want_clean_text; clean_checks; }
def cr_only; case_cr_only() { newdir "$FUNCNAME"
    printf '// comment\rthing {\r sphere {\r radius x } }\rend\r' > "$D/s.txt"
    run 10 "$RT" --check s.txt; want_rc 1; want_err 's.txt:4:'; want_clean_text; clean_checks; }
def mixed_endings; case_mixed_endings() { newdir "$FUNCNAME"; printf '%s\n' "$SCENE_OK" | awk '{ printf "%s%s", $0, (NR % 2 ? "\r\n" : "\n") }' > "$D/s.txt"
    run 10 "$RT" s.txt new.ppm; want_rc 0; want_ppm new.ppm 16 12; clean_checks; }
def no_final_newline; case_no_final_newline() { newdir "$FUNCNAME"; printf '%s' "$SCENE_OK" > "$D/s.txt"
    run 10 "$RT" s.txt new.ppm; want_rc 0; want_ppm new.ppm 16 12; clean_checks; }
def tabs_and_formfeeds; case_tabs_and_formfeeds() { newdir "$FUNCNAME"; printf '%s\n' "$SCENE_OK" | tr ' ' '\t' > "$D/s.txt"
    run 10 "$RT" s.txt new.ppm; want_rc 0; want_ppm new.ppm 16 12; clean_checks; }
def empty_file; case_empty_file() { newdir "$FUNCNAME"; : > "$D/s.txt"
    run 10 "$RT" s.txt old.ppm; want_rc 1; want_err 's.txt:'; clean_checks; }
def long_line; case_long_line() { newdir "$FUNCNAME"; { head -c 2000000 /dev/zero | tr '\0' 'x'; echo; echo end; } > "$D/s.txt"
    run 10 "$RT" s.txt old.ppm; want_rc 1; want_fast 5; want_clean_text; clean_checks
    [ "${#ERR}" -lt 20000 ] || problem "stderr of ${#ERR} bytes"; }
def deep_braces; case_deep_braces() { newdir "$FUNCNAME"; { for _ in $(seq 20000); do printf 'thing { '; done; echo end; } > "$D/s.txt"
    run 10 "$RT" s.txt old.ppm; want_rc 1; want_fast 5; clean_checks; }
def many_warnings; case_many_warnings() { newdir "$FUNCNAME"
    { echo 'thing {'; for _ in $(seq 2000); do echo 'sphere { position 5 0 1 radius 1 material { reflection 0 refraction 0 scattering 0 } }'; done; echo '}'
      printf '%s\n' "$SCENE_OK"; } > "$D/s.txt"
    run 20 "$RT" s.txt new.ppm; want_rc 0; want_ppm new.ppm 16 12
    local n; n=$(grep -c 'warning' <<< "$ERR"); [ "$n" -le 21 ] || problem "$n warnings printed (cap 20)"; want_err 'more warnings not shown'; clean_checks; }

# --- scene extremes ---------------------------------------------------------------

def mirror_box_depth1000_sigterm; case_mirror_box_depth1000_sigterm() { newdir "$FUNCNAME"; endless_box_scene > "$D/s.txt"
    start "$RT" --quiet --max-depth 1000 s.txt old.ppm; signal_after 1 5 TERM; want_rc 143; want_fast 1; want_err interrupted; clean_checks; }
def mirror_box_depth1000_sigint; case_mirror_box_depth1000_sigint() { newdir "$FUNCNAME"; endless_box_scene > "$D/s.txt"
    start "$RT" --quiet --max-depth 1000 --width 2 --height 2 s.txt old.ppm; signal_after 0.5 5 INT; want_rc 130; want_fast 1; clean_checks; }
def mirror_box_depth1000_timeout; case_mirror_box_depth1000_timeout() { newdir "$FUNCNAME"; endless_box_scene > "$D/s.txt"
    # `timeout` alone (one SIGTERM) must end it.
    run 30 timeout 2 "$RT" --quiet --max-depth 1000 s.txt old.ppm; want_rc 124; want_fast 3; clean_checks; }
def mirror_box_depth1000_finishes; case_mirror_box_depth1000_finishes() { need_render_fixes; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; mirror_box_scene > "$D/s.txt"
    run 60 "$RT" --quiet --max-depth 1000 s.txt new.ppm; want_rc 0; want_ppm new.ppm 16 12; want_fast 10; clean_checks; }
def lamps_1000; case_lamps_1000() { newdir "$FUNCNAME"; lamps_scene 1000 > "$D/s.txt"
    run 30 "$RT" --quiet s.txt new.ppm; want_rc 0; want_ppm new.ppm 16 12; clean_checks; }
def lamps_10000_check; case_lamps_10000_check() { newdir "$FUNCNAME"; lamps_scene 10000 > "$D/s.txt"
    run 10 "$RT" --check s.txt; want_rc 0; want_fast 3; want_err '10000 lights'; clean_checks; }
def lamps_10000_sigterm; case_lamps_10000_sigterm() { newdir "$FUNCNAME"; lamps_scene 10000 > "$D/s.txt"
    start "$RT" --quiet --width 640 --height 480 s.txt old.ppm; signal_after 1 5 TERM; want_rc 143; want_fast 1; clean_checks; }
def lamps_10000_finishes; case_lamps_10000_finishes() { need_render_fixes; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; lamps_scene 10000 > "$D/s.txt"
    run 60 "$RT" --quiet s.txt new.ppm; want_rc 0; want_ppm new.ppm 16 12; want_fast 5; clean_checks; }
def lamps_10000_viewer_time_limit; case_lamps_10000_viewer_time_limit() { need_render_fixes; need_viewer; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; lamps_scene 10000 > "$D/s.txt"
    run 60 "$VIEW" s.txt --screenshot shot.png --size 320x240 --time-limit 2; want_rc 0; want_fast 6; clean_checks; }
def time_limit_accuracy; case_time_limit_accuracy() { need_render_fixes; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; mirror_box_scene > "$D/s.txt"
    run 30 "$RT" --quiet --samples 65536 --time-limit 1 --width 160 --height 120 s.txt new.ppm; want_rc 0; want_fast 1.3; want_ppm new.ppm 160 120; clean_checks; }
def huge_picture_sigterm; case_huge_picture_sigterm() { newdir "$FUNCNAME"
    start "$RT" --quiet --width 16384 --height 16384 ok.txt old.ppm; signal_after 1.5 5 TERM; want_rc 143; want_fast 1; clean_checks; }
def huge_picture_memory_limit; case_huge_picture_memory_limit() { need_no_sanitizer; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"
    start bash -c "ulimit -v 8000000; exec '$RT' --quiet --width 16384 --height 16384 ok.txt old.ppm"; signal_after 2 5 TERM
    [ "$RC" = 143 ] || { want_rc 2; want_err 'out of memory'; }; clean_checks; }
def huge_picture_check; case_huge_picture_check() { newdir "$FUNCNAME"
    run 10 "$RT" --width 16384 --height 16384 --print-scene ok.txt; want_rc 0; grep -q 'x_max 16384' <<< "$OUT_TEXT" || problem "no x_max 16384"; clean_checks; }
def size_16385; case_size_16385() { newdir "$FUNCNAME"; run 10 "$RT" --width 16385 ok.txt old.ppm; want_rc 2; want_err '1 and 16384'; clean_checks; }
def picture_1x1; case_picture_1x1() { newdir "$FUNCNAME"; run 10 "$RT" --width 1 --height 1 ok.txt new.ppm; want_rc 0; want_ppm new.ppm 1 1; clean_checks; }
def picture_1x4000; case_picture_1x4000() { newdir "$FUNCNAME"; run 20 "$RT" --quiet --width 1 --height 4000 ok.txt new.ppm; want_rc 0; want_ppm new.ppm 1 4000; clean_checks; }
def coincident_spheres; case_coincident_spheres() { newdir "$FUNCNAME"; spheres_scene 2000 1 > "$D/s.txt"
    run 30 "$RT" --quiet s.txt new.ppm; want_rc 0; want_ppm new.ppm 16 12; clean_checks; }
def row_of_spheres; case_row_of_spheres() { newdir "$FUNCNAME"; spheres_scene 20000 0 > "$D/s.txt"
    run 30 "$RT" --quiet s.txt new.ppm; want_rc 0; want_ppm new.ppm 16 12; clean_checks; }
def build_200k_sigterm; case_build_200k_sigterm() { newdir "$FUNCNAME"; spheres_scene 200000 0 > "$D/s.txt"
    start "$RT" --quiet --width 4000 --height 3000 s.txt old.ppm; signal_after 0.7 5 TERM; want_rc 143; want_fast 1; clean_checks; }
def zero_radius; case_zero_radius() { newdir "$FUNCNAME"; printf '%s\n' "${SCENE_OK/radius 1 /radius 0 }" > "$D/s.txt"
    run 10 "$RT" s.txt new.ppm; [ "$RC" = 0 ] && want_ppm new.ppm 16 12 || { want_rc 1; want_err 'error'; }; clean_checks; }
def degenerate_tetrahedron; case_degenerate_tetrahedron() { newdir "$FUNCNAME"
    { echo 'thing { tetrahedron { point 1 5 0 0 point 2 5 0 0 point 3 5 0 0 point 4 5 0 0 } }'; printf '%s\n' "$SCENE_OK" | tail -n +2; } > "$D/s.txt"
    run 10 "$RT" s.txt new.ppm; [ "$RC" = 0 ] && want_ppm new.ppm 16 12 || { want_rc 1; want_err 'error'; }; clean_checks; }
def flat_tetrahedron; case_flat_tetrahedron() { newdir "$FUNCNAME"
    { echo 'thing { tetrahedron { point 1 5 0 0 point 2 5 1 0 point 3 5 0 1 point 4 5 1 1 } }'; printf '%s\n' "$SCENE_OK" | tail -n +2; } > "$D/s.txt"
    run 10 "$RT" s.txt new.ppm; [ "$RC" = 0 ] && want_ppm new.ppm 16 12 || { want_rc 1; want_err 'error'; }; clean_checks; }
def torus_minor_gt_major; case_torus_minor_gt_major() { newdir "$FUNCNAME"
    { echo 'thing { torus { position 5 0 1 major 0.2 minor 1 } }'; printf '%s\n' "$SCENE_OK" | tail -n +2; } > "$D/s.txt"
    run 10 "$RT" s.txt new.ppm; [ "$RC" = 0 ] && want_ppm new.ppm 16 12 || { want_rc 1; want_err 'error'; }; clean_checks; }
def huge_coordinates; case_huge_coordinates() { newdir "$FUNCNAME"; printf '%s\n' "${SCENE_OK/position 5 0 1 /position 1e15 0 1 }" > "$D/s.txt"
    run 10 "$RT" s.txt new.ppm; [ "$RC" = 0 ] && want_ppm new.ppm 16 12 || { want_rc 1; want_err 'error'; }; clean_checks; }
def out_of_range_number; case_out_of_range_number() { newdir "$FUNCNAME"; printf '%s\n' "${SCENE_OK/radius 1 /radius 1e400 }" > "$D/s.txt"
    run 10 "$RT" s.txt old.ppm; want_rc 1; want_err 'out of range'; clean_checks; }
def camera_up_collinear; case_camera_up_collinear() { newdir "$FUNCNAME"; printf '%s\n' "${SCENE_OK/up 5 0 2/up 10 0 0}" > "$D/s.txt"
    run 10 "$RT" s.txt new.ppm; [ "$RC" = 0 ] && want_ppm new.ppm 16 12 || { want_rc 1; want_err 'error'; }; clean_checks; }
def camera_inside_sphere; case_camera_inside_sphere() { newdir "$FUNCNAME"; printf '%s\n' "${SCENE_OK/radius 1 /radius 10 }" > "$D/s.txt"
    run 10 "$RT" s.txt new.ppm; want_rc 0; want_ppm new.ppm 16 12; clean_checks; }
def csg_coincident; case_csg_coincident() { newdir "$FUNCNAME"
    { echo 'thing { constructive_solid_geometry { difference sphere { position 5 0 1 radius 1 } sphere { position 5 0 1 radius 1 } } }'; printf '%s\n' "$SCENE_OK" | tail -n +2; } > "$D/s.txt"
    run 10 "$RT" s.txt new.ppm; [ "$RC" = 0 ] && want_ppm new.ppm 16 12 || { want_rc 1; want_err 'error'; }; clean_checks; }
# The scene with its first object replaced by THING (the lights, camera and size kept).
with_thing() { printf 'thing { %s }\n' "$1"; printf '%s\n' "$SCENE_OK" | tail -n +2; }
# refused ERROR MAKER ARGS...: the scene MAKER ARGS writes is refused with ERROR, and the
# old output stays; renders MAKER ARGS...: it renders.
refused() { local err=$1; shift; "$@" > "$D/s.txt"; run 10 "$RT" s.txt old.ppm; want_rc 1; want_err "$err"; clean_checks; }
renders() { "$@" > "$D/s.txt"; run 10 "$RT" s.txt new.ppm; want_rc 0; want_ppm new.ppm 16 12; clean_checks; }
# Box, cone and transforms: each mistake an error naming it, nothing rendered.
def box_equal_corners; case_box_equal_corners() { newdir "$FUNCNAME"; refused 's.txt:1:9: error: box corner_1 and corner_2 are the same point' with_thing 'box { corner_1 5 0 1 corner_2 5 0 1 }'; }
def box_flat; case_box_flat() { newdir "$FUNCNAME"; refused 'box is flat' with_thing 'box { corner_1 5 0 1 corner_2 6 1 1 }'; }
def cone_both_radii_zero; case_cone_both_radii_zero() { newdir "$FUNCNAME"; refused 'radius_1 and radius_2 are both 0' with_thing 'cone { end_1 5 0 0 end_2 5 0 2 radius_1 0 radius_2 0 }'; }
def cone_point_and_huge_base; case_cone_point_and_huge_base() { newdir "$FUNCNAME"; renders with_thing 'cone { end_1 5 0 0 end_2 5 0 1e-9 radius_1 1e15 radius_2 0 } cone { end_1 5 0 0 end_2 1e15 0 0 radius_1 0 radius_2 1e-15 }'; }
def scale_zero; case_scale_zero() { newdir "$FUNCNAME"; refused 's.txt:1:48: error: scale must be 1e-9 .. 1e9 on every axis' with_thing 'sphere { position 5 0 1 radius 1 scale 0 }'; }
def scale_negative_axis; case_scale_negative_axis() { newdir "$FUNCNAME"; refused 'mirrors, are refused' with_thing 'box { corner_1 0 0 0 corner_2 1 1 1 scale 1 -1 1 }'; }
def rotation_nan; case_rotation_nan() { newdir "$FUNCNAME"; refused "expected 3 numbers after 'rotation', got 'nan'" with_thing 'sphere { rotation nan 0 0 }'; }
def rotation_inf; case_rotation_inf() { newdir "$FUNCNAME"; refused 'out of range' with_thing 'sphere { rotation 0 1e400 0 }'; }
def transform_extremes; case_transform_extremes() { newdir "$FUNCNAME"
    with_thing 'sphere { position 1e15 0 0 radius 1e15 scale 1e9 rotation 1e15 -1e15 7 translate -1e15 0 1e15 } box { corner_1 0 0 0 corner_2 1e-15 1e-15 1e-15 scale 1e-9 } cone { scale 1e-9 1e9 1 rotation 0 90 0 }' > "$D/s.txt"
    run 10 "$RT" s.txt new.ppm; want_rc 0; want_ppm new.ppm 16 12; clean_checks; }
def transformed_csg_256_deep; case_transformed_csg_256_deep() { newdir "$FUNCNAME"
    { printf 'thing { '; for _ in $(seq 256); do printf 'constructive_solid_geometry { type U rotation 1 2 3 scale 1.01 translate 0.01 0 0 left { '; done
      printf 'box { corner_1 4 -1 0 corner_2 6 1 2 }'; for _ in $(seq 256); do printf ' } right { cone { end_1 5 0 0 end_2 5 0 1 } } }'; done
      echo ' }'; printf '%s\n' "$SCENE_OK" | tail -n +2; } > "$D/s.txt"
    run 20 "$RT" s.txt new.ppm; want_rc 0; want_ppm new.ppm 16 12; clean_checks; }
# Named materials and includes: each mistake an error at its place, nothing rendered.
with_head() { printf '%s\n' "$1"; printf '%s\n' "$SCENE_OK"; }
def material_used_before_defined; case_material_used_before_defined() { newdir "$FUNCNAME"; refused "s.txt:1:27: error: unknown material 'gold'" with_head 'thing { sphere { material gold } } define { material gold { } }'; }
def material_defined_twice; case_material_defined_twice() { newdir "$FUNCNAME"; refused "s.txt:1:37: error: material 'gold' is defined twice" with_head 'define { material gold { } material gold { } }'; }
def material_as_object; case_material_as_object() { newdir "$FUNCNAME"; refused "unknown object 'gold'" with_head 'define { material gold { } } thing { gold { } }'; }
def instance_undefined; case_instance_undefined() { newdir "$FUNCNAME"; refused "s.txt:1:27: error: unknown object 'chair'" with_head 'thing { instance { object chair translate 5 0 0 } }'; }
def instance_of_material; case_instance_of_material() { newdir "$FUNCNAME"; refused "'gold' is a material, not an object" with_head 'define { material gold { } } thing { instance { object gold } }'; }
def instances_100k; case_instances_100k() { newdir "$FUNCNAME"
    { echo 'define { object post { constructive_solid_geometry { left { cylinder { end_1 0 0 0 end_2 0 0 1 radius 0.1 } } right { cone { end_1 0 0 1 end_2 0 0 1.3 } } } } }'
      awk 'BEGIN { print "thing {"; for (i = 0; i < 100000; i++) printf "instance { object post translate %d %d 0 scale 1 1 %d }\n", 5 + i % 300, i / 300 - 150, 1 + i % 3; print "}" }'
      printf '%s\n' "$SCENE_OK" | tail -n +2; } > "$D/s.txt"
    run 30 "$RT" s.txt new.ppm; want_rc 0; want_ppm new.ppm 16 12; want_fast 10; clean_checks; }
def include_missing; case_include_missing() { newdir "$FUNCNAME"; refused "s.txt:1:1: error: cannot include 'nothing.txt': No such file" with_head 'include "nothing.txt"'; }
def include_folder; case_include_folder() { newdir "$FUNCNAME"; mkdir "$D/sub"; with_head 'include "sub"' > "$D/s.txt"
    run 10 "$RT" s.txt old.ppm; want_rc 1; want_err 'it is a folder'; clean_checks; }
def include_dev_zero; case_include_dev_zero() { newdir "$FUNCNAME"; with_head 'include "/dev/zero"' > "$D/s.txt"
    run 10 "$RT" s.txt old.ppm; want_rc 1; want_err 'not a regular file'; want_fast 2; clean_checks; }
def include_fifo; case_include_fifo() { newdir "$FUNCNAME"; mkfifo "$D/pipe.txt"; with_head 'include "pipe.txt"' > "$D/s.txt"
    run 10 "$RT" s.txt old.ppm; want_rc 1; want_err 'not a regular file'; want_fast 2; clean_checks; }
def include_itself; case_include_itself() { newdir "$FUNCNAME"; with_head 'include "s.txt"' > "$D/s.txt"
    run 10 "$RT" s.txt old.ppm; want_rc 1; want_err 's.txt:1:1: error: include cycle: the scene includes s.txt, the scene itself'; want_fast 2; clean_checks; }
def include_cycle_of_three; case_include_cycle_of_three() { newdir "$FUNCNAME"
    echo 'include "b.txt"' > "$D/a.txt"; echo 'include "c.txt"' > "$D/b.txt"; echo 'include "a.txt"' > "$D/c.txt"; with_head 'include "a.txt"' > "$D/s.txt"
    run 10 "$RT" s.txt old.ppm; want_rc 1; want_err 'c.txt:1:1: error: include cycle: a.txt includes b.txt includes c.txt includes a.txt'; clean_checks; }
def include_chain_65; case_include_chain_65() { newdir "$FUNCNAME"
    for i in $(seq 65); do echo "include \"n$((i + 1)).txt\"" > "$D/n$i.txt"; done; echo 'thing { sphere { } }' > "$D/n66.txt"; with_head 'include "n1.txt"' > "$D/s.txt"
    run 10 "$RT" s.txt old.ppm; want_rc 1; want_err 'includes nested too deeply \(limit 64 files\)'; clean_checks; }
def include_10mb_nested_csg; case_include_10mb_nested_csg() { newdir "$FUNCNAME"
    awk 'BEGIN { printf "thing {\n"; for (i = 0; i < 20000; i++) { printf "constructive_solid_geometry { type U rotation 0 0 %d left { ", i % 360; for (k = 0; k < 200; k++) printf "constructive_solid_geometry { left { "; printf "box { corner_1 4 -1 0 corner_2 6 1 2 }"; for (k = 0; k < 200; k++) printf " } right { sphere { position 5 0 1 radius 0.5 } } }"; printf " } right { cone { end_1 5 0 0 end_2 5 0 1 } } }\n"; if (i > 520) break } printf "}\n" }' > "$D/big.txt"
    with_head 'include "big.txt"' > "$D/s.txt"
    run 60 "$RT" s.txt new.ppm; want_rc 0; want_ppm new.ppm 16 12; clean_checks; }

# --- special files ------------------------------------------------------------------

def scene_dev_zero; case_scene_dev_zero() { newdir "$FUNCNAME"; run 20 "$RT" /dev/zero old.ppm; want_rc 2; want_err 'larger than'; want_fast 5; clean_checks; }
def scene_dev_null; case_scene_dev_null() { newdir "$FUNCNAME"; run 10 "$RT" /dev/null old.ppm; want_rc 1; clean_checks; }
def scene_dev_urandom; case_scene_dev_urandom() { newdir "$FUNCNAME"; run 20 "$RT" /dev/urandom old.ppm; want_rc 2; want_err 'larger than'; want_fast 10; clean_checks; }
def scene_folder; case_scene_folder() { newdir "$FUNCNAME"; run 10 "$RT" . old.ppm; want_rc 2; want_err 'Is a directory'; clean_checks; }
def scene_sparse_10g; case_scene_sparse_10g() { newdir "$FUNCNAME"; truncate -s 10G "$D/s.txt"; run 10 "$RT" s.txt old.ppm; want_rc 2; want_err 'larger than'; want_fast 2; clean_checks; }
def scene_sparse_tail; case_scene_sparse_tail() { newdir "$FUNCNAME"; printf '%s\n' "$SCENE_OK" > "$D/s.txt"; truncate -s 1M "$D/s.txt"
    # A megabyte of NUL bytes after `end`, which ends the scene.
    run 10 "$RT" s.txt new.ppm; [ "$RC" = 0 ] && want_ppm new.ppm 16 12 || { want_rc 1; want_clean_text; }; clean_checks; }
def scene_sparse_head; case_scene_sparse_head() { newdir "$FUNCNAME"; truncate -s 1M "$D/s.txt"; printf '%s\n' "$SCENE_OK" >> "$D/s.txt"
    run 10 "$RT" s.txt old.ppm; want_rc 1; want_clean_text; clean_checks; }
def scene_fifo_sigterm; case_scene_fifo_sigterm() { newdir "$FUNCNAME"; mkfifo "$D/s.txt"; start "$RT" s.txt old.ppm; signal_after 0.3 5 TERM; want_rc 143; want_fast 1; clean_checks; }
def scene_fifo_sigint; case_scene_fifo_sigint() { newdir "$FUNCNAME"; mkfifo "$D/s.txt"; start "$RT" s.txt old.ppm; signal_after 0.3 5 INT; want_rc 130; want_fast 1; clean_checks; }
def scene_fifo_sighup; case_scene_fifo_sighup() { newdir "$FUNCNAME"; mkfifo "$D/s.txt"; start "$RT" s.txt old.ppm; signal_after 0.3 5 HUP; want_rc 129; want_fast 1; clean_checks; }
def scene_fifo_fed; case_scene_fifo_fed() { newdir "$FUNCNAME"; mkfifo "$D/s.txt"; (printf '%s\n' "$SCENE_OK" > "$D/s.txt" &)
    run 10 "$RT" s.txt new.ppm; want_rc 0; want_ppm new.ppm 16 12; clean_checks; }
def scene_proc; case_scene_proc() { newdir "$FUNCNAME"; run 10 "$RT" /proc/self/status old.ppm; want_rc 1; want_err 'error'; clean_checks; }
def scene_symlink_loop; case_scene_symlink_loop() { newdir "$FUNCNAME"; ln -s a.txt "$D/b.txt"; ln -s b.txt "$D/a.txt"; run 10 "$RT" a.txt old.ppm; want_rc 2; want_err 'Too many levels'; clean_checks; }
def scene_missing; case_scene_missing() { newdir "$FUNCNAME"; run 10 "$RT" nosuch.txt old.ppm; want_rc 2; want_err 'No such file'; clean_checks; }
def scene_unreadable; case_scene_unreadable() { need_root; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; chmod 000 "$D/ok.txt"; chmod 777 "$D"
    run 10 "${AS_NOBODY[@]}" "$RT" ok.txt new.ppm; want_rc 2; want_err 'Permission denied'; clean_checks; }
def scene_latin1_name; case_scene_latin1_name() { newdir "$FUNCNAME"; run 10 "$RT" "$(printf 'no\xe9\x1b[1m.txt')" old.ppm; want_rc 2; want_clean_text; clean_checks; }

# --- textures and model materials ---------------------------------------------------
# A texture file must give its error at its name in the scene (nothing written) or a
# correct picture; never a hang (FIFO, /dev/zero) or an allocation of what a header
# claims.

SRC=$(cd "$(dirname "$0")/../.." && pwd)
# The good scene with its sphere textured by FILE.
tex_scene() { printf '%s\n' "${SCENE_OK/colour 0.9 0.2 0.15 /colour 0.9 0.2 0.15 texture \"$1\" }"; }
# A texture case that must be refused: the reason in stderr at the file name's place.
tex_refused() {  # REASON
    run 10 "$RT" s.txt new.ppm; want_rc 1; want_err "s.txt:1:[0-9]+: error: .*$1"; want_fast 3
    [ -e "$D/new.ppm" ] && problem "new.ppm written"; clean_checks; }
# A texture case that must render.
tex_renders() { run 20 "$RT" s.txt new.ppm; want_rc 0; want_ppm new.ppm 16 12; clean_checks; }
def tex_truncated; case_tex_truncated() { newdir "$FUNCNAME"; head -c 120 "$SRC/scenes/textures/uv-grid.png" > "$D/t.png"; tex_scene t.png > "$D/s.txt"; tex_refused 't.png: '; }
def tex_empty; case_tex_empty() { newdir "$FUNCNAME"; : > "$D/t.png"; tex_scene t.png > "$D/s.txt"; tex_refused 'empty'; }
def tex_folder; case_tex_folder() { newdir "$FUNCNAME"; mkdir "$D/t.png"; tex_scene t.png > "$D/s.txt"; tex_refused 'is a folder'; }
def tex_dev_zero; case_tex_dev_zero() { newdir "$FUNCNAME"; tex_scene /dev/zero > "$D/s.txt"; tex_refused 'not a regular file'; }
def tex_fifo; case_tex_fifo() { newdir "$FUNCNAME"; mkfifo "$D/t.png"; tex_scene t.png > "$D/s.txt"; tex_refused 'not a regular file'; }
def tex_not_image; case_tex_not_image() { newdir "$FUNCNAME"; printf '%s\n' "$SCENE_OK" > "$D/t.png"; tex_scene t.png > "$D/s.txt"; tex_refused 'not a PNG or JPEG'; }
def tex_missing; case_tex_missing() { newdir "$FUNCNAME"; tex_scene nosuch.png > "$D/s.txt"; tex_refused 'No such file'; }
def tex_huge_header; case_tex_huge_header() { newdir "$FUNCNAME"
    # A PNG header claiming 100000 x 100000 pixels (30 GB of texels), and nothing after it.
    printf '\x89PNG\r\n\x1a\n\x00\x00\x00\x0dIHDR\x00\x01\x86\xa0\x00\x01\x86\xa0\x08\x02\x00\x00\x00\x00\x00\x00\x00' > "$D/t.png"
    tex_scene t.png > "$D/s.txt"; tex_refused '100000 x 100000 pixels is too large'; }
def tex_huge_jpeg; case_tex_huge_jpeg() { newdir "$FUNCNAME"; need_no_sanitizer; [ -n "$SKIPPED" ] && return
    # A JPEG header claiming 65000 x 65000 under a 1 GB address space: refused by its size.
    printf '\xff\xd8\xff\xc0\x00\x11\x08\xfd\xe8\xfd\xe8\x03\x01\x22\x00\x02\x11\x01\x03\x11\x01\xff\xd9' > "$D/t.jpg"
    tex_scene t.jpg > "$D/s.txt"; run 10 bash -c "ulimit -v 1000000; exec '$RT' s.txt new.ppm"; want_rc 1; want_err '65000 x 65000'
    [ -e "$D/new.ppm" ] && problem "new.ppm written"; clean_checks; }
def tex_png16; case_tex_png16() { newdir "$FUNCNAME"; convert -size 8x8 xc:'rgb(200,100,50)' -depth 16 PNG48:"$D/t.png"; tex_scene t.png > "$D/s.txt"; tex_renders; }
def tex_grey; case_tex_grey() { newdir "$FUNCNAME"; convert -size 8x8 xc:'gray(40%)' -define png:color-type=0 -depth 8 "$D/t.png"; tex_scene t.png > "$D/s.txt"; tex_renders; }
def tex_grey_alpha; case_tex_grey_alpha() { newdir "$FUNCNAME"; convert -size 8x8 xc:'graya(40%,0.5)' -define png:color-type=4 -depth 8 "$D/t.png"; tex_scene t.png > "$D/s.txt"; tex_renders; }
def tex_alpha; case_tex_alpha() { newdir "$FUNCNAME"; convert -size 8x8 xc:'rgba(200,100,50,0.3)' PNG32:"$D/t.png"; tex_scene t.png > "$D/s.txt"; tex_renders; }
def tex_cmyk_jpeg; case_tex_cmyk_jpeg() { newdir "$FUNCNAME"; cp "$SRC/tests/textures/cmyk.jpg" "$D/t.jpg"; tex_scene t.jpg > "$D/s.txt"; tex_renders; }
def tex_progressive_jpeg; case_tex_progressive_jpeg() { newdir "$FUNCNAME"; cp "$SRC/tests/textures/progressive.jpg" "$D/t.jpg"; tex_scene t.jpg > "$D/s.txt"; tex_renders; }
# An OBJ naming an MTL file: its scene is the good one with this mesh added.
mtl_case() {  # MTL_TEXT (written to m.mtl unless empty)
    printf 'mtllib m.mtl\nv 4 -1 0\nv 4 1 0\nv 4 0 2\nusemtl a\nf 1 2 3\n' > "$D/m.obj"
    [ -n "$1" ] && printf '%s\n' "$1" > "$D/m.mtl"
    { echo 'thing { mesh { file "m.obj" } }'; printf '%s\n' "$SCENE_OK" | tail -n +2; } > "$D/s.txt"; }
def mtl_missing; case_mtl_missing() { newdir "$FUNCNAME"; mtl_case ''
    run 10 "$RT" s.txt new.ppm; want_rc 0; want_err 's.txt:1:21: warning: m.obj: material file m.mtl: No such file'; want_ppm new.ppm 16 12; clean_checks; }
def mtl_names_itself; case_mtl_names_itself() { newdir "$FUNCNAME"; mtl_case 'newmtl a
map_Kd m.mtl'; run 10 "$RT" s.txt new.ppm; want_rc 1; want_err 'map_Kd m.mtl names the material file itself'; [ -e "$D/new.ppm" ] && problem "new.ppm written"; clean_checks; }
def mtl_missing_texture; case_mtl_missing_texture() { newdir "$FUNCNAME"; mtl_case 'newmtl a
map_Kd gone.png'; run 10 "$RT" s.txt new.ppm; want_rc 1; want_err 'm.mtl:2: map_Kd gone.png: No such file'; [ -e "$D/new.ppm" ] && problem "new.ppm written"; clean_checks; }
def mtl_fifo_texture; case_mtl_fifo_texture() { newdir "$FUNCNAME"; mkfifo "$D/p.png"; mtl_case 'newmtl a
map_Kd p.png'; run 10 "$RT" s.txt new.ppm; want_rc 1; want_err 'not a regular file'; want_fast 3; clean_checks; }

# --- output edge cases -------------------------------------------------------------

def out_name_248; case_out_name_248() { newdir "$FUNCNAME"; local n; n=$(printf 'o%.0s' $(seq 244)).ppm; run 10 "$RT" ok.txt "$n"; want_rc 0; want_ppm "$n" 16 12; clean_checks; }
def out_name_255; case_out_name_255() { newdir "$FUNCNAME"; local n; n=$(printf 'o%.0s' $(seq 251)).ppm; run 10 "$RT" ok.txt "$n"; want_rc 0; want_ppm "$n" 16 12; clean_checks; }
def out_name_255_replace; case_out_name_255_replace() { newdir "$FUNCNAME"; local n; n=$(printf 'o%.0s' $(seq 251)).ppm; echo old > "$D/$n"; run 10 "$RT" ok.txt "$n"; want_rc 0; want_ppm "$n" 16 12; clean_checks; }
def out_name_256; case_out_name_256() { newdir "$FUNCNAME"; local n; n=$(printf 'o%.0s' $(seq 252)).ppm; empty_scene 4000 4000 > "$D/s.txt"
    run 10 "$RT" s.txt "$n"; want_rc 2; want_err 'File name too long'; want_fast 1; clean_checks; }
def out_path_max; case_out_path_max() { newdir "$FUNCNAME"; local p=$D i; for i in $(seq 22); do p=$p/$(printf 'd%.0s' $(seq 200)); done; mkdir -p "$p" 2> /dev/null
    run 10 "$RT" ok.txt "$p/x.ppm"; want_rc 2; want_err 'File name too long'; clean_checks; rm -rf "$D"/ddd* 2> /dev/null; }
def out_dangling_link; case_out_dangling_link() { newdir "$FUNCNAME"; ln -s target.ppm "$D/link.ppm"; run 10 "$RT" ok.txt link.ppm; want_rc 0; want_ppm target.ppm 16 12
    [ -L "$D/link.ppm" ] || problem "the link was replaced"; clean_checks; }
def out_live_link; case_out_live_link() { newdir "$FUNCNAME"; echo old > "$D/target.ppm"; ln -s target.ppm "$D/link.ppm"; run 10 "$RT" ok.txt link.ppm; want_rc 0; want_ppm target.ppm 16 12
    [ -L "$D/link.ppm" ] || problem "the link was replaced"; clean_checks; }
def out_link_loop; case_out_link_loop() { newdir "$FUNCNAME"; ln -s a.ppm "$D/b.ppm"; ln -s b.ppm "$D/a.ppm"; empty_scene 4000 4000 > "$D/s.txt"
    run 10 "$RT" s.txt a.ppm; want_rc 2; want_err 'Too many levels of symbolic links'; want_fast 1; [ -L "$D/a.ppm" ] || problem "the link was replaced"; clean_checks; }
def out_self_link; case_out_self_link() { newdir "$FUNCNAME"; ln -s self.ppm "$D/self.ppm"; run 10 "$RT" ok.txt self.ppm; want_rc 2; want_err 'Too many levels'; clean_checks; }
def out_link_to_scene; case_out_link_to_scene() { newdir "$FUNCNAME"; cp "$D/ok.txt" "$D/s.ppm"; ln -s s.ppm "$D/l.ppm"; run 10 "$RT" s.ppm l.ppm; want_rc 2; want_err 'scene file itself'; clean_checks; }
def out_is_folder; case_out_is_folder() { newdir "$FUNCNAME"; mkdir "$D/d.ppm"; run 10 "$RT" ok.txt d.ppm; want_rc 2; want_err 'directory'; clean_checks; }
def out_trailing_slash; case_out_trailing_slash() { newdir "$FUNCNAME"; run 10 "$RT" ok.txt sub/; want_rc 2; clean_checks; }
def out_missing_folder; case_out_missing_folder() { newdir "$FUNCNAME"; empty_scene 4000 4000 > "$D/s.txt"; run 10 "$RT" s.txt no/such/o.ppm; want_rc 2; want_err 'does not exist'; want_fast 1; clean_checks; }
def out_folder_is_file; case_out_folder_is_file() { newdir "$FUNCNAME"; run 10 "$RT" ok.txt old.ppm/o.ppm; want_rc 2; want_err 'Not a directory|not a folder'; clean_checks; }
def out_is_scene; case_out_is_scene() { newdir "$FUNCNAME"; cp "$D/ok.txt" "$D/s.ppm"; run 10 "$RT" s.ppm s.ppm; want_rc 2; want_err 'scene file itself'; cmp -s "$D/s.ppm" "$D/ok.txt" || problem "scene changed"; clean_checks; }
def out_bad_extension; case_out_bad_extension() { newdir "$FUNCNAME"; run 10 "$RT" ok.txt o.jpg; want_rc 2; want_err '.pfm or .exr'; clean_checks; }
def out_dev_null; case_out_dev_null() { newdir "$FUNCNAME"; run 10 "$RT" ok.txt /dev/null; want_rc 2; want_err '.pfm or .exr'; clean_checks; }
def out_dev_full_link; case_out_dev_full_link() { newdir "$FUNCNAME"; ln -s /dev/full "$D/full.ppm"; run 10 "$RT" ok.txt full.ppm; want_rc 2; want_err 'No space left'; [ -c /dev/full ] || problem "/dev/full replaced"; clean_checks; }
def out_dev_null_link; case_out_dev_null_link() { newdir "$FUNCNAME"; ln -s /dev/null "$D/null.ppm"; run 10 "$RT" ok.txt null.ppm; want_rc 0; [ -c /dev/null ] || problem "/dev/null replaced"; clean_checks; }
def out_fifo_sigterm; case_out_fifo_sigterm() { newdir "$FUNCNAME"; mkfifo "$D/o.ppm"; start "$RT" --quiet ok.txt o.ppm; signal_after 1 5 TERM; want_rc 143; want_fast 1; [ -p "$D/o.ppm" ] || problem "FIFO replaced"; clean_checks; }
def out_fifo_read; case_out_fifo_read() { newdir "$FUNCNAME"; mkfifo "$D/o.ppm"; (head -c 100000 "$D/o.ppm" > "$D/got" &); run 10 "$RT" --quiet ok.txt o.ppm; want_rc 0
    [ "$(head -c 2 "$D/got")" = P6 ] || problem "no PPM through the FIFO"; clean_checks; }
def out_spaces_newline; case_out_spaces_newline() { newdir "$FUNCNAME"; local n=$'a b\nc.ppm'; run 10 "$RT" ok.txt "$n"; want_rc 0; want_ppm "$n" 16 12; clean_checks; }
def out_latin1_name; case_out_latin1_name() { newdir "$FUNCNAME"; local n; n=$(printf 'caf\xe9.ppm'); run 10 "$RT" ok.txt "$n"; want_rc 0; want_ppm "$n" 16 12; clean_checks; }
def out_png; case_out_png() { newdir "$FUNCNAME"; run 10 "$RT" ok.txt o.PNG; want_rc 0; [ "$(head -c 4 "$D/o.PNG" | tail -c 3)" = PNG ] || problem "not a PNG"; clean_checks; }
def out_readonly_file_nobody; case_out_readonly_file_nobody() { need_root; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; chmod 777 "$D"; chown 65534 "$D/old.ppm"; chmod 444 "$D/old.ppm"
    empty_scene 4000 4000 > "$D/s.txt"; run 10 "${AS_NOBODY[@]}" "$RT" s.txt old.ppm; want_rc 2; want_err 'read-only.*Permission denied'; want_fast 1; clean_checks; }
def out_readonly_folder_nobody; case_out_readonly_folder_nobody() { need_root; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; mkdir "$D/ro"; echo precious > "$D/ro/o.ppm"; chmod 666 "$D/ro/o.ppm"; chmod 555 "$D/ro"
    empty_scene 4000 4000 > "$D/s.txt"; run 10 "${AS_NOBODY[@]}" "$RT" s.txt ro/o.ppm; want_rc 2; want_err 'not writable'; want_fast 1
    [ "$(cat "$D/ro/o.ppm")" = precious ] || problem "ro/o.ppm changed"; clean_checks; }
def out_sticky_other_user; case_out_sticky_other_user() { need_root; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; mkdir "$D/t"; chmod 1777 "$D/t"; echo precious > "$D/t/o.ppm"; chmod 666 "$D/t/o.ppm"
    empty_scene 4000 4000 > "$D/s.txt"; run 10 "${AS_NOBODY[@]}" "$RT" s.txt t/o.ppm; want_rc 2; want_err 'sticky.*Operation not permitted'; want_fast 1
    [ "$(cat "$D/t/o.ppm")" = precious ] || problem "t/o.ppm changed"; [ -z "$(ls -A "$D/t" | grep -v '^o.ppm$')" ] || problem "left: $(ls -A "$D/t")"; clean_checks; }
def out_root_replaces_users_file; case_out_root_replaces_users_file() { need_root; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; chown 65534:65534 "$D/old.ppm"; chmod 640 "$D/old.ppm"
    run 10 "$RT" ok.txt old.ppm; want_rc 0; want_ppm old.ppm 16 12
    [ "$(stat -c '%u:%g %a' "$D/old.ppm")" = "65534:65534 640" ] || problem "owner/mode now $(stat -c '%u:%g %a' "$D/old.ppm")"; clean_checks replaced; }
def out_full_disk; case_out_full_disk() { need_root; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; mkdir "$D/small"
    # A 64 KiB tmpfs in a private mount namespace; a 1 MB picture cannot fit.
    run 20 unshare -m bash -c "mount -t tmpfs -o size=64k tmpfs small && echo precious > small/o.ppm && '$RT' --quiet --width 600 --height 600 ok.txt small/o.ppm; rc=\$?; [ \"\$(cat small/o.ppm)\" = precious ] || rc=99; ls -A small | grep -qv '^o.ppm$' && rc=98; exit \$rc"
    if grep -q 'mount:' <<< "$ERR"; then SKIPPED="(cannot mount a tmpfs here)"; return; fi
    want_rc 2; want_err 'No space left'; clean_checks; }

# --- signals at random moments -------------------------------------------------------

random_delay() { awk -v s="$RANDOM" 'BEGIN { srand(s); printf "%.2f", 0.05 + rand() * 1.2 }'; }
signal_case() {  # SIG: a 600x600 render with a write, signalled at a random moment
    local sig=$1 expect=$2 d
    newdir "sig_$sig"; mirror_box_scene > "$D/s.txt"; d=$(random_delay)
    start "$RT" --quiet --width 300 --height 300 --max-depth 40 s.txt old.ppm; signal_after "$d" 5 "$sig"
    if [ "$RC" = 0 ]; then want_ppm old.ppm 300 300; clean_checks replaced; else want_rc "$expect"; want_fast 1; clean_checks; fi
    SECS="$SECS (after $d s)"; }
for k in 1 2 3 4; do
    def "random_sigterm_$k"; eval "case_random_sigterm_$k() { signal_case TERM 143; }"
    def "random_sigint_$k"; eval "case_random_sigint_$k() { signal_case INT 130; }"
done
def random_sighup; case_random_sighup() { signal_case HUP 129; }
write_signal_case() {  # signals once the temporary file is being filled
    newdir "$1"; shift; empty_scene 3000 3000 > "$D/s.txt"
    start "$RT" --quiet s.txt old.ppm
    wait_for_temp_file
    signal_after 0 5 "$@"
    want_fast 1
    # The old file, or (had the write ended and the rename happened before the signal
    # came: the picture is 27 MB, written in tens of ms) the complete new one.
    if [ "$(cat "$D/old.ppm" 2> /dev/null | head -c 8)" != precious ]; then
        [ "$RC" = 0 ] || { want_rc 143; want_err interrupted; }
        want_ppm old.ppm 3000 3000; clean_checks replaced
    else
        if [ "$RC" = 0 ]; then problem "exit 0 after a signal, the old file kept"; fi
        want_rc 143; want_err interrupted; clean_checks
    fi; }
def sigterm_during_write; case_sigterm_during_write() { write_signal_case "$FUNCNAME" TERM; }
def two_sigterms_during_write; case_two_sigterms_during_write() { write_signal_case "$FUNCNAME" TERM TERM; }
def three_signals_during_write; case_three_signals_during_write() { write_signal_case "$FUNCNAME" TERM INT TERM; }
def sigterm_during_parse; case_sigterm_during_parse() { newdir "$FUNCNAME"; spheres_scene 400000 0 > "$D/s.txt"
    start "$RT" --quiet --width 4000 --height 3000 s.txt old.ppm; signal_after 0.2 5 TERM; want_rc 143; want_fast 1; clean_checks; }
def sigint_twice; case_sigint_twice() { newdir "$FUNCNAME"; endless_box_scene > "$D/s.txt"
    start "$RT" --quiet --max-depth 1000 s.txt old.ppm; signal_after 0.5 5 INT INT; want_rc 130; want_fast 1; clean_checks; }
def sigterm_at_prompt; case_sigterm_at_prompt() { newdir "$FUNCNAME"
    (cd "$D" && exec "$RT" ok.txt < <(sleep 5) > "$WORK/.out" 2> "$WORK/.err") & PID=$!
    signal_after 0.3 5 TERM; [ "$RC" = 143 ] || problem "exit $RC"; want_fast 1; clean_checks; }
def sigkill_during_write; case_sigkill_during_write() { newdir "$FUNCNAME"; empty_scene 3000 3000 > "$D/s.txt"
    # SIGKILL cannot be caught: the old file stays; only a temporary file may remain.
    start "$RT" --quiet s.txt old.ppm
    wait_for_temp_file
    signal_after 0 5 KILL; [ "$(cat "$D/old.ppm" | head -c 8)" = precious ] || want_ppm old.ppm 3000 3000; } 2> /dev/null

# --- option values ---------------------------------------------------------------------

opt_case() {  # NAME EXPECTED_RC STDERR_REGEX ARGS...
    local name=$1 rc=$2 re=$3; shift 3
    def "opt_$name"; eval "case_opt_$name() { newdir opt_$name; run 10 \"\$RT\" $(printf '%q ' "$@"); want_rc $rc; [ -n $(printf '%q' "$re") ] && want_err $(printf '%q' "$re"); want_clean_text; clean_checks; }"
}
opt_case hex_float 2 'decimal' --time-limit 0x1p3 ok.txt old.ppm
opt_case time_inf 2 'decimal' --time-limit inf ok.txt old.ppm
opt_case time_nan 2 'decimal' --time-limit nan ok.txt old.ppm
opt_case time_zero 2 'more than 0' --time-limit 0 ok.txt old.ppm
opt_case time_negative 2 'more than 0' --time-limit -1 ok.txt old.ppm
opt_case time_huge 2 'at most' --time-limit 1e30 ok.txt old.ppm
opt_case width_space 2 'decimal' --width ' 12' ok.txt old.ppm
opt_case width_trailing_space 2 'decimal' --width '12 ' ok.txt old.ppm
opt_case width_hex 2 'decimal' --width 0x10 ok.txt old.ppm
opt_case width_exp 2 'decimal' --width 1e2 ok.txt old.ppm
opt_case width_empty 2 'decimal' --width= ok.txt old.ppm
opt_case width_zero 2 'between 1 and' --width 0 ok.txt old.ppm
opt_case width_overflow 2 'between 1 and' --width 99999999999999999999999 ok.txt old.ppm
opt_case samples_65537 2 'between 1 and 65536' --samples 65537 ok.txt old.ppm
opt_case threads_257 2 'between 1 and 256' --threads 257 ok.txt old.ppm
opt_case depth_1001 2 'between 1 and 1000' --max-depth 1001 ok.txt old.ppm
opt_case missing_value 2 'needs' ok.txt old.ppm --width
opt_case unknown 2 'unknown option' --frobnicate ok.txt old.ppm
opt_case latin1_value 2 'decimal' --width "$(printf '1\xe9')" ok.txt old.ppm
opt_case too_many 2 'too many' ok.txt a.ppm b.ppm
opt_case flag_with_value 2 'takes no value' --quiet=1 ok.txt old.ppm
opt_case check_extra 2 'only the scene' --check ok.txt old.ppm
opt_case print_scene_extra 2 'exactly one' --print-scene ok.txt old.ppm
def print_scene_full; case_print_scene_full() { newdir "$FUNCNAME"; (cd "$D" && "$RT" --print-scene ok.txt > /dev/full 2> "$WORK/.err"); RC=$?; ERR=$(cat "$WORK/.err")
    want_rc 2; want_err 'standard output: No space left'; clean_checks; }
def print_scene_closed; case_print_scene_closed() { newdir "$FUNCNAME"; (cd "$D" && "$RT" --print-scene ok.txt >&- 2> "$WORK/.err"); RC=$?; ERR=$(cat "$WORK/.err")
    want_rc 2; want_err 'standard output'; clean_checks; }
def options_plus_sign; case_options_plus_sign() { newdir "$FUNCNAME"; run 10 "$RT" --width +8 --height 6 --time-limit .5 ok.txt new.ppm; want_rc 0; want_ppm new.ppm 8 6; clean_checks; }
def no_answer_at_prompt; case_no_answer_at_prompt() { newdir "$FUNCNAME"; run 10 "$RT"; want_rc 2; want_err 'no scene file'; clean_checks; }

# --- the viewer, headless ----------------------------------------------------------------

def view_screenshot_is_scene; case_view_screenshot_is_scene() { need_viewer; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; cp "$D/ok.txt" "$D/s.png"
    run 20 "$VIEW" s.png --screenshot s.png; want_rc 2; want_err 'scene file itself'; cmp -s "$D/s.png" "$D/ok.txt" || problem "scene overwritten"; clean_checks; }
def view_screenshot_link_to_scene; case_view_screenshot_link_to_scene() { need_viewer; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; ln -s ok.txt "$D/l.png"
    run 20 "$VIEW" ok.txt --screenshot l.png; want_rc 2; want_err 'scene file itself'; cmp -s "$D/ok.txt" <(printf '%s\n' "$SCENE_OK") || problem "scene overwritten"; clean_checks; }
def view_view_scene_is_scene; case_view_view_scene_is_scene() { need_viewer; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"
    run 20 "$VIEW" ok.txt --screenshot shot.png --view-scene ./ok.txt; want_rc 2; want_err 'scene file itself'; cmp -s "$D/ok.txt" <(printf '%s\n' "$SCENE_OK") || problem "scene rewritten"; clean_checks; }
def view_size_16384_memory_limit; case_view_size_16384_memory_limit() { need_viewer; need_no_sanitizer; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"
    run 30 bash -c "ulimit -v 8000000; exec '$VIEW' ok.txt --screenshot shot.png --size 16384x16384"; want_rc 2; want_err 'out of memory'; want_fast 5; [ -e "$D/shot.png" ] && problem "shot.png written"; clean_checks; }
def view_size_too_small; case_view_size_too_small() { need_viewer; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; run 10 "$VIEW" --screenshot s.png --size 63x63; want_rc 2; want_err 'size'; clean_checks; }
def view_size_garbage; case_view_size_garbage() { need_viewer; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; run 10 "$VIEW" --screenshot s.png --size ' 640x480'; want_rc 2; want_err 'size'; clean_checks; }
def view_time_hex; case_view_time_hex() { need_viewer; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; run 10 "$VIEW" --screenshot s.png --time-limit 0x1p3; want_rc 2; want_err 'number'; clean_checks; }
def view_orbit_nan; case_view_orbit_nan() { need_viewer; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; run 10 "$VIEW" --screenshot s.png --orbit nan; want_rc 2; clean_checks; }
def view_warnings_capped; case_view_warnings_capped() { need_viewer; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"
    { echo 'thing {'; for _ in $(seq 2000); do echo 'sphere { position 5 0 1 radius 1 material { reflection 0 refraction 0 scattering 0 } }'; done; echo '}'; printf '%s\n' "$SCENE_OK"; } > "$D/s.txt"
    run 60 "$VIEW" s.txt --screenshot shot.png --size 320x240 --samples 1; want_rc 0
    local n; n=$(grep -c 'warning' <<< "$ERR"); [ "$n" -le 21 ] || problem "$n warnings printed (cap 20)"; want_err 'more warnings not shown'; clean_checks; }
def view_latin1_scene; case_view_latin1_scene() { need_viewer; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; printf 'thing { sph\xe8re\x1b[2J { } }\nend\n' > "$D/s.txt"
    run 20 "$VIEW" s.txt --screenshot shot.png --size 320x240; want_rc 1; want_clean_text; clean_checks; }
def view_missing_scene; case_view_missing_scene() { need_viewer; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; run 20 "$VIEW" nosuch.txt --screenshot shot.png; want_rc 2; want_err 'No such file'; clean_checks; }
def view_screenshot_missing_folder; case_view_screenshot_missing_folder() { need_viewer; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"
    run 30 "$VIEW" ok.txt --screenshot no/shot.png --size 320x240 --samples 1; want_rc 2; want_err 'No such file'; want_fast 0.5; clean_checks; }
def view_screenshot_bad_extension; case_view_screenshot_bad_extension() { need_viewer; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"
    run 30 "$VIEW" ok.txt --screenshot shot.jpg --size 320x240; want_rc 2; want_err '.png or .ppm'; want_fast 0.5; clean_checks; }
def view_sigterm; case_view_sigterm() { need_viewer; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; endless_box_scene > "$D/s.txt"
    start "$VIEW" s.txt --screenshot old.ppm --size 320x240 --samples 65536 --aa-threshold off; signal_after 1.5 5 TERM; want_rc 143; want_fast 1; clean_checks; }
def view_fifo_scene_sigint; case_view_fifo_scene_sigint() { need_viewer; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; mkfifo "$D/s.txt"
    start "$VIEW" s.txt --screenshot old.ppm --size 320x240; signal_after 0.5 5 INT; want_rc 130; want_fast 1; clean_checks; }
def view_good; case_view_good() { need_viewer; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; run 60 "$VIEW" ok.txt --screenshot shot.ppm --size 320x240 --samples 1; want_rc 0; want_ppm shot.ppm 320 240; clean_checks; }

# --- raytracer-mpi (where it applies) ------------------------------------------------

RT_MPI=$BIN/raytracer-mpi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export HWLOC_COMPONENTS=-gl  # (hwloc would open any X display there is: see tests/mpi/mpi_test.sh)
need_mpi() { { [ -x "$RT_MPI" ] && command -v mpirun > /dev/null; } || SKIPPED="(no raytracer-mpi or mpirun)"; }
def mpi_sigterm_render; case_mpi_sigterm_render() { need_mpi; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; endless_box_scene > "$D/s.txt"
    # As a batch system cancels a job: SIGTERM to mpirun, which passes it on to the ranks.
    start mpirun --oversubscribe -np 2 "$RT_MPI" --quiet --max-depth 1000 s.txt old.ppm; signal_after 2 10 TERM
    [ "$RC" != 0 ] || problem "exit 0"; want_fast 3; clean_checks; }
def mpi_sigterm_write; case_mpi_sigterm_write() { need_mpi; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; empty_scene 3000 3000 > "$D/s.txt"
    start mpirun --oversubscribe -np 1 "$RT_MPI" --quiet s.txt old.ppm
    wait_for_temp_file
    signal_after 0 10 TERM; [ "$RC" != 0 ] || problem "exit 0"; want_fast 3
    if [ "$(head -c 8 "$D/old.ppm")" != precious ]; then want_ppm old.ppm 3000 3000; clean_checks replaced; else clean_checks; fi; }
def mpi_fifo_scene; case_mpi_fifo_scene() { need_mpi; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; mkfifo "$D/s.txt"
    start mpirun --oversubscribe -np 2 "$RT_MPI" s.txt old.ppm; signal_after 2 10 TERM; [ "$RC" != 0 ] || problem "exit 0"; want_fast 3; clean_checks; }
def mpi_long_out_name; case_mpi_long_out_name() { need_mpi; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"; local n; n=$(printf 'o%.0s' $(seq 251)).ppm
    run 60 mpirun --oversubscribe -np 2 "$RT_MPI" --quiet ok.txt "$n"; want_rc 0; want_ppm "$n" 16 12; clean_checks; }
def mpi_options; case_mpi_options() { need_mpi; [ -n "$SKIPPED" ] && return; newdir "$FUNCNAME"
    run 60 mpirun --oversubscribe -np 2 "$RT_MPI" --tile ' 16' ok.txt old.ppm; want_rc 2; want_err 'decimal'; clean_checks; }

# --- the realism keys (New:): each bad value is an error at its place, nothing written.
realism_case() {  # NAME SED-EXPRESSION ERROR-REGEX
    newdir "$1"; printf '%s\n' "$SCENE_OK" | sed "$2" > "$D/s.txt"
    run 10 "$RT" s.txt old.ppm; want_rc 1; want_err "$3"; clean_checks; }
def light_radius_negative; case_light_radius_negative() { realism_case "$FUNCNAME" 's/size 0.2/size 0.2 radius -1/' 's.txt:3:[0-9]+: error: light radius must not be negative'; }
def aperture_negative; case_aperture_negative() { realism_case "$FUNCNAME" 's/angle_y 46.8/angle_y 46.8 aperture -0.1/' 's.txt:4:[0-9]+: error: aperture must not be negative'; }
def focus_zero; case_focus_zero() { realism_case "$FUNCNAME" 's/angle_y 46.8/angle_y 46.8 focus_distance 0/' 's.txt:4:[0-9]+: error: focus_distance must be greater than 0'; }
def specular_negative; case_specular_negative() { realism_case "$FUNCNAME" 's/colour 0.9 0.2 0.15/colour 0.9 0.2 0.15 specular -0.5/' 's.txt:1:[0-9]+: error: specular must be 0..1'; }
def shininess_huge; case_shininess_huge() { realism_case "$FUNCNAME" 's/colour 0.9 0.2 0.15/colour 0.9 0.2 0.15 specular 1 shininess 1e9/' 's.txt:1:[0-9]+: error: shininess must be 1..10000'; }
def texture_scale_negative; case_texture_scale_negative() { realism_case "$FUNCNAME" 's/colour 0.6 0.6 0.6/colour 0.6 0.6 0.6 texture_scale -2/' 's.txt:2:[0-9]+: error: texture_scale must be greater than 0'; }
def light_radius_nan; case_light_radius_nan() { realism_case "$FUNCNAME" 's/size 0.2/size 0.2 radius nan/' 's.txt:3:[0-9]+: error'; }
def huge_radius_aperture; case_huge_radius_aperture() { newdir "$FUNCNAME"
    # Legal but extreme: a light around everything, a lens wider than the scene: renders.
    printf '%s\n' "$SCENE_OK" | sed 's/size 0.2/size 0.2 radius 1e12/; s/angle_y 46.8/angle_y 46.8 aperture 1e9 background 1e15 0 0/' > "$D/s.txt"
    run 20 "$RT" --samples 4 s.txt out.ppm; want_rc 0; want_ppm out.ppm 16 12; }

# --- run -----------------------------------------------------------------------------

t_all=$(date +%s)
# ONLY=REGEX runs the cases whose names match (ONLY='radius|aperture').
for c in "${ORDER[@]}"; do if [ -z "${ONLY:-}" ] || [[ "$c" =~ $ONLY ]]; then run_case "$c"; fi; done
echo
echo "hostile: $pass passed, $fail failed, $skip skipped ($(( $(date +%s) - t_all )) s; work folder $WORK)"
if [ "$fail" -gt 0 ]; then
    printf 'failed: %s\n' "${failed[*]}"
    exit 1
fi
[ -z "${2:-}" ] && rm -rf "$WORK"
exit 0
