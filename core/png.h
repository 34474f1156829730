// PNG encoding for the pictures the renderer writes: 8-bit RGB, fast rather than small.
// The rows are cut into strips that are filtered and compressed on several threads at
// once, each strip its own IDAT chunk; together the chunks hold one ordinary zlib
// stream, so any PNG reader reads the file.
#pragma once

#include <cstdint>
#include <string>

namespace rt {

// Appends the PNG file of the width x height picture `rgb` (3 bytes a pixel, top row
// first) to `out`, in up to `threads` strips (0: the process pool's threads; the file's
// bytes depend on it) compressed on the process pool (parallel.h). False if out of
// memory.
bool encode_png(const std::uint8_t* rgb, int width, int height, std::string& out, int threads = 0);

}  // namespace rt
