#!/usr/bin/env bash
# Sanitizer builds, as CI runs them:
#   1. build-asan: every target with AddressSanitizer + UndefinedBehaviorSanitizer
#      (-Og -g1: the sanitizers' checks are the same as at -O2 and the build takes less
#      than half the time; line tables are all their reports need), then the whole
#      ctest suite, JOBS at a time (leak checking on, any UB fatal).
#   2. build-tsan: ThreadSanitizer (-O1 -g1: line tables for its reports); builds and runs the renderer tests
#      (rt_renderer_tests: tests/test_renderer*.cpp) and the viewer-logic tests.
#   ./scripts/sanitize.sh [asan|tsan|all]      (default all)
# Environment: JOBS (default 2), CC/CXX (default: the system compiler), CMAKE_ARGS
# (extra CMake options for both builds), TSAN_TEST_FILES (a doctest -sf filter:
# when set, TSan builds the whole rt_tests and runs the files it names), SANITIZE_XVFB=1 (also the Xvfb window test).
set -euo pipefail
cd "$(dirname "$0")/.."

WHAT=${1:-all}
case "$WHAT" in asan|tsan|all) ;; *) echo "usage: $0 [asan|tsan|all]" >&2; exit 2;; esac
JOBS=${JOBS:-2}
TSAN_TEST_FILES=${TSAN_TEST_FILES:-}

run() { echo "+ $*" >&2; "$@"; }
stage() { echo; echo "=== $* ($(date +%T))"; }

# The viewer is always configured: its logic library and tests (tests/viewer) need no
# GUI libraries, and its CMakeLists builds the windowed and headless programs only when
# imgui, glfw3 and osmesa are installed.
if ! pkg-config --exists imgui glfw3 osmesa 2>/dev/null; then
    echo "note: GUI libraries (imgui, glfw3, osmesa) missing: only the viewer logic is built" >&2
fi
# (The test programs with a precompiled header: these builds are made once, and most of
# their time went into compiling doctest and the standard library in every test file.)
COMMON=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DRAYTRACER_TESTS=ON -DRAYTRACER_BENCH=OFF -DRAYTRACER_FUZZ=OFF
        -DRAYTRACER_VIEWER=ON -DRAYTRACER_TEST_PCH=ON)
# shellcheck disable=SC2206  # CMAKE_ARGS is a list of words
COMMON+=(${CMAKE_ARGS:-})

# Leaks are checked, and any UB or race report is fatal.
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:strict_string_checks=1:detect_stack_use_after_return=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1

# ThreadSanitizer's shadow memory layout does not fit every address-space
# randomisation setting (gcc 12 / clang 14 abort with "unexpected memory mapping" when
# vm.mmap_rnd_bits > 28); run its programs without randomisation when we can.
NORAND=()
if setarch "$(uname -m)" -R true 2>/dev/null; then NORAND=(setarch "$(uname -m)" -R); fi

status=0

if [ "$WHAT" != tsan ]; then
    stage "AddressSanitizer + UndefinedBehaviorSanitizer: build-asan"
    run cmake -S . -B build-asan -DRAYTRACER_SANITIZE=address,undefined "${COMMON[@]}" \
        "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-Og -g1 -DNDEBUG" "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-Og -g1 -DNDEBUG"
    run cmake --build build-asan -j"$JOBS"
    stage "ctest under ASan+UBSan"
    # viewer_xvfb, viewer_xvfb_move and viewer_xvfb_turn drive the real window through
    # the system's libGL, Mesa and X libraries, which leak a few hundred bytes at exit from modules already unloaded
    # (so no suppression can name them), and it takes minutes under ASan. The same
    # viewer code runs in viewer_logic and viewer_headless. SANITIZE_XVFB=1 runs it
    # too, with leak checking off.
    # The user journeys (journey_*) drive the same window through the same libraries:
    # they run in the plain build (the README's test command).
    run ctest --test-dir build-asan --output-on-failure -j"$JOBS" --timeout 600 -E '^(viewer_xvfb(_move|_turn)?|journey_.*)$' || status=1
    if [ "${SANITIZE_XVFB:-0}" = 1 ]; then
        ASAN_OPTIONS=${ASAN_OPTIONS/detect_leaks=1/detect_leaks=0} \
            run ctest --test-dir build-asan --output-on-failure --timeout 600 -R '^viewer_xvfb(_move|_turn)?$' || status=1
    fi
fi

if [ "$WHAT" != asan ]; then
    stage "ThreadSanitizer: build-tsan"
    run cmake -S . -B build-tsan -DRAYTRACER_SANITIZE=thread "${COMMON[@]}" \
        "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG"
    # Only the test programs (and what they link); the viewer-logic test programs are
    # whatever tests/viewer defines.
    viewer_tests=()
    if [ -d build-tsan/tests/viewer ]; then
        while IFS= read -r t; do viewer_tests+=("$t"); done < <(
            cmake --build build-tsan --target help | sed -n 's/^\.\.\. \([^ ]*\).*/\1/p; s/^\([^ :]*\): phony$/\1/p' |
                grep -iE 'view.*test|test.*view' | sort -u)
    fi
    tsan_core=rt_renderer_tests
    [ -n "$TSAN_TEST_FILES" ] && tsan_core=rt_tests
    run cmake --build build-tsan -j"$JOBS" --target "$tsan_core" "${viewer_tests[@]}"

    # The renderer tests keep about one core busy, so the viewer-logic tests run beside
    # them (their output is shown when they end).
    if [ ${#viewer_tests[@]} -eq 0 ]; then
        echo "note: no viewer-logic test program (tests/viewer) to run under TSan" >&2
    fi
    (
        vstatus=0
        for t in "${viewer_tests[@]}"; do
            echo "+ ${NORAND[*]} build-tsan/bin/$t"
            "${NORAND[@]}" "build-tsan/bin/$t" || vstatus=1
        done
        exit $vstatus
    ) > build-tsan/viewer-tests.log 2>&1 &
    viewer_pid=$!

    stage "renderer tests under TSan (the viewer-logic tests beside them)"
    if [ -n "$TSAN_TEST_FILES" ]; then
        run "${NORAND[@]}" build-tsan/bin/rt_tests -sf="$TSAN_TEST_FILES" || status=1
    else
        run "${NORAND[@]}" build-tsan/bin/rt_renderer_tests || status=1
    fi
    vstatus=0
    wait "$viewer_pid" || vstatus=1
    stage "viewer-logic tests under TSan: ${viewer_tests[*]}"
    cat build-tsan/viewer-tests.log
    [ $vstatus -eq 0 ] || status=1
fi

echo
if [ $status -eq 0 ]; then echo "sanitize.sh: all clean"; else echo "sanitize.sh: FAILED" >&2; fi
exit $status
