// Small PNG files made in the tests (through zlib), for the texture tests: any bit
// depth and colour type, and headers with no image behind them.
#pragma once

#include <zlib.h>

#include <cstdint>
#include <string>
#include <vector>

namespace rt_test {

inline void png_chunk(std::string& out, const char* type, const std::string& data) {
    auto be32 = [&](std::uint32_t v) {
        for (int s = 24; s >= 0; s -= 8) out += char((v >> s) & 0xff);
    };
    be32(std::uint32_t(data.size()));
    const std::string body = std::string(type, 4) + data;
    out += body;
    be32(std::uint32_t(crc32(0, reinterpret_cast<const Bytef*>(body.data()), uInt(body.size()))));
}

inline std::string png_ihdr(std::uint32_t w, std::uint32_t h, int depth, int colour_type) {
    std::string d;
    for (std::uint32_t v : {w, h})
        for (int s = 24; s >= 0; s -= 8) d += char((v >> s) & 0xff);
    d += char(depth), d += char(colour_type), d += '\0', d += '\0', d += '\0';
    return d;
}

// A PNG of the rows in `samples` (bytes as the format stores them, no filter bytes):
// colour_type 0 grey, 2 RGB, 4 grey + alpha, 6 RGBA.
inline std::string png_raw(int w, int h, int depth, int colour_type, const std::vector<unsigned char>& samples) {
    const std::size_t row = samples.size() / std::size_t(h);
    std::string raw;
    for (int y = 0; y < h; ++y) {
        raw += '\0';
        raw.append(reinterpret_cast<const char*>(samples.data()) + std::size_t(y) * row, row);
    }
    uLongf n = compressBound(uLong(raw.size()));
    std::string z(n, '\0');
    compress(reinterpret_cast<Bytef*>(&z[0]), &n, reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size()));
    z.resize(n);
    std::string out = "\x89PNG\r\n\x1a\n";
    png_chunk(out, "IHDR", png_ihdr(std::uint32_t(w), std::uint32_t(h), depth, colour_type));
    png_chunk(out, "IDAT", z);
    png_chunk(out, "IEND", "");
    return out;
}

inline std::string png_rgb8(int w, int h, const std::vector<unsigned char>& rgb) { return png_raw(w, h, 8, 2, rgb); }

// A signature and an IHDR claiming w x h, then a tiny IDAT and the end.
inline std::string png_header_only(std::uint32_t w, std::uint32_t h) {
    std::string out = "\x89PNG\r\n\x1a\n";
    png_chunk(out, "IHDR", png_ihdr(w, h, 8, 2));
    png_chunk(out, "IDAT", std::string("\x78\x9c\x03\x00\x00\x00\x00\x01", 8));
    png_chunk(out, "IEND", "");
    return out;
}

}  // namespace rt_test
