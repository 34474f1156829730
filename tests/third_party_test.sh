#!/usr/bin/env bash
# third_party/ names the Debian package of a library that is missing: configures the
# project in scratch folders with one library hidden (-DCMAKE_DISABLE_FIND_PACKAGE_<name>)
# and checks the outcome and the message. Configure only; nothing is built.
# Usage: third_party_test.sh SOURCE_DIR CMAKE
set -euo pipefail
SRC=$1
CMAKE=${2:-cmake}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# configure NAME ARGS...: configures in the background; after `wait`, status NAME puts
# its exit status into $status. Output goes to $work/NAME.log. (The five configures
# run at once: each is mostly waiting on compiler checks.)
configure() {
    name=$1; shift
    ( rc=0
      "$CMAKE" -G "Unix Makefiles" -S "$SRC" -B "$work/$name" -DRAYTRACER_TESTS=ON -DRAYTRACER_BENCH=OFF "$@" \
          > "$work/$name.log" 2>&1 || rc=$?
      echo "$rc" > "$work/$name.status" ) &
}
status() { status=$(cat "$work/$1.status"); }

configure stb -DCMAKE_DISABLE_FIND_PACKAGE_stb=ON
configure zlib -DCMAKE_DISABLE_FIND_PACKAGE_ZLIB=ON
configure imgui -DCMAKE_DISABLE_FIND_PACKAGE_imgui=ON
configure x11 -DCMAKE_DISABLE_FIND_PACKAGE_X11=ON
configure embree -DRAYTRACER_BENCH=ON -DCMAKE_DISABLE_FIND_PACKAGE_embree=ON
wait

# Needed by the core: the configure stops and says what to install.
status stb
[ "$status" -ne 0 ] || fail "configure without stb succeeded"
grep -q "apt-get install libstb-dev" "$work/stb.log" || { cat "$work/stb.log"; fail "no libstb-dev in the message"; }
status zlib
[ "$status" -ne 0 ] || fail "configure without zlib succeeded"
# (CMake wraps the message: compare it with its lines joined.)
tr -s ' \n' ' ' < "$work/zlib.log" | grep -q "apt-get install zlib1g-dev" ||
    { cat "$work/zlib.log"; fail "no zlib1g-dev in the message"; }

# optional NAME PACKAGES LEFT_OUT GONE KEPT: without library NAME the configure succeeds,
# the message names the Debian PACKAGES and says LEFT_OUT, target GONE is not made
# and target KEPT still is.
optional() {
    status "$1"
    local log="$work/$1.log" make="$work/$1/Makefile"
    [ "$status" -eq 0 ] || { cat "$log"; fail "configure without $1 failed"; }
    grep -q "apt-get install $2" "$log" || { cat "$log"; fail "no '$2' in the $1 message"; }
    grep -q "$3" "$log" || { cat "$log"; fail "the $1 message does not say '$3'"; }
    if grep -q "^$4:" "$make"; then fail "$4 is still a target without $1"; fi
    grep -q "^$5:" "$make" || fail "$5 is no longer a target without $1"
}

# The viewer is left out with a warning, the rest configures.
optional imgui libimgui-dev "raytracer-view is not built" raytracer-view raytracer
# Without Xlib the window tests are not registered; the rest is.
optional x11 "libx11-dev libxext-dev" "Xvfb window tests are not registered" rtview-xframes raytracer
if grep -q "viewer_xvfb" "$work/x11/tests/viewer/CTestTestfile.cmake"; then fail "an Xvfb test is still registered"; fi
# Without Embree bench/ leaves its reference out; the other benchmarks stay.
optional embree libembree-dev "embree_ref is not built" embree_ref renderer_bench
echo "third_party messages: ok"
