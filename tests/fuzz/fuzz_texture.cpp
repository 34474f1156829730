// libFuzzer target: the texture decoder (the signature checks, the header's size read
// before stb_image allocates, the project's PNG reader and stb_image's PNG and JPEG
// decoders, sRGB decoding) on arbitrary bytes. Besides crashes, hangs, leaks and
// allocations over -malloc_limit_mb (a header claiming a huge image), it checks
// rtfuzz::check_texture: an error with a message, or an image within the limits with
// texels and samples in 0..1; and that a PNG the project's reader takes (png_read.h)
// decodes to stb_image's texels wherever stb_image decodes it too (palette images
// aside: stb_image reads an index past the palette from memory it never set).
#include <stb/stb_image.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string_view>

#include "fuzz_common.h"
#include "png_read.h"

namespace {

void check_png_reader(std::string_view bytes) {
    long long w = 0, h = 0;
    if (!rt::image_size(bytes, w, h) || std::uint64_t(w) * std::uint64_t(h) > (1u << 18)) return;
    int rw = 0, rh = 0;
    const std::unique_ptr<std::uint8_t, rt::PngFree> ours = rt::read_png8(bytes, rw, rh);
    if (!ours || (bytes.size() > 25 && bytes[25] == 3)) return;  // not taken, or a palette image
    int sw = 0, sh = 0, c = 0;
    std::unique_ptr<stbi_uc, void (*)(void*)> theirs(
            stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), int(bytes.size()), &sw, &sh, &c, 3),
            stbi_image_free);
    if (!theirs) return;
    if (sw != rw || sh != rh) rtfuzz::fail("the PNG reader's size differs from stb_image's");
    if (std::memcmp(ours.get(), theirs.get(), std::size_t(rw) * std::size_t(rh) * 3) != 0)
        rtfuzz::fail("the PNG reader's texels differ from stb_image's");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    rtfuzz::or_abort([&] {
        rtfuzz::check_texture(bytes);
        check_png_reader(bytes);
    });
    return 0;
}
