// libFuzzer target: the MTL reader on arbitrary bytes. Besides crashes, hangs and
// leaks, it checks rtfuzz::check_mtl: an error with a message at a line, or materials
// whose numbers are in the ranges the scene format keeps.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    rtfuzz::or_abort([&] { rtfuzz::check_mtl(bytes); });
    return 0;
}
