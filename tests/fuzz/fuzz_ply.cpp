// libFuzzer target: the PLY reader (ASCII and both binary byte orders) on arbitrary
// bytes, with the same promises as the OBJ reader's (rtfuzz::check_model): a header
// claiming more records than the bytes can hold is refused before anything is
// allocated, and whatever is accepted is whole triangles naming vertices there are.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    rtfuzz::or_abort([&] { rtfuzz::check_model(bytes, rt::read_ply); });
    return 0;
}
