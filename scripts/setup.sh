#!/usr/bin/env bash
# Installs the build dependencies on Debian 12 (apt-get, only what is missing) and
# builds everything into build/ (or $BUILD_DIR). This is the one list of packages:
# CI (.ci/run) installs through it too, so the fresh-machine path is the tested one.
#   ./scripts/setup.sh [--with-mpi] [--with-fuzz] [--with-models] [--deps-only]
#     --with-mpi    also Open MPI, and build raytracer-mpi (-DRAYTRACER_MPI=ON)
#     --with-fuzz   also clang and its sanitizer/libFuzzer runtimes (scripts/fuzz.sh)
#     --with-models also Debian's assimp test models (OBJ and PLY files, some broken
#                   on purpose), which the model readers' tests read where installed
#     --deps-only   install the packages, build nothing
# The same as environment variables: WITH_MPI=1, WITH_FUZZ=1, WITH_MODELS=1, DEPS_ONLY=1. Extra CMake
# options: $CMAKE_ARGS, e.g. CMAKE_ARGS=-DRAYTRACER_VIEWER=OFF for a machine without
# GL libraries.
set -euo pipefail
cd "$(dirname "$0")/.."

WITH_MPI=${WITH_MPI:-0}
WITH_FUZZ=${WITH_FUZZ:-0}
WITH_MODELS=${WITH_MODELS:-0}
DEPS_ONLY=${DEPS_ONLY:-0}
for arg in "$@"; do
    case "$arg" in
        --with-mpi) WITH_MPI=1 ;;
        --with-fuzz) WITH_FUZZ=1 ;;
        --with-models) WITH_MODELS=1 ;;
        --deps-only) DEPS_ONLY=1 ;;
        -h|--help) sed -n '2,13s/^# \{0,1\}//p' "$0"; exit 0 ;;
        *) echo "setup.sh: unknown option '$arg' (try --help)" >&2; exit 2 ;;
    esac
done

# The build, the tests (doctest, Xvfb and xdotool drive the viewer, ImageMagick's
# `import` takes its screenshots, python3 runs the function-length check), the viewer's
# GUI libraries and its UI font (DejaVu), OpenEXR for the .exr pictures, libdeflate for
# the PNG textures.
PACKAGES=(build-essential cmake pkg-config libglfw3-dev libimgui-dev libosmesa6-dev libglm-dev
          doctest-dev libstb-dev libdeflate-dev libopenexr-dev zlib1g-dev libtinyobjloader-dev xvfb xauth xdotool imagemagick fonts-dejavu-core python3)
MPI_PACKAGES=(openmpi-bin libopenmpi-dev)
FUZZ_PACKAGES=(clang libclang-rt-14-dev)
MODEL_PACKAGES=(assimp-testmodels)
[ "$WITH_MPI" = 1 ] && PACKAGES+=("${MPI_PACKAGES[@]}")
[ "$WITH_FUZZ" = 1 ] && PACKAGES+=("${FUZZ_PACKAGES[@]}")
[ "$WITH_MODELS" = 1 ] && PACKAGES+=("${MODEL_PACKAGES[@]}")

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
[ "$DEPS_ONLY" = 1 ] && { echo "Dependencies installed."; exit 0; }

BUILD_DIR=${BUILD_DIR:-build}
EXTRA=()
[ "$WITH_MPI" = 1 ] && EXTRA+=(-DRAYTRACER_MPI=ON)
# shellcheck disable=SC2086  # CMAKE_ARGS is a list of words
cmake -S . -B "$BUILD_DIR" "${EXTRA[@]}" ${CMAKE_ARGS:-}
cmake --build "$BUILD_DIR" -j"$(nproc)"
echo "Built: $BUILD_DIR/bin/"
