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
# its exit status into $status. Output goes to $work/NAME.log. (The four configures
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
configure imgui -DCMAKE_DISABLE_FIND_PACKAGE_imgui=ON
configure x11 -DCMAKE_DISABLE_FIND_PACKAGE_X11=ON
configure embree -DRAYTRACER_BENCH=ON -DCMAKE_DISABLE_FIND_PACKAGE_embree=ON
wait

# Needed by the core: the configure stops and says what to install.
status stb
[ "$status" -ne 0 ] || fail "configure without stb succeeded"
grep -q "apt-get install libstb-dev" "$work/stb.log" || { cat "$work/stb.log"; fail "no libstb-dev in the message"; }

# Optional: the viewer is left out with a warning, the rest configures.
status imgui
[ "$status" -eq 0 ] || { cat "$work/imgui.log"; fail "configure without ImGui failed"; }
grep -q "apt-get install libimgui-dev" "$work/imgui.log" || { cat "$work/imgui.log"; fail "no libimgui-dev in the message"; }
grep -q "raytracer-view" "$work/imgui.log" || fail "the message does not say what is left out"
if grep -q "^raytracer-view:" "$work/imgui/Makefile" 2>/dev/null; then fail "raytracer-view is still a target"; fi
grep -q "^raytracer:" "$work/imgui/Makefile" || fail "raytracer is no longer a target"

# Optional for the tests: without Xlib the window tests are not registered, the rest is.
status x11
[ "$status" -eq 0 ] || { cat "$work/x11.log"; fail "configure without X11 failed"; }
grep -q "apt-get install libx11-dev libxext-dev" "$work/x11.log" || { cat "$work/x11.log"; fail "no libx11-dev in the message"; }
grep -q "Xvfb window tests are not registered" "$work/x11.log" || fail "the X11 message does not say what is left out"
if grep -q "^rtview-xframes:" "$work/x11/Makefile"; then fail "rtview-xframes is still a target"; fi
if grep -q "viewer_xvfb" "$work/x11/tests/viewer/CTestTestfile.cmake" 2>/dev/null; then fail "an Xvfb test is still registered"; fi
grep -q "^raytracer:" "$work/x11/Makefile" || fail "raytracer is no longer a target (X11 hidden)"

# Optional for bench/: without Embree its reference is left out, the benchmarks stay.
status embree
[ "$status" -eq 0 ] || { cat "$work/embree.log"; fail "configure without Embree failed"; }
grep -q "apt-get install libembree-dev" "$work/embree.log" || { cat "$work/embree.log"; fail "no libembree-dev in the message"; }
grep -q "embree_ref is not built" "$work/embree.log" || fail "the Embree message does not say what is left out"
if grep -q "^embree_ref:" "$work/embree/Makefile"; then fail "embree_ref is still a target"; fi
grep -q "^renderer_bench:" "$work/embree/Makefile" || fail "renderer_bench is no longer a target (Embree hidden)"
echo "third_party messages: ok"
