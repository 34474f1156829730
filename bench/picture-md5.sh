#!/usr/bin/env bash
# The md5 list of the reference pictures: every scene in scenes/ and bench/scenes/
# (and, with -b, the 1M-sphere grid and the 1M-triangle mesh from make-grid.sh and
# make-mesh.sh) rendered at one sample, at 4 samples and adaptively, each on both ISA
# paths (RT_ISA=sse2, avx2) and at 1 and 2 threads. The four renders of one setting
# must agree (it says so when they do not); the list holds one md5 per scene and
# setting. Compare it with the stored one after a change that must not change pictures:
#   bench/picture-md5.sh [-b] [BIN_DIR] > /tmp/md5.txt && diff tests/refs/md5.txt /tmp/md5.txt
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
big=0
[ "${1:-}" = -b ] && { big=1; shift; }
bin=${1:-$here/build/bin}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
scenes=("$here"/scenes/*.txt "$here"/bench/scenes/*.txt)
if [ "$big" = 1 ]; then
    [ -f /tmp/rt-big/g1000.txt ] || { mkdir -p /tmp/rt-big; "$here/bench/make-grid.sh" 1000 /tmp/rt-big/g1000.txt; }
    [ -f /tmp/rt-big/mesh1m.txt ] || MAKE_MESH="$bin/make_mesh" "$here/bench/make-mesh.sh" 1000000 /tmp/rt-big/mesh1m >/dev/null
    scenes+=(/tmp/rt-big/g1000.txt /tmp/rt-big/mesh1m.txt)
fi
settings=("1spp|" "4spp|--samples 4" "adaptive|--samples 16 --aa-threshold 0.1")
bad=0
for s in "${scenes[@]}"; do
    name=$(basename "$s" .txt)
    size=()
    case "$s" in */bench/scenes/*|/tmp/rt-big/*) size=(--width 480 --height 270) ;; esac
    for st in "${settings[@]}"; do
        label=${st%%|*} args=${st#*|}
        sums=()
        for isa in sse2 avx2; do
            for th in 1 2; do
                # shellcheck disable=SC2086
                RT_ISA=$isa "$bin/raytracer" --quiet --threads $th "${size[@]}" $args "$s" "$tmp/p.ppm"
                sums+=("$(md5sum < "$tmp/p.ppm" | cut -c1-32)")
            done
        done
        for x in "${sums[@]}"; do
            [ "$x" = "${sums[0]}" ] || { echo "picture-md5.sh: $name $label differs across ISA paths or threads: ${sums[*]}" >&2; bad=1; break; }
        done
        echo "${sums[0]}  $name $label"
    done
done
exit $bad
