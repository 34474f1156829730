// libFuzzer target: parse_scene on arbitrary bytes. Besides crashes, hangs and leaks
// (the sanitizers), it checks the parser's promises (fuzz_common.h): every diagnostic
// has a position in the text, in file order; a scene without errors respects the
// limits (scene.h) and the format's New: rules for degenerate geometry and camera; a
// lower error cap does not change whether the scene is ok.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_common.h"

// The lower error cap takes the early-stop paths (Stop thrown from deep inside). A cap
// of 1 is the strictest: it found that the whole-scene checks, run outside the parser's
// try block, could throw past parse_scene (fixed in 56916a8; regression test in
// tests/test_fuzz_regressions.cpp).
#ifndef RT_FUZZ_MAX_ERRORS
#define RT_FUZZ_MAX_ERRORS 1
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    rtfuzz::or_abort([&] { rtfuzz::check_parse(text, RT_FUZZ_MAX_ERRORS); });
    return 0;
}
