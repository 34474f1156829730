#!/usr/bin/env bash
# Regenerates every picture in the documentation:
#
#   docs/img/NAME.png      one thumbnail per ```scene NAME example in docs/scene-format.md,
#                          rendered from the example text itself (so the document and its
#                          pictures cannot drift apart)
#   docs/gallery/NAME.png  one picture per scenes/NAME.txt, 480 pixels wide
#   docs/gallery/viewer.png  a raytracer-view screenshot of the default scene, when the
#                          headless viewer is built (otherwise an existing one is kept)
#   docs/gallery.md        the gallery page: every scene with its picture, captioned with
#                          the comment at the top of the scene file
#
# It also runs `raytracer --check` on every ```scene-check example and compares the
# output with the ```text block that follows it in the document.
#
# It builds nothing. The renderer is $RAYTRACER, else build/bin/raytracer; the headless
# viewer is $RAYTRACER_VIEW, else build/bin/raytracer-view-headless. ImageMagick
# (installed by scripts/setup.sh) checks every picture (a black, blank or broken one stops
# the script) and recompresses them losslessly.
#
# Usage: docs/make-gallery.sh            (from anywhere)
# Environment: RAYTRACER, RAYTRACER_VIEW, THUMB_SAMPLES (default 4),
#              GALLERY_SAMPLES (default 16), GALLERY_WIDTH (default 480)
set -euo pipefail

docs=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$docs")
RAYTRACER=${RAYTRACER:-$root/build/bin/raytracer}
RAYTRACER_VIEW=${RAYTRACER_VIEW:-$root/build/bin/raytracer-view-headless}
THUMB_WIDTH=240
THUMB_SAMPLES=${THUMB_SAMPLES:-4}
GALLERY_WIDTH=${GALLERY_WIDTH:-480}
GALLERY_SAMPLES=${GALLERY_SAMPLES:-16}

die() { echo "make-gallery: $*" >&2; exit 1; }

[ -x "$RAYTRACER" ] || die "no renderer at '$RAYTRACER': build first (scripts/setup.sh) or set RAYTRACER"
RAYTRACER=$(cd "$(dirname "$RAYTRACER")" && pwd)/$(basename "$RAYTRACER")
for tool in convert identify awk; do
    command -v "$tool" >/dev/null || die "'$tool' is needed (apt-get install imagemagick)"
done

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# Height for a picture WIDTH pixels wide with the scene's own proportions, read from
# the normalised scene so that any layout of picture_size works.
height_for() {  # SCENE WIDTH
    "$RAYTRACER" --print-scene "$1" | awk -v w="$2" '
        $1 == "x_max" { x = $2 } $1 == "y_max" { y = $2 }
        END { if (!x || !y) exit 1; h = int(w * y / x + 0.5); print (h < 1 ? 1 : h) }'
}

# Refuses a picture that is missing, of the wrong size, black, blank or nearly so.
check_image() {  # PNG WIDTH HEIGHT
    local info w h mean sd colours
    info=$(identify -format '%w %h %[fx:mean] %[fx:standard_deviation] %k' "$1" 2>/dev/null) ||
        die "$1: not a readable image"
    read -r w h mean sd colours <<<"$info"
    if [ "$w" != "$2" ] || [ "$h" != "$3" ]; then die "$1: is ${w}x${h}, expected ${2}x${3}"; fi
    awk -v m="$mean" -v s="$sd" -v c="$colours" 'BEGIN { exit !(m >= 0.03 && s >= 0.02 && c >= 64) }' ||
        die "$1: looks black or blank (mean $mean, deviation $sd, $colours colours)"
}

# Lossless recompression: smaller files, identical pixels.
shrink() {  # IN OUT
    convert "$1" -strip -define png:compression-level=9 -define png:compression-filter=5 "$2"
    if [ "$(stat -c %s "$2")" -ge "$(stat -c %s "$1")" ]; then cp "$1" "$2"; fi
}

# Scenes with sphere lights or a lens (New: radius, aperture) need many samples for
# their penumbrae and blur: SAMPLED_SAMPLES (default 64) instead of the given count.
samples_for() {  # SCENE SAMPLES
    if "$RAYTRACER" --print-scene "$1" |
        awk '/^light \{/ { l = 1 } /^camera \{/ { l = 0 } (l && /^ *radius /) || /^ *aperture / { f = 1 } END { exit !f }'; then
        echo "${SAMPLED_SAMPLES:-64}"
    else
        echo "$2"
    fi
}

render() {  # SCENE OUT WIDTH SAMPLES
    local h n
    h=$(height_for "$1" "$3") || die "$1: cannot read its picture_size"
    n=$(samples_for "$1" "$4")
    "$RAYTRACER" "$1" "$tmp/render.png" --width "$3" --height "$h" --samples "$n" --quiet ||
        die "$1: raytracer failed"
    check_image "$tmp/render.png" "$3" "$h"
    shrink "$tmp/render.png" "$tmp/small.png"
    check_image "$tmp/small.png" "$3" "$h"
    mv "$tmp/small.png" "$2"
}

# --- 1. the examples in scene-format.md ------------------------------------------------
# Writes each fenced block to $tmp/blocks/N.TAG.NAME (N counts blocks from 1).
mkdir -p "$tmp/blocks"
awk -v dir="$tmp/blocks" '
    /^```/ {
        if (open) { close(file); open = 0; next }
        n++; split(substr($0, 4), w, " ")
        file = sprintf("%s/%03d.%s.%s", dir, n, (w[1] == "" ? "none" : w[1]), w[2])
        printf "" > file; open = 1; next
    }
    open { print > file }
' "$docs/scene-format.md"

mkdir -p "$docs/img" "$tmp/examples" "$tmp/check"
# The examples' models and textures are named as from scenes/, where they are.
ln -s "$root/scenes/models" "$tmp/examples/models"
ln -s "$root/scenes/textures" "$tmp/examples/textures"
thumbs=()
for block in "$tmp"/blocks/*.scene.*; do
    [ -e "$block" ] || die "no \`\`\`scene blocks found in scene-format.md"
    name=${block##*.scene.}
    [ -n "$name" ] || die "$(basename "$block"): a \`\`\`scene block without a name"
    cp "$block" "$tmp/examples/$name.txt"
    ( cd "$tmp/examples" && "$RAYTRACER" --check "$name.txt" --quiet ) ||
        die "the example '$name' in scene-format.md has errors"
    render "$tmp/examples/$name.txt" "$docs/img/$name.png" "$THUMB_WIDTH" "$THUMB_SAMPLES"
    thumbs+=("$name.png")
    echo "docs/img/$name.png"
done
# Thumbnails of examples that no longer exist.
for f in "$docs"/img/*.png; do
    [ -e "$f" ] || continue
    case " ${thumbs[*]} " in *" $(basename "$f") "*) ;; *) echo "removing stale $f"; rm -f "$f" ;; esac
done

# The output shown after each ```scene-check block must be what raytracer prints.
for block in "$tmp"/blocks/*.scene-check.*; do
    [ -e "$block" ] || continue
    name=${block##*.scene-check.}
    n=$(basename "$block"); n=${n%%.*}
    next=$(printf '%03d' $((10#$n + 1)))
    expected=$(ls "$tmp/blocks/$next".text.* 2>/dev/null) || die "scene-check '$name': no \`\`\`text block after it"
    cp "$block" "$tmp/check/$name.txt"
    {
        echo "\$ raytracer --check $name.txt"
        ( cd "$tmp/check" && "$RAYTRACER" --check "$name.txt" 2>&1 ) || true
    } >"$tmp/check/$name.out"
    diff -u "$expected" "$tmp/check/$name.out" >&2 ||
        die "scene-check '$name': the output shown in scene-format.md differs from raytracer's (above)"
    echo "checked the error example '$name'"
done

# --- 2. the gallery ------------------------------------------------------------------
mkdir -p "$docs/gallery"
shots=()
for scene in "$root"/scenes/*.txt; do
    name=$(basename "$scene" .txt)
    render "$scene" "$docs/gallery/$name.png" "$GALLERY_WIDTH" "$GALLERY_SAMPLES"
    shots+=("$name.png")
    echo "docs/gallery/$name.png"
done

viewer_note=""
if [ -x "$RAYTRACER_VIEW" ]; then
    "$RAYTRACER_VIEW" "$root/scenes/default.txt" --screenshot "$tmp/viewer.png" --size 960x600 \
        --samples "$GALLERY_SAMPLES" || die "the headless viewer failed"
    check_image "$tmp/viewer.png" 960 600
    shrink "$tmp/viewer.png" "$docs/gallery/viewer.png"
    echo "docs/gallery/viewer.png"
elif [ -e "$docs/gallery/viewer.png" ]; then
    viewer_note="kept the old docs/gallery/viewer.png: no headless viewer at '$RAYTRACER_VIEW'"
fi
[ -e "$docs/gallery/viewer.png" ] && shots+=("viewer.png")
for f in "$docs"/gallery/*.png; do
    [ -e "$f" ] || continue
    case " ${shots[*]} " in *" $(basename "$f") "*) ;; *) echo "removing stale $f"; rm -f "$f" ;; esac
done

# --- 3. gallery.md -------------------------------------------------------------------
# The caption is the comment block at the top of the scene file, without a leading
# "NAME -- " (the heading already names the scene).
caption() {  # SCENE NAME
    awk -v name="$2" '
        /^[ \t]*\/\// { sub(/^[ \t]*\/\/[ \t]?/, ""); text = text (text == "" ? "" : " ") $0; next }
        { exit }
        END {
            for (p = 1; p <= 2; p++) {
                prefix = (p == 1 ? name ".txt" : name)
                if (index(text, prefix " -- ") == 1) text = substr(text, length(prefix) + 5)
            }
            print toupper(substr(text, 1, 1)) substr(text, 2)
        }' "$1"
}

{
    echo "# Gallery"
    echo
    echo "Every scene in [\`scenes/\`](../scenes), rendered by \`raytracer\` at ${GALLERY_WIDTH} pixels wide"
    echo "with ${GALLERY_SAMPLES} samples per pixel. This page and its pictures are made by"
    echo "[\`docs/make-gallery.sh\`](make-gallery.sh); run it again after changing a scene."
    echo "The scene format is described in [scene-format.md](scene-format.md)."
    echo
    echo "To render one yourself:"
    echo
    echo '```sh'
    echo "raytracer scenes/showcase.txt showcase.png --samples 16"
    echo '```'
    for scene in "$root"/scenes/*.txt; do
        name=$(basename "$scene" .txt)
        echo
        echo "## $name"
        echo
        echo "![$name](gallery/$name.png)"
        echo
        text=$(caption "$scene" "$name")
        [ -n "$text" ] && echo "$text" && echo
        echo "Scene file: [\`scenes/$name.txt\`](../scenes/$name.txt)"
    done
    if [ -e "$docs/gallery/viewer.png" ]; then
        echo
        echo "## The viewer"
        echo
        echo "![raytracer-view on the default scene](gallery/viewer.png)"
        echo
        echo "\`raytracer-view\` on the default scene, drawn without a display by"
        echo "\`raytracer-view --headless scenes/default.txt --screenshot viewer.png --size 960x600\`."
    fi
} >"$tmp/gallery.md"
mv "$tmp/gallery.md" "$docs/gallery.md"
echo "docs/gallery.md"
[ -z "$viewer_note" ] || echo "make-gallery: $viewer_note" >&2
echo "make-gallery: done (${#thumbs[@]} thumbnails, ${#shots[@]} gallery pictures)"
