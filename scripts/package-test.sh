#!/usr/bin/env bash
# Builds the Debian package from an existing build (build/ or $BUILD_DIR) with
# `cpack -G DEB`, unpacks it into a scratch root (dpkg -x: nothing is installed on the
# machine, no root needed) and checks it: the files are where Debian wants them, every
# library the programs load is found and named in Depends, the unpacked raytracer renders
# a scene from the package exactly as the build does, and the unpacked
# `raytracer-view --headless` finds its sibling raytracer-view-headless next to itself.
# Usage: scripts/package-test.sh   (after scripts/setup.sh or scripts/test.sh)
#        PACKAGE_TEST_KEEP=shot.png scripts/package-test.sh   keeps the screenshot to look at
set -euo pipefail
cd "$(dirname "$0")/.."

BUILD_DIR=${BUILD_DIR:-build}
fail() { echo "package-test: FAIL: $*" >&2; exit 1; }
[ -x "$BUILD_DIR/bin/raytracer" ] || fail "no $BUILD_DIR/bin/raytracer: build first (scripts/setup.sh)"

rm -f "$BUILD_DIR"/raytracer_*.deb
(cd "$BUILD_DIR" && cpack -G DEB > cpack.log 2>&1) || { cat "$BUILD_DIR/cpack.log" >&2; fail "cpack -G DEB failed"; }
debs=("$BUILD_DIR"/raytracer_*.deb)
[ -f "${debs[0]}" ] || fail "cpack made no raytracer_*.deb"
deb=${debs[0]}
echo "package-test: $deb ($(du -k "$deb" | cut -f1) KiB)"
dpkg-deb --field "$deb" Package Version Architecture Installed-Size

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
root=$scratch/root
dpkg -x "$deb" "$root"

# The files, where a Debian system looks for them.
expect=(usr/bin/raytracer usr/share/man/man1/raytracer.1 usr/share/raytracer/scenes/default.txt
        usr/share/raytracer/scenes/showcase.txt)
viewer=no
if [ -x "$BUILD_DIR/bin/raytracer-view" ] && [ -x "$BUILD_DIR/bin/raytracer-view-headless" ]; then
    viewer=yes
    expect+=(usr/bin/raytracer-view usr/bin/raytracer-view-headless usr/share/man/man1/raytracer-view.1)
fi
[ -x "$BUILD_DIR/bin/raytracer-mpi" ] && expect+=(usr/bin/raytracer-mpi)
for f in "${expect[@]}"; do
    [ -e "$root/$f" ] || fail "the package has no /$f"
done
scenes=$(find "$root/usr/share/raytracer/scenes" -name '*.txt' | wc -l)
[ "$scenes" -eq "$(find scenes -maxdepth 1 -name '*.txt' | wc -l)" ] || fail "the package has $scenes scenes"
if find "$root" -path "$root/usr/local" -prune -o -name 'rt_tests*' -print | grep -q .; then
    fail "test programs are in the package"
fi

# Depends: the package of every library a program links directly is named there (the
# libraries those load in turn are their packages' business), and nothing is missing.
depends=$(dpkg-deb --field "$deb" Depends)
echo "package-test: Depends: $depends"
[ -n "$depends" ] || fail "the package declares no Depends"
names=$(echo "$depends" | tr ',|' '\n\n' | awk '{ print $1 }' | sed 's/:.*//')
for exe in "$root"/usr/bin/*; do
    if ldd "$exe" | grep -q 'not found'; then
        ldd "$exe" >&2
        fail "$(basename "$exe") needs a library that is not on this machine"
    fi
    for soname in $(objdump -p "$exe" | awk '$1 == "NEEDED" { print $2 }'); do
        lib=$(ldd "$exe" | awk -v s="$soname" '$1 == s { print $3 }')
        [ -n "$lib" ] || fail "$(basename "$exe"): $soname not resolved"
        owner=$(dpkg -S "$lib" 2>/dev/null || dpkg -S "$(readlink -f "$lib")" 2>/dev/null || true)
        owner=${owner%%:*}
        [ -n "$owner" ] || continue  # not from a package (a local build): nothing to declare
        echo "$names" | grep -qx "$owner" ||
            fail "$(basename "$exe") links $soname from $owner, which Depends does not name"
    done
done
for dep in $(echo "$depends" | tr ',' '\n' | awk '{ print $1 }'); do
    dpkg-query -W -f='${Status}\n' "${dep%%|*}" 2>/dev/null | grep -q 'ok installed' ||
        fail "Depends names $dep, which is not installed here (does it exist?)"
done

# The unpacked raytracer renders a scene from the package, byte for byte as the build's.
# Neither the build folder nor the scratch root is on PATH.
export PATH=/usr/sbin:/usr/bin:/sbin:/bin
scene=$root/usr/share/raytracer/scenes/showcase.txt
"$root/usr/bin/raytracer" "$scene" "$scratch/packaged.ppm" --width 64 --height 48 --samples 2 2> "$scratch/err" ||
    { cat "$scratch/err" >&2; fail "the packaged raytracer exited with $?"; }
"$BUILD_DIR/bin/raytracer" "$scene" "$scratch/built.ppm" --width 64 --height 48 --samples 2 2> /dev/null
cmp -s "$scratch/packaged.ppm" "$scratch/built.ppm" || fail "the packaged raytracer renders differently"
head -c 2 "$scratch/packaged.ppm" | grep -q P6 || fail "no PPM written"
for exe in "$root"/usr/bin/*; do
    "$exe" --version > /dev/null 2>&1 || fail "$(basename "$exe") --version exited with $?"
done
man -l "$root/usr/share/man/man1/raytracer.1" > /dev/null 2>&1 || ! command -v man > /dev/null ||
    fail "man cannot read raytracer.1"
echo "package-test: the packaged raytracer renders showcase.txt as the build does"

if [ "$viewer" = yes ]; then
    # `raytracer-view --headless` execs raytracer-view-headless from its own folder:
    # from the package, that is the unpacked usr/bin.
    # An empty PATH: the sibling cannot come from anywhere else.
    mkdir "$scratch/empty"
    export MESA_SHADER_CACHE_DISABLE=true
    PATH=$scratch/empty "$root/usr/bin/raytracer-view" --headless --screenshot "$scratch/shot.png" --size 320x200 --samples 1 \
        "$root/usr/share/raytracer/scenes/sphere.txt" 2> "$scratch/err" ||
        { cat "$scratch/err" >&2; fail "the packaged raytracer-view --headless exited with $?"; }
    [ "$(head -c 8 "$scratch/shot.png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] ||
        fail "the packaged raytracer-view --headless wrote no PNG"
    [ -z "${PACKAGE_TEST_KEEP:-}" ] || cp "$scratch/shot.png" "$PACKAGE_TEST_KEEP"
    echo "package-test: the packaged raytracer-view --headless ran its packaged sibling and took a screenshot"
fi
echo "package-test: passed"
