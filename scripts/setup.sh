#!/usr/bin/env bash
# Installs the build dependencies on Debian 12 (apt-get, only what is missing) and
# builds everything into build/ (or $BUILD_DIR). Extra CMake options: $CMAKE_ARGS,
# e.g. CMAKE_ARGS=-DRAYTRACER_VIEWER=OFF for a machine without GL libraries.
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(build-essential cmake pkg-config libglfw3-dev libimgui-dev libosmesa6-dev libglm-dev
          doctest-dev libstb-dev xvfb xauth xdotool imagemagick)

missing=()
for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
    # Root on a fresh machine; otherwise sudo, if there is one.
    SUDO=
    [ "$(id -u)" = 0 ] || SUDO=sudo
    export DEBIAN_FRONTEND=noninteractive
    $SUDO apt-get update
    $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
fi

BUILD_DIR=${BUILD_DIR:-build}
# shellcheck disable=SC2086  # CMAKE_ARGS is a list of words
cmake -S . -B "$BUILD_DIR" ${CMAKE_ARGS:-}
cmake --build "$BUILD_DIR" -j"$(nproc)"
echo "Built: $BUILD_DIR/bin/"
