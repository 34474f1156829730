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

# configure NAME ARGS...: exit status into $status, output into $work/NAME.log
configure() {
    name=$1; shift
    status=0
    "$CMAKE" -G "Unix Makefiles" -S "$SRC" -B "$work/$name" -DRAYTRACER_TESTS=ON -DRAYTRACER_BENCH=OFF "$@" > "$work/$name.log" 2>&1 || status=$?
}

# Needed by the core: the configure stops and says what to install.
configure stb -DCMAKE_DISABLE_FIND_PACKAGE_stb=ON
[ "$status" -ne 0 ] || fail "configure without stb succeeded"
grep -q "apt-get install libstb-dev" "$work/stb.log" || { cat "$work/stb.log"; fail "no libstb-dev in the message"; }

# Optional: the viewer is left out with a warning, the rest configures.
configure imgui -DCMAKE_DISABLE_FIND_PACKAGE_imgui=ON
[ "$status" -eq 0 ] || { cat "$work/imgui.log"; fail "configure without ImGui failed"; }
grep -q "apt-get install libimgui-dev" "$work/imgui.log" || { cat "$work/imgui.log"; fail "no libimgui-dev in the message"; }
grep -q "raytracer-view" "$work/imgui.log" || fail "the message does not say what is left out"
if grep -q "^raytracer-view:" "$work/imgui/Makefile" 2>/dev/null; then fail "raytracer-view is still a target"; fi
grep -q "^raytracer:" "$work/imgui/Makefile" || fail "raytracer is no longer a target"
echo "third_party messages: ok"
