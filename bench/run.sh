#!/usr/bin/env bash
# Times our `raytracer` against POV-Ray 3.7 on the benchmark scene pairs in
# bench/scenes/ and prints a markdown table: the median wall-clock and CPU time of
# several runs of the whole process (parse, render, write), for both programs.
#
#   bench/run.sh [OPTIONS] [SCENE...]      (default: all five scenes)
#
#   -r, --runs N       runs per measurement (default 3); the median is reported
#   -t, --threads N    threads for both renderers (default 2)
#   -b, --binary PATH  our raytracer (default: build/bin/raytracer)
#   -o, --out DIR      keep pictures and logs in DIR (default: a temporary folder)
#   -s, --scaling      also time ours with 1 thread (each run right after a multi-
#                      threaded one) and report the speed-up, of the whole process and
#                      of the render phase alone (from --stats)
#   -P, --no-pov       skip POV-Ray
#   -E, --no-embree    skip the Embree reference (build/bin/embree_ref, built where
#                      Embree 3 is installed): for spheres-10k and things-like it
#                      traces the same camera, shadow and mirror rays without shading
#                      (single rays, packets of 8 and of 16, all with Embree's coherent
#                      flag), and Embree's best of the three over ours is printed
#   -M, --no-micro     skip renderer_bench (preview and cancel latency, BVH build)
#   -g, --grid N       also an N x N sphere grid (bench/make-grid.sh; 1000 gives a
#                      million spheres, a ~100 MB file), generated into the output
#                      folder with its POV-Ray twin: our whole run split into parse
#                      (and its MB/s), compile (BVH build), render and write, peak
#                      memory, and POV-Ray's whole run on the twin
#   -m, --mesh N       also a bumpy ball of N triangles (bench/make-mesh.sh; 1000000 for
#                      issue 27's table), generated into the output folder as binary
#                      PLY and OBJ with its POV-Ray twin (mesh2): our whole run on the
#                      PLY scene split into read + BVH build (parse + compile), render
#                      and write, peak memory, the same read + build from the OBJ file,
#                      POV-Ray's whole run on the twin, and (with -E off) Embree's best
#                      on the same rays with its own triangles over ours
#   -a, --aa           also the anti-aliasing section: for things-like, csg-400 and
#                      glass-stack, POV-Ray's +A0.3 (one run) against ours with the
#                      largest --aa-threshold whose RMSE is no worse, each RMSE (8-bit
#                      units, bench/image_rmse) measured against the program's own
#                      converged picture (POV-Ray +A0.0 +AM1 +R6, ours --samples 256)
#       --aa-refs DIR  keep the converged pictures in DIR and reuse them (they take
#                      minutes to render; delete them when a renderer changes)
#   -R, --realism      also the realism section (640x360): things-soft (things-like with
#                      three sphere lights and a lens) against its POV-Ray twin (area
#                      lights 5x5 adaptive 1 jitter circular orient, focal blur 20
#                      samples, +A0.3): POV-Ray's time against ours at the fewest
#                      samples per pixel whose RMSE is no worse, each against its own
#                      converged picture (POV-Ray 17x17 adaptive 3, 255 blur samples,
#                      +A0.0 +AM1 +R3; ours --samples 256; kept with --aa-refs); the
#                      same for ours with adaptive sampling (--samples 64, the largest
#                      --aa-threshold whose RMSE is no worse); and at
#                      1280x720, 1 sample, the soft shadows' cost: things-soft without
#                      its lens against things-like (point lights), medians of --runs
#   -T, --textured N   also a textured bumpy ball of N triangles (1000000 for issue 38's
#                      table) with texture coordinates, at 1920x1080 and 1 sample: its
#                      material with a 4096x4096 texture (generated, never committed)
#                      and highlights (specular 0.5) against the same mesh and material
#                      without them, whole run and render phase, medians of --runs
#   -q, --quick        160x90, 1 run, a smoke test of this script (used by CI)
#   -h, --help         this text
#
# Scenes: things-like spheres-10k csg-400 glass-stack placed. Each renders at the size in its
# .txt file (1920x1080 or 1280x720). POV-Ray runs as in bench/README.md:
#   povray -D -A +W<width> +H<height> +WT<threads> File_Gamma=1.0 +INAME.pov +Oout.png
set -euo pipefail

HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/.." && pwd)
RUNS=3 THREADS=2 BIN=$ROOT/build/bin/raytracer OUT= SCALING=0 POV=1 EMBREE=1 MICRO=1 QUICK=0 GRID=0 AA=0 AA_REFS= MESH=0
REALISM=0 TEXTURED=0
SCENES=()

usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; }
need_value() { [ $# -ge 2 ] || { echo "run.sh: $1 needs a value" >&2; exit 2; }; }
while [ $# -gt 0 ]; do
    case $1 in
        -r|--runs) need_value "$@"; RUNS=$2; shift ;;
        -t|--threads) need_value "$@"; THREADS=$2; shift ;;
        -b|--binary) need_value "$@"; BIN=$2; shift ;;
        -o|--out) need_value "$@"; OUT=$2; shift ;;
        -s|--scaling) SCALING=1 ;;
        -P|--no-pov) POV=0 ;;
        -E|--no-embree) EMBREE=0 ;;
        -M|--no-micro) MICRO=0 ;;
        -g|--grid) need_value "$@"; GRID=$2; shift ;;
        -m|--mesh) need_value "$@"; MESH=$2; shift ;;
        -a|--aa) AA=1 ;;
        -R|--realism) REALISM=1 ;;
        -T|--textured) need_value "$@"; TEXTURED=$2; shift ;;
        --aa-refs) need_value "$@"; AA_REFS=$2; shift ;;
        -q|--quick) QUICK=1 ;;
        -h|--help) usage; exit 0 ;;
        -*) echo "run.sh: unknown option '$1'" >&2; usage >&2; exit 2 ;;
        *) SCENES+=("$1") ;;
    esac
    shift
done
[ ${#SCENES[@]} -gt 0 ] || SCENES=(things-like spheres-10k csg-400 glass-stack placed)
[[ $RUNS =~ ^[1-9][0-9]*$ ]] || { echo "run.sh: --runs must be a positive integer" >&2; exit 2; }
[[ $THREADS =~ ^[1-9][0-9]*$ ]] || { echo "run.sh: --threads must be a positive integer" >&2; exit 2; }
[[ $GRID =~ ^[0-9]+$ ]] && { [ "$GRID" = 0 ] || [ "$GRID" -ge 2 ]; } ||
    { echo "run.sh: --grid must be an integer of at least 2" >&2; exit 2; }
[[ $MESH =~ ^[0-9]+$ ]] || { echo "run.sh: --mesh must be a number of triangles" >&2; exit 2; }
[[ $TEXTURED =~ ^[0-9]+$ ]] || { echo "run.sh: --textured must be a number of triangles" >&2; exit 2; }
[ -x "$BIN" ] || { echo "run.sh: no raytracer binary at $BIN (build first, or pass -b)" >&2; exit 2; }
for s in "${SCENES[@]}"; do
    [ -f "$HERE/scenes/$s.txt" ] || { echo "run.sh: unknown scene '$s' (no bench/scenes/$s.txt)" >&2; exit 2; }
done
[ $QUICK = 1 ] && RUNS=1
if [ $POV = 1 ] && ! command -v povray > /dev/null; then
    echo "run.sh: povray not installed; skipping POV-Ray" >&2
    POV=0
fi

if [ -n "$OUT" ]; then
    mkdir -p "$OUT"
else
    OUT=$(mktemp -d "${TMPDIR:-/tmp}/rt-bench.XXXXXX")
    trap 'rm -rf "$OUT"' EXIT
fi

median() { printf '%s\n' "$@" | sort -g | awk '{ v[NR] = $1 } END {
    if (NR == 0) { print "n/a"; exit }
    if (NR % 2) printf "%.3f\n", v[(NR + 1) / 2]; else printf "%.3f\n", (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (a == "n/a" || b == "n/a" || b == 0) print "n/a"; else printf "%.2f\n", a / b }'; }
millions() { awk -v r="$1" 'BEGIN { if (r == "n/a") print r; else printf "%.1f M\n", r }'; }
picture_size() { awk -v k="$2" '$1 == k { print $2; exit }' "$HERE/scenes/$1.txt"; }

# Runs a command with its output in LOG; prints "WALL CPU" in seconds. CPU time (user +
# sys of the process and its threads) is reported too because this machine may be
# shared: other load stretches wall time far more than CPU time.
timed() {  # LOG CMD...
    local log=$1 t rc=0 TIMEFORMAT='%R %U %S'
    shift
    t=$( { time "$@" > "$log" 2>&1; } 2>&1 ) || rc=$?
    [ $rc = 0 ] || return $rc
    awk -v t="$t" 'BEGIN { split(t, a, " "); printf "%.3f %.3f\n", a[1], a[2] + a[3] }'
}
run_ours() {  # NAME W H THREADS; its --stats output stays in $OUT/NAME-ours-tTHREADS.log
    local log=$OUT/$1-ours-t$4.log
    timed "$log" "$BIN" --quiet --stats --threads "$4" --width "$2" --height "$3" \
        "$HERE/scenes/$1.txt" "$OUT/$1.ppm" ||
        { echo "run.sh: our raytracer failed on $1:" >&2; cat "$log" >&2; exit 1; }
}
render_time() { sed -n 's/.*render \([0-9.]*\) s.*/\1/p' "$1"; }  # from a --stats log
run_pov() {  # NAME W H THREADS
    local log=$OUT/$1-pov.log
    # POV-Ray rejects `+I FILE` with a space; the name must be attached.
    (cd "$HERE/scenes" && timed "$log" povray -D -A +W"$2" +H"$3" +WT"$4" File_Gamma=1.0 \
        +I"$1.pov" +O"$OUT/$1-pov.png") ||
        { echo "run.sh: povray failed on $1:" >&2; tail -20 "$log" >&2; exit 1; }
}

echo "Machine: $(lscpu 2>/dev/null | sed -n 's/^Model name: *//p' | head -1), $(nproc) CPUs;" \
     "$(date -u '+%Y-%m-%d %H:%M UTC'); load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "Threads: $THREADS; runs per measurement: $RUNS (medians; times of the whole process)"
echo
echo "| scene | resolution | ours (s) | POV-Ray (s) | POV/ours | our rays/s | ours CPU (s) | POV-Ray CPU (s) |"
echo "|---|---|---|---|---|---|---|---|"

declare -A OURS OURS_CPU ONE RENDER ONE_RENDER
for s in "${SCENES[@]}"; do
    if [ $QUICK = 1 ]; then W=160 H=90; else W=$(picture_size "$s" x_max) H=$(picture_size "$s" y_max); fi
    ours=() ours_cpu=() pov=() pov_cpu=() rps=() render=() one=() one_render=()
    for _ in $(seq "$RUNS"); do
        t=$(run_ours "$s" "$W" "$H" "$THREADS"); read -r wall cpu <<< "$t"
        ours+=("$wall") ours_cpu+=("$cpu")
        rps+=("$(sed -n 's/.*(\([0-9.]*\) M rays\/s).*/\1/p' "$OUT/$s-ours-t$THREADS.log")")
        render+=("$(render_time "$OUT/$s-ours-t$THREADS.log")")
        if [ $SCALING = 1 ]; then
            # Right after the multi-threaded run, so that both see the same machine.
            t=$(run_ours "$s" "$W" "$H" 1); read -r wall cpu <<< "$t"
            one+=("$wall") one_render+=("$(render_time "$OUT/$s-ours-t1.log")")
        fi
        if [ $POV = 1 ]; then
            t=$(run_pov "$s" "$W" "$H" "$THREADS"); read -r wall cpu <<< "$t"
            pov+=("$wall") pov_cpu+=("$cpu")
        fi
    done
    # The picture must be what was asked for, or the timing means nothing.
    hdr=$(head -c 64 "$OUT/$s.ppm" | LC_ALL=C tr -d '\000' | LC_ALL=C awk 'NR <= 4 && !/^#/' |
          tr '\n' ' ' | awk '{ print $1, $2, $3 }')
    if [ "$hdr" != "P6 $W $H" ]; then
        echo "run.sh: $s.ppm is not a ${W}x$H PPM" >&2; exit 1
    fi
    OURS[$s]=$(median "${ours[@]}") OURS_CPU[$s]=$(median "${ours_cpu[@]}")
    p=n/a pc=n/a
    if [ $POV = 1 ]; then p=$(median "${pov[@]}") pc=$(median "${pov_cpu[@]}"); fi
    echo "| $s | ${W}x$H | ${OURS[$s]} | $p | $(ratio "$p" "${OURS[$s]}") | $(millions "$(median "${rps[@]}")") |" \
         "$(median "${ours_cpu[@]}") | $pc |"
    RENDER[$s]=$(median "${render[@]}")
    if [ $SCALING = 1 ]; then
        ONE[$s]=$(median "${one[@]}") ONE_RENDER[$s]=$(median "${one_render[@]}")
    fi
done
echo

if [ $SCALING = 1 ]; then
    for s in "${SCENES[@]}"; do
        echo "- $s, ours: 1 thread ${ONE[$s]} s, $THREADS threads ${OURS[$s]} s," \
             "speed-up $(ratio "${ONE[$s]}" "${OURS[$s]}")x; render phase alone" \
             "${ONE_RENDER[$s]} s / ${RENDER[$s]} s = $(ratio "${ONE_RENDER[$s]}" "${RENDER[$s]}")x"
    done
fi
if [ -n "${OURS[spheres-10k]:-}" ] && [ -n "${OURS[things-like]:-}" ]; then
    echo "- ours, spheres-10k / things-like time: $(ratio "${OURS[spheres-10k]}" "${OURS[things-like]}")" \
         "(10,000 spheres vs 8 objects at the same size)"
fi

ER=$(dirname "$BIN")/embree_ref
if [ $EMBREE = 1 ] && [ -x "$ER" ]; then
    for s in "${SCENES[@]}"; do
        case $s in spheres-10k|things-like) ;; *) continue ;; esac
        if [ $QUICK = 1 ]; then size=(--width 160 --height 90); else size=(); fi
        "$ER" "$HERE/scenes/$s.txt" --threads "$THREADS" --repeats "$RUNS" "${size[@]}" > "$OUT/$s-embree.log" 2>&1 ||
            { echo "run.sh: embree_ref failed on $s:" >&2; cat "$OUT/$s-embree.log" >&2; exit 1; }
        best=$(sed -n 's/^best \([0-9.]*\)$/\1/p' "$OUT/$s-embree.log")
        best_cpu=$(sed -n 's/^best_cpu \([0-9.]*\)$/\1/p' "$OUT/$s-embree.log")
        single=$(sed -n 's/^ *single rays: *\([0-9.]*\) s.*/\1/p' "$OUT/$s-embree.log")
        packets=$(sed -n 's/^ *packets of 8 ([0-9x]*): *\([0-9.]*\) s.*/\1/p' "$OUT/$s-embree.log")
        packets16=$(sed -n 's/^ *packets of 16 ([0-9x]*): *\([0-9.]*\) s.*/\1/p' "$OUT/$s-embree.log")
        echo "- $s, Embree $THREADS threads, coherent flag, traversal only (camera, shadow, mirror rays): single rays" \
             "$single s, packets of 8 $packets s, of 16 $packets16 s; Embree best / ours: $(ratio "$best" "${OURS[$s]}") (our whole" \
             "process ${OURS[$s]} s), $(ratio "$best" "${RENDER[$s]}") (our render phase ${RENDER[$s]} s);" \
             "by processor time (steadier on a loaded machine): Embree best $best_cpu s / our whole process" \
             "${OURS_CPU[$s]} s = $(ratio "$best_cpu" "${OURS_CPU[$s]}")"
    done
elif [ $EMBREE = 1 ]; then
    echo "run.sh: no embree_ref next to $BIN (Embree 3 not installed?); skipping Embree" >&2
fi

if [ "$GRID" != 0 ]; then
    # The big scene: generated here (never committed), rendered at its own 1920x1080.
    G=$OUT/grid$GRID
    "$HERE/make-grid.sh" "$GRID" "$G.txt" "$G.pov"
    bytes=$(stat -c %s "$G.txt")
    walls=() parses=() compiles=() renders=() writes=() rss=() pov=() pov_cpu=()
    for _ in $(seq "$RUNS"); do
        # GNU time's %M is the peak resident set of the process in KiB.
        if [ -x /usr/bin/time ]; then
            t=$( { /usr/bin/time -f '%e %M' "$BIN" --quiet --stats --threads "$THREADS" "$G.txt" "$G.ppm" \
                     2> "$G-ours.log" > /dev/null; } 2>&1; tail -1 "$G-ours.log")
        else
            t="$(timed "$G-ours.log" "$BIN" --quiet --stats --threads "$THREADS" "$G.txt" "$G.ppm" | cut -d' ' -f1) n/a"
        fi
        grep -q '^time:' "$G-ours.log" || { echo "run.sh: our raytracer failed on the grid:" >&2; cat "$G-ours.log" >&2; exit 1; }
        read -r wall kb <<< "$t"
        walls+=("$wall") rss+=("$kb")
        parses+=("$(sed -n 's/.*parse \([0-9.]*\) s.*/\1/p' "$G-ours.log")")
        compiles+=("$(sed -n 's/.*compile \([0-9.]*\) s.*/\1/p' "$G-ours.log")")
        renders+=("$(render_time "$G-ours.log")")
        writes+=("$(sed -n 's/.*write \([0-9.]*\) s.*/\1/p' "$G-ours.log")")
        if [ $POV = 1 ]; then
            t=$(cd "$OUT" && timed "$G-pov.log" povray -D -A +W1920 +H1080 +WT"$THREADS" File_Gamma=1.0 \
                    +I"grid$GRID.pov" +O"$G-pov.png") ||
                { echo "run.sh: povray failed on the grid:" >&2; tail -20 "$G-pov.log" >&2; exit 1; }
            read -r wall cpu <<< "$t"
            pov+=("$wall") pov_cpu+=("$cpu")
        fi
    done
    p=$(median "${parses[@]}")
    mbs=$(awk -v b="$bytes" -v t="$p" 'BEGIN { if (t > 0) printf "%.0f", b / t / 1e6; else print "n/a" }')
    kb=n/a
    [ "${rss[0]}" != n/a ] && kb=$(median "${rss[@]}")
    mem=$(awk -v k="$kb" 'BEGIN { if (k == "n/a") print k; else printf "%.0f MB", k * 1024 / 1e6 }')
    pw=n/a
    [ $POV = 1 ] && pw=$(median "${pov[@]}")
    echo
    echo "Grid of $GRID x $GRID spheres ($(awk -v b="$bytes" 'BEGIN { printf "%.1f", b / 1e6 }') MB file), 1920x1080, 1 sample per pixel, $THREADS threads, medians:"
    echo
    echo "| ours whole (s) | parse (s) | parse MB/s | compile (s) | render (s) | write (s) | ours peak memory | POV-Ray whole (s) | POV/ours |"
    echo "|---|---|---|---|---|---|---|---|---|"
    echo "| $(median "${walls[@]}") | $p | $mbs | $(median "${compiles[@]}") | $(median "${renders[@]}") |" \
         "$(median "${writes[@]}") | $mem | $pw | $(ratio "$pw" "$(median "${walls[@]}")") |"
    rm -f "$G.txt" "$G.pov"
fi

# The big mesh: generated here (never committed), rendered at its own 1920x1080. Every
# ratio comes from runs of one loop turn, so that a change of load on a shared machine
# shifts both sides of it alike.
mesh_section() {
    local M=$OUT/mesh$MESH t wall kb e_best=n/a
    MAKE_MESH=${MAKE_MESH:-$(dirname "$BIN")/make_mesh} "$HERE/make-mesh.sh" "$MESH" "$M" --pov
    local walls=() reads=() renders=() writes=() rss=() objreads=() pov=() embree=() cpus=() small_cpus=() embree_cpu=()
    local cpu small
    for _ in $(seq "$RUNS"); do
        if [ -x /usr/bin/time ]; then
            t=$( { /usr/bin/time -f '%e %M %U %S' "$BIN" --quiet --stats --threads "$THREADS" "$M.txt" "$M.ppm" \
                     2> "$M-ours.log" > /dev/null; } 2>&1; tail -1 "$M-ours.log")
            t=$(awk '{ printf "%s %s %.3f\n", $1, $2, $3 + $4 }' <<< "$t")
        else
            t=$(timed "$M-ours.log" "$BIN" --quiet --stats --threads "$THREADS" "$M.txt" "$M.ppm" | awk '{ print $1, "n/a", $2 }')
        fi
        grep -q '^time:' "$M-ours.log" || { echo "run.sh: our raytracer failed on the mesh:" >&2; cat "$M-ours.log" >&2; exit 1; }
        read -r wall kb cpu <<< "$t"
        walls+=("$wall") rss+=("$kb") cpus+=("$cpu")
        # The same run at 8x8: its processor time is the reading and the build, so the
        # difference is the render's (steadier than its wall time on a loaded machine).
        small=$(timed "$M-small.log" "$BIN" --quiet --threads "$THREADS" --width 8 --height 8 "$M.txt" "$M-small.ppm") ||
            { echo "run.sh: our raytracer failed on the mesh at 8x8:" >&2; cat "$M-small.log" >&2; exit 1; }
        small_cpus+=("$(cut -d' ' -f2 <<< "$small")")
        reads+=("$(awk '/^time:/ { for (i = 1; i < NF; ++i) { if ($i == "parse") p = $(i + 1); if ($i == "compile") c = $(i + 1) } print p + c }' "$M-ours.log")")
        renders+=("$(render_time "$M-ours.log")")
        writes+=("$(sed -n 's/.*write \([0-9.]*\) s.*/\1/p' "$M-ours.log")")
        "$BIN" --quiet --stats --threads "$THREADS" --width 8 --height 8 "$M-obj.txt" "$M-obj.ppm" 2> "$M-obj.log" ||
            { echo "run.sh: our raytracer failed on the OBJ mesh:" >&2; cat "$M-obj.log" >&2; exit 1; }
        objreads+=("$(awk '/^time:/ { for (i = 1; i < NF; ++i) { if ($i == "parse") p = $(i + 1); if ($i == "compile") c = $(i + 1) } print p + c }' "$M-obj.log")")
        if [ $POV = 1 ]; then
            t=$(cd "$OUT" && timed "$M-pov.log" povray -D -A +W1920 +H1080 +WT"$THREADS" File_Gamma=1.0 \
                    +I"mesh$MESH.pov" +O"$M-pov.png") ||
                { echo "run.sh: povray failed on the mesh:" >&2; tail -20 "$M-pov.log" >&2; exit 1; }
            read -r wall _ <<< "$t"
            pov+=("$wall")
        fi
        if [ $EMBREE = 1 ] && [ -x "$(dirname "$BIN")/embree_ref" ]; then
            "$(dirname "$BIN")/embree_ref" "$M.txt" --threads "$THREADS" --repeats 1 > "$M-embree.log" 2>&1 ||
                { echo "run.sh: embree_ref failed on the mesh:" >&2; cat "$M-embree.log" >&2; exit 1; }
            embree+=("$(sed -n 's/^best \([0-9.]*\)$/\1/p' "$M-embree.log")")
            embree_cpu+=("$(sed -n 's/^best_cpu \([0-9.]*\)$/\1/p' "$M-embree.log")")
        fi
    done
    kb=n/a
    [ "${rss[0]}" != n/a ] && kb=$(median "${rss[@]}")
    local mem pw
    mem=$(awk -v k="$kb" 'BEGIN { if (k == "n/a") print k; else printf "%.0f MB", k * 1024 / 1e6 }')
    pw=n/a
    [ $POV = 1 ] && pw=$(median "${pov[@]}")
    local e_cpu=n/a render_cpu
    [ ${#embree[@]} -gt 0 ] && e_best=$(median "${embree[@]}") && e_cpu=$(median "${embree_cpu[@]}")
    render_cpu=$(awk -v a="$(median "${cpus[@]}")" -v b="$(median "${small_cpus[@]}")" \
        'BEGIN { if (a == "n/a" || b == "n/a") print "n/a"; else printf "%.3f\n", a - b }')
    echo
    echo "Bumpy ball of about $MESH triangles (bench/make-mesh.sh), 1920x1080, 1 sample per pixel, $THREADS threads, medians of $RUNS:"
    echo
    echo "| ours whole (s) | PLY read + BVH (s) | OBJ read + BVH (s) | render (s) | write (s) | ours peak memory | POV-Ray whole (s) | POV/ours | Embree best (s) | Embree best / our render | Embree best / ours whole | render processor time (s): Embree best / ours |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
    local ow
    ow=$(median "${walls[@]}")
    echo "| $ow | $(median "${reads[@]}") | $(median "${objreads[@]}") | $(median "${renders[@]}") | $(median "${writes[@]}") |" \
         "$mem | $pw | $(ratio "$pw" "$ow") | $e_best | $(ratio "$e_best" "$(median "${renders[@]}")") | $(ratio "$e_best" "$ow") |" \
         "$e_cpu / $render_cpu = $(ratio "$e_cpu" "$render_cpu") |"
    rm -f "$M.ply" "$M.obj" "$M.inc"
}
[ "$MESH" != 0 ] && mesh_section

# The textured mesh (-T): the cost of a big texture and highlights at one sample. Both
# scenes read the same PLY file (with its texture coordinates), so that the two differ
# only in the material; each run of one is right after a run of the other.
textured_section() {
    local M=$OUT/texmesh$TEXTURED W=1920 H=1080 size=4096 t
    [ $QUICK = 1 ] && W=160 H=90 size=256
    "${MAKE_MESH:-$(dirname "$BIN")/make_mesh}" "$TEXTURED" "$M.ply" --uv --texture "$size" "$M.png" > /dev/null ||
        { echo "run.sh: make_mesh could not write the textured mesh" >&2; exit 1; }
    scene() {  # FILE MATERIAL
        cat > "$1" <<SCENE
// texmesh$TEXTURED -- a bumpy ball of about $TEXTURED triangles with texture coordinates (bench/run.sh -T)
thing { mesh { file "texmesh$TEXTURED.ply" position 0 0 1.2 material { scattering 1 colour 0.9 0.9 0.9 $2 } } }
special_thing {
  plane { material { scattering 1 colour 0.6 0.6 0.6 } point 1 0 0 0  point 2 1 0 0  point 3 0 1 0  point 4 0 0 1 }
}
light {
  spotlight { colour 60 60 57 position -4 -6 8 }
  spotlight { colour 20 21 25 position 5 3 6 }
}
camera { position 0 -4.2 2.4 centre 0 0 1 up 0 0 2 projection 2 angle_x 60 angle_y 35.9834 }
picture_size { x_max $W y_max $H }
end
SCENE
    }
    scene "$M-plain.txt" ""
    scene "$M-tex.txt" "texture \"texmesh$TEXTURED.png\" specular 0.5 shininess 60"
    local pw=() pr=() tw=() tr=()
    for _ in $(seq "$RUNS"); do
        t=$(timed "$M-plain.log" "$BIN" --quiet --stats --threads "$THREADS" "$M-plain.txt" "$M-plain.ppm") ||
            { echo "run.sh: our raytracer failed on the plain mesh:" >&2; cat "$M-plain.log" >&2; exit 1; }
        pw+=("${t%% *}") pr+=("$(render_time "$M-plain.log")")
        t=$(timed "$M-tex.log" "$BIN" --quiet --stats --threads "$THREADS" "$M-tex.txt" "$M-tex.ppm") ||
            { echo "run.sh: our raytracer failed on the textured mesh:" >&2; cat "$M-tex.log" >&2; exit 1; }
        tw+=("${t%% *}") tr+=("$(render_time "$M-tex.log")")
    done
    local pwm prm twm trm
    pwm=$(median "${pw[@]}") prm=$(median "${pr[@]}") twm=$(median "${tw[@]}") trm=$(median "${tr[@]}")
    echo
    echo "Textured bumpy ball of about $TEXTURED triangles, ${W}x$H, 1 sample per pixel, $THREADS threads, medians of" \
         "$RUNS: a ${size}x$size texture and highlights (specular 0.5) against the same mesh and material without them:"
    echo
    echo "| without: whole (s) | render (s) | with texture + highlights: whole (s) | render (s) | with / without, whole | render |"
    echo "|---|---|---|---|---|---|"
    echo "| $pwm | $prm | $twm | $trm | $(ratio "$twm" "$pwm") | $(ratio "$trm" "$prm") |"
    rm -f "$M.ply" "$M.png"
}
[ "$TEXTURED" != 0 ] && textured_section

# The anti-aliasing section: POV-Ray's usual anti-aliasing against ours at the same
# quality. Quality is the RMSE against each program's own converged picture.
# aa_run SCENE THRESHOLD: one timed run of ours; AA_RESULT="WALL RMSE SPP"; succeeds
# if the RMSE is no worse than POV-Ray's ($pr). (Uses aa_section's W, H, ourref.)
aa_run() {
    local t wall or spp
    t=$(timed "$OUT/$1-ours-aa.log" "$BIN" --quiet --stats --threads "$THREADS" --width "$W" --height "$H" \
        --aa-threshold "$2" "$HERE/scenes/$1.txt" "$OUT/$1-ours-aa.png") ||
        { echo "run.sh: our raytracer failed on $1:" >&2; cat "$OUT/$1-ours-aa.log" >&2; exit 1; }
    read -r wall _ <<< "$t"
    or=$("$RMSE_BIN" "$OUT/$1-ours-aa.png" "$ourref" | awk '{ print $2 }')
    spp=$(sed -n 's/.*, \([0-9.]*\) samples per pixel on average.*/\1/p' "$OUT/$1-ours-aa.log")
    AA_RESULT="$wall $or $spp"
    awk -v a="$or" -v b="$pr" 'BEGIN { exit !(a <= b) }'
}

aa_section() {
    local refs=${AA_REFS:-$OUT/aa-refs} s t wall or spp aa
    RMSE_BIN=$(dirname "$BIN")/image_rmse
    [ -x "$RMSE_BIN" ] || { echo "run.sh: no image_rmse next to $BIN; skipping anti-aliasing" >&2; return; }
    [ $POV = 1 ] || { echo "run.sh: anti-aliasing compares with POV-Ray; skipping it" >&2; return; }
    mkdir -p "$refs"
    echo
    echo "Anti-aliasing: POV-Ray +A0.3 against ours at the largest --aa-threshold (searched in steps of" \
         "0.05 from 0.6, then to 0.00625) whose RMSE is no worse; one run each, whole process, both writing PNG:"
    echo
    echo "| scene | resolution | POV-Ray +A0.3 (s) | its RMSE | ours: threshold | ours (s) | our RMSE | our samples per pixel | POV/ours |"
    echo "|---|---|---|---|---|---|---|---|---|"
    for s in things-like csg-400 glass-stack; do
        if [ $QUICK = 1 ]; then W=160 H=90; else W=$(picture_size "$s" x_max) H=$(picture_size "$s" y_max); fi
        local povref=$refs/$s-${W}x$H-pov.png
        ourref=$refs/$s-${W}x$H-ours256.ppm
        [ -s "$povref" ] || (cd "$HERE/scenes" && povray -D +A0.0 +AM1 +R6 +W"$W" +H"$H" +WT"$THREADS" \
            File_Gamma=1.0 +I"$s.pov" +O"$povref" > "$OUT/$s-povref.log" 2>&1) ||
            { echo "run.sh: povray failed on $s:" >&2; tail -20 "$OUT/$s-povref.log" >&2; exit 1; }
        [ -s "$ourref" ] || "$BIN" --quiet --threads "$THREADS" --width "$W" --height "$H" --samples 256 \
            "$HERE/scenes/$s.txt" "$ourref" || { echo "run.sh: our raytracer failed on $s" >&2; exit 1; }
        t=$(cd "$HERE/scenes" && timed "$OUT/$s-pov-aa.log" povray -D +A0.3 +W"$W" +H"$H" +WT"$THREADS" \
            File_Gamma=1.0 +I"$s.pov" +O"$OUT/$s-pov-aa.png") ||
            { echo "run.sh: povray failed on $s:" >&2; tail -20 "$OUT/$s-pov-aa.log" >&2; exit 1; }
        read -r pwall _ <<< "$t"
        pr=$("$RMSE_BIN" "$OUT/$s-pov-aa.png" "$povref" | awk '{ print $2 }')  # (aa_run reads it)
        # Down in steps of 0.05 to the first threshold that matches POV-Ray's RMSE, then
        # three halvings of the step between it and the one above it that did not.
        local fail= ok= best=
        for aa in 0.6 0.55 0.5 0.45 0.4 0.35 0.3 0.25 0.2 0.15 0.1 0.05; do
            aa_run "$s" "$aa" && { ok=$aa; break; }
            fail=$aa
        done
        best=$AA_RESULT
        for _ in 1 2 3; do
            [ -n "$ok" ] && [ -n "$fail" ] || break
            aa=$(awk -v a="$ok" -v b="$fail" 'BEGIN { printf "%.4g\n", (a + b) / 2 }')
            if aa_run "$s" "$aa"; then ok=$aa best=$AA_RESULT; else fail=$aa; fi
        done
        [ -n "$ok" ] || ok=$aa
        read -r wall or spp <<< "$best"
        awk -v a="$or" -v b="$pr" 'BEGIN { exit !(a > b) }' && or="$or (worse)"
        aa=$ok
        echo "| $s | ${W}x$H | $pwall | $pr | $aa | $wall | $or | $spp | $(ratio "$pwall" "$wall") |"
    done
}
[ $AA = 1 ] && aa_section

# Ours on $s at ${W}x$H with each setting in turn (raytracer's options, as words)
# until its RMSE against $ourref is no worse than POV-Ray's ($pr): the setting, the
# run's wall time and the RMSE (marked "(worse)" if no setting got there) in
# RUN_SETTING, RUN_WALL and RUN_RMSE.
fewest_matching() {
    local setting t
    for setting in "$@"; do
        # shellcheck disable=SC2086  # the setting is a list of options
        t=$(timed "$OUT/$s-ours.log" "$BIN" --quiet --threads "$THREADS" --width "$W" --height "$H" $setting \
            "$HERE/scenes/$s.txt" "$OUT/$s-ours.png") ||
            { echo "run.sh: our raytracer failed on $s:" >&2; cat "$OUT/$s-ours.log" >&2; exit 1; }
        read -r RUN_WALL _ <<< "$t"
        RUN_RMSE=$("$RMSE_BIN" "$OUT/$s-ours.png" "$ourref" | awk '{ print $2 }')
        RUN_SETTING=$setting
        awk -v a="$RUN_RMSE" -v b="$pr" 'BEGIN { exit !(a <= b) }' && return 0
    done
    RUN_RMSE="$RUN_RMSE (worse)"
}

# The realism section (-R): see the usage above.
realism_section() {
    local refs=${AA_REFS:-$OUT/aa-refs} s=things-soft t pwall pr W H point=() soft=()
    RMSE_BIN=$(dirname "$BIN")/image_rmse
    [ -x "$RMSE_BIN" ] || { echo "run.sh: no image_rmse next to $BIN; skipping the realism section" >&2; return; }
    mkdir -p "$refs"
    if [ $QUICK = 1 ]; then W=160 H=90; else W=640 H=360; fi
    echo
    echo "Realism: $s (three sphere lights, a lens) at ${W}x$H, $THREADS threads; POV-Ray's twin with area" \
         "lights and focal blur at +A0.3 against ours at the fewest samples per pixel whose RMSE is no worse" \
         "(each against its own converged picture); one run each, whole process, both writing PNG:"
    echo
    if [ $POV = 1 ]; then
        local povref=$refs/$s-${W}x$H-pov.png ourref=$refs/$s-${W}x$H-ours256.ppm
        [ -s "$povref" ] || (cd "$HERE/scenes" && povray -D +A0.0 +AM1 +R3 +W"$W" +H"$H" +WT"$THREADS" File_Gamma=1.0 \
            Declare=AREA_N=17 Declare=AREA_ADAPT=3 Declare=BLUR_N=255 +I"$s.pov" +O"$povref" > "$OUT/$s-povref.log" 2>&1) ||
            { echo "run.sh: povray failed on $s:" >&2; tail -20 "$OUT/$s-povref.log" >&2; exit 1; }
        [ -s "$ourref" ] || "$BIN" --quiet --threads "$THREADS" --width "$W" --height "$H" --samples 256 \
            "$HERE/scenes/$s.txt" "$ourref" || { echo "run.sh: our raytracer failed on $s" >&2; exit 1; }
        t=$(cd "$HERE/scenes" && timed "$OUT/$s-pov.log" povray -D +A0.3 +W"$W" +H"$H" +WT"$THREADS" \
            File_Gamma=1.0 +I"$s.pov" +O"$OUT/$s-pov.png") ||
            { echo "run.sh: povray failed on $s:" >&2; tail -20 "$OUT/$s-pov.log" >&2; exit 1; }
        read -r pwall _ <<< "$t"
        pr=$("$RMSE_BIN" "$OUT/$s-pov.png" "$povref" | awk '{ print $2 }')
        echo "| scene | POV-Ray +A0.3 (s) | its RMSE | ours: samples per pixel | ours (s) | our RMSE | POV/ours |"
        echo "|---|---|---|---|---|---|---|"
        fewest_matching "--samples "{1,2,3,4,6,8,12,16,24,32,48,64,96,128}
        echo "| $s | $pwall | $pr | ${RUN_SETTING#--samples } | $RUN_WALL | $RUN_RMSE | $(ratio "$pwall" "$RUN_WALL") |"
        # Adaptive: up to 64 samples where a pixel's samples still spread or it differs
        # from a neighbour by T; the largest T (fewest samples) whose RMSE is no worse.
        fewest_matching "--samples 64 --aa-threshold "{0.04,0.03,0.02,0.015,0.012,0.01,0.008,0.006,0.004}
        echo "| $s | $pwall | $pr | adaptive, at most 64, ${RUN_SETTING#--samples 64 } | $RUN_WALL | $RUN_RMSE |" \
             "$(ratio "$pwall" "$RUN_WALL") |"
    fi
    # The soft shadows' cost at one sample: sphere lights against the same points.
    if [ $QUICK = 1 ]; then W=160 H=90; else W=1280 H=720; fi
    sed '/aperture/d' "$HERE/scenes/$s.txt" > "$OUT/things-softonly.txt"
    for _ in $(seq "$RUNS"); do
        t=$(timed "$OUT/point.log" "$BIN" --quiet --threads "$THREADS" --width "$W" --height "$H" \
            "$HERE/scenes/things-like.txt" "$OUT/point.ppm") || { cat "$OUT/point.log" >&2; exit 1; }
        point+=("${t%% *}")
        t=$(timed "$OUT/soft.log" "$BIN" --quiet --threads "$THREADS" --width "$W" --height "$H" \
            "$OUT/things-softonly.txt" "$OUT/soft.ppm") || { cat "$OUT/soft.log" >&2; exit 1; }
        soft+=("${t%% *}")
    done
    local pm sm
    pm=$(median "${point[@]}") sm=$(median "${soft[@]}")
    echo
    echo "Soft shadows at 1 sample per pixel, ${W}x$H, $THREADS threads, medians of $RUNS whole runs:"
    echo
    echo "| things-like, point lights (s) | the same, sphere lights of radius 0.6 (s) | sphere / point |"
    echo "|---|---|---|"
    echo "| $pm | $sm | $(ratio "$sm" "$pm") |"
}
[ $REALISM = 1 ] && realism_section

if [ $MICRO = 1 ]; then
    MB=$(dirname "$BIN")/renderer_bench
    if [ -x "$MB" ]; then
        echo
        if [ $QUICK = 1 ]; then
            "$MB" 64 36 --repeats 2 --spheres 2000 --threads "$THREADS"
        else
            "$MB" --threads "$THREADS"
        fi
    else
        echo "run.sh: no renderer_bench next to $BIN; skipping the micro-benchmark" >&2
    fi
fi
