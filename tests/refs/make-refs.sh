#!/usr/bin/env bash
# Renders every scene in scenes/ at a quarter of its picture size into tests/refs/,
# the stored references of the end-to-end test. Look at the results (make-refs.sh
# also writes refs.png, a contact sheet, when ImageMagick is present) before
# committing new references.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
bin=${RAYTRACER:-$root/build/bin/raytracer}
for scene in "$root"/scenes/*.txt; do
    name=$(basename "$scene" .txt)
    w=$(awk '/x_max/ { for (i = 1; i < NF; ++i) if ($i == "x_max") print $(i + 1) }' "$scene" | tail -1)
    h=$(awk '/y_max/ { for (i = 1; i < NF; ++i) if ($i == "y_max") print $(i + 1) }' "$scene" | tail -1)
    "$bin" --quiet --width $((w / 4)) --height $((h / 4)) "$scene" "$here/$name.ppm"
    echo "$name: $((w / 4))x$((h / 4))"
done
if command -v montage >/dev/null; then
    montage -label '%t' -geometry +4+4 -tile 5x "$here"/*.ppm /tmp/refs.png && echo "contact sheet: /tmp/refs.png"
fi
