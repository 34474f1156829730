#!/usr/bin/env bash
# The reuse target of the scene-language issue: a scene of 100,000 placements of one
# named 49-object CSG (instance blocks, each turned and moved) against 100,000 spheres,
# parsed, built and rendered at 8x8 by `raytracer`: time and peak memory of each.
#   bench/instances-bench.sh [BIN_DIR]
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
bin=${1:-$here/build/bin}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
tail='light { lamp { position 2 3 6 colour 50 50 50 size 0.2 } }
camera { position -5 -5 5 centre 150 150 0 up 150 150 1 angle_x 60 angle_y 45 }
picture_size { x_max 8 y_max 8 }
end'
awk -v tail="$tail" 'BEGIN {
    csg = "sphere { position 0 0 0 radius 0.3 }"
    for (k = 1; k < 25; k++) csg = "constructive_solid_geometry { type U left { box { corner_1 0 0 0 corner_2 0.1 0.1 0.1 } } right { " csg " } }"
    print "define { object thing49 { " csg " } }"
    print "thing {"
    for (i = 0; i < 100000; i++) printf "  instance { object thing49 translate %d %d 0 rotation 0 0 %d }\n", i % 316, int(i / 316), i % 90
    print "}"; print tail }' > "$tmp/instances.txt"
awk -v tail="$tail" 'BEGIN {
    print "thing {"
    for (i = 0; i < 100000; i++) printf "  sphere { position %d %d 0 radius 0.3 }\n", i % 316, int(i / 316)
    print "}"; print tail }' > "$tmp/spheres.txt"
for scene in spheres instances; do
    for run in 1 2 3; do
        /usr/bin/time -f "$scene: %e s, %M KB" "$bin/raytracer" "$tmp/$scene.txt" "$tmp/out.ppm" --quiet --threads 2
    done
done
