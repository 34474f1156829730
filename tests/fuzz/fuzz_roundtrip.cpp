// libFuzzer target: parse -> write -> parse. For every input that parses without
// errors, text2 = write_scene(scene) must parse without errors to an equal scene
// (operator==), and writing that scene again must give text2 byte for byte.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    rtfuzz::or_abort([&] { rtfuzz::check_roundtrip(text); });
    return 0;
}
