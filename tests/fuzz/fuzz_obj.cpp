// libFuzzer target: the OBJ reader (tinyobjloader and the checks around it) on arbitrary
// bytes. Besides crashes, hangs and leaks (the sanitizers), it checks the reader's
// promises (rtfuzz::check_model): an error with a message, or whole triangles naming
// vertices there are, at finite coordinates, whose BVH builds and answers rays.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    rtfuzz::or_abort([&] { rtfuzz::check_model(bytes, rt::read_obj); });
    return 0;
}
