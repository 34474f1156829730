#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, AddressSanitizer + UndefinedBehaviorSanitizer)
# into build-fuzz/ and runs each for SECONDS (default 60), all at once.
#   ./scripts/fuzz.sh [SECONDS]
# Corpora persist in build-fuzz/fuzz/corpus-*; the seed corpus is rebuilt each run from
# scenes/, bench/scenes/, the parser tests and built-in snippets. Crash, leak, timeout
# and out-of-memory inputs are saved in build-fuzz/fuzz/artifacts/ and make the script
# exit non-zero; turn each into a regression test (tests/test_fuzz_regressions.cpp).
# Environment: BUILD_DIR (default build-fuzz), JOBS (build jobs, default 2),
# FUZZ_EXTRA (more libFuzzer flags), FUZZ_TARGETS (default: the scene parser's two, the
# model readers' two, the texture decoder's, the MTL reader's and fuzz_edits; fuzz_edits plays user edits through the viewer's
# document, so the viewer's logic is configured too).
set -euo pipefail
cd "$(dirname "$0")/.."

SECONDS_EACH=${1:-60}
case "$SECONDS_EACH" in ''|*[!0-9]*) echo "usage: $0 [SECONDS]" >&2; exit 2;; esac
BUILD_DIR=${BUILD_DIR:-build-fuzz}
JOBS=${JOBS:-2}
TARGETS=${FUZZ_TARGETS:-fuzz_parser fuzz_roundtrip fuzz_obj fuzz_ply fuzz_texture fuzz_mtl fuzz_edits}

run() { echo "+ $*" >&2; "$@"; }

# clang with libFuzzer and the sanitizer runtimes: setup.sh's list has them.
if ! command -v clang++ >/dev/null 2>&1 || ! ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1; then
    run ./scripts/setup.sh --with-fuzz --deps-only
fi

run cmake -S . -B "$BUILD_DIR" \
    -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g" \
    -DRAYTRACER_FUZZ=ON -DRAYTRACER_SANITIZE=address,undefined \
    -DRAYTRACER_TESTS=OFF -DRAYTRACER_VIEWER=ON -DRAYTRACER_BENCH=OFF
# shellcheck disable=SC2086  # TARGETS is a list of words
run cmake --build "$BUILD_DIR" -j"$JOBS" --target $TARGETS fuzz_seed_corpus

WORK=$BUILD_DIR/fuzz
SEEDS=$WORK/seeds
rm -rf "$SEEDS"
mkdir -p "$SEEDS" "$WORK/artifacts"
shopt -s nullglob
SEED_FILES=()
for f in scenes/*.txt bench/scenes/*.txt tests/test_parser.cpp tests/test_writer.cpp tests/test_limits.cpp \
         tests/test_fuzz_regressions.cpp tests/fuzz/regressions/* tests/models/* tests/textures/* scenes/textures/*; do
    [ -f "$f" ] && SEED_FILES+=("$f")
done
run "$BUILD_DIR/bin/fuzz_seed_corpus" "$SEEDS" "${SEED_FILES[@]}"

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
FLAGS=(-max_total_time="$SECONDS_EACH" -timeout=2 -rss_limit_mb=2048 -malloc_limit_mb=2048
       -max_len=65536 -dict=tests/fuzz/scene.dict -use_value_profile=1 -print_final_stats=1
       -reload=0)
# shellcheck disable=SC2206  # FUZZ_EXTRA is a list of words
FLAGS+=(${FUZZ_EXTRA:-})

# The known regressions first: each must run clean before new fuzzing starts.
REGRESSIONS=(tests/fuzz/regressions/*)
status=0
for t in $TARGETS; do
    if [ ${#REGRESSIONS[@]} -gt 0 ]; then
        echo "+ $BUILD_DIR/bin/$t -timeout=2 -rss_limit_mb=2048 tests/fuzz/regressions/* > $WORK/$t-regressions.log" >&2
        "$BUILD_DIR/bin/$t" -timeout=2 -rss_limit_mb=2048 "${REGRESSIONS[@]}" >"$WORK/$t-regressions.log" 2>&1 || {
            echo "FAIL: $t on tests/fuzz/regressions/ (log: $WORK/$t-regressions.log)" >&2
            tail -n 40 "$WORK/$t-regressions.log" >&2
            status=1
        }
    fi
done

pids=()
for t in $TARGETS; do
    mkdir -p "$WORK/corpus-$t" "$WORK/artifacts/$t"
    echo "+ $BUILD_DIR/bin/$t ${FLAGS[*]} -artifact_prefix=$WORK/artifacts/$t/ $WORK/corpus-$t $SEEDS > $WORK/$t.log" >&2
    "$BUILD_DIR/bin/$t" "${FLAGS[@]}" -artifact_prefix="$WORK/artifacts/$t/" "$WORK/corpus-$t" "$SEEDS" \
        >"$WORK/$t.log" 2>&1 &
    pids+=($!)
done

i=0
for t in $TARGETS; do
    if wait "${pids[$i]}"; then
        echo "ok: $t: $(grep -E '^stat::number_of_executed_units' "$WORK/$t.log" | awk '{print $2}') runs in ${SECONDS_EACH} s, corpus $(find "$WORK/corpus-$t" -type f | wc -l) files"
    else
        echo "FAIL: $t found a problem (log: $WORK/$t.log; inputs in $WORK/artifacts/$t/):" >&2
        grep -E 'ERROR|WARNING: |fuzz invariant|SUMMARY|Test unit written|ALARM|==[0-9]+==' "$WORK/$t.log" | head -n 40 >&2 || true
        tail -n 30 "$WORK/$t.log" >&2
        status=1
    fi
    i=$((i + 1))
done
exit $status
