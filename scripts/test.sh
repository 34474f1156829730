#!/usr/bin/env bash
# Configures, builds and runs every test (ctest) in build/ (or $BUILD_DIR), JOBS
# (default: the number of cores) at a time.
# Extra CMake options: $CMAKE_ARGS. Extra ctest arguments: this script's arguments,
# e.g. ./scripts/test.sh -R core
set -euo pipefail
cd "$(dirname "$0")/.."

BUILD_DIR=${BUILD_DIR:-build}
JOBS=${JOBS:-$(nproc)}
# shellcheck disable=SC2086  # CMAKE_ARGS is a list of words
cmake -S . -B "$BUILD_DIR" -DRAYTRACER_TESTS=ON ${CMAKE_ARGS:-}
cmake --build "$BUILD_DIR" -j"$JOBS"
ctest --test-dir "$BUILD_DIR" --output-on-failure -j"$JOBS" "$@"
