// PNG decoding for textures, the common case only: 8-bit, non-interlaced, grey, grey
// with alpha, RGB, RGBA or palette. The image data is inflated by libdeflate (about
// twice as fast as stb_image's or zlib's inflater on a big texture) straight into the
// buffer that becomes the texels, and unfiltered there. The texels are the ones
// stb_image gives (stbi_load_from_memory asked for 3 channels) byte for byte; a file
// this reader does not take, or in which anything is unusual (a tRNS chunk, an unknown
// critical chunk, a data stream that is damaged, too short or too long, a checksum
// that does not match), is left to stb_image, which decodes it or says what is wrong
// as it did before.
#pragma once

#include <cstdint>
#include <memory>
#include <string_view>

namespace rt {

struct PngFree {
    void operator()(std::uint8_t* p) const;
};

// The texels (3 bytes each, rows from the top, from malloc: freed with std::free) of
// the PNG file `bytes` with its size in w and h; null when the file is not one this
// reader takes (see above).
std::unique_ptr<std::uint8_t, PngFree> read_png8(std::string_view bytes, int& w, int& h);

}  // namespace rt
