// libFuzzer target: the texture decoder (the signature checks, the header's size read
// before stb_image allocates, stb_image's PNG and JPEG decoders, sRGB decoding) on
// arbitrary bytes. Besides crashes, hangs, leaks and allocations over -malloc_limit_mb
// (a header claiming a huge image), it checks rtfuzz::check_texture: an error with a
// message, or an image within the limits with texels and samples in 0..1.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    rtfuzz::or_abort([&] { rtfuzz::check_texture(bytes); });
    return 0;
}
