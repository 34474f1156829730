// PNG encoding (png.h). Every row is Sub-filtered (each byte minus the one a pixel to
// its left: zeros and runs of small numbers where a rendering is flat or evenly
// shaded) and compressed by the project's own DEFLATE encoder (deflate.h), which looks
// for exactly those repeats: about a tenth of the raw size for a typical render, at
// several times the speed of zlib's fastest setting. Strips of rows are compressed
// on several threads; all but the last end in a sync flush (an empty stored block:
// byte-aligned, not final), so their data strung together is one stream, behind one
// zlib header and before one Adler-32, combined (by zlib) from the strips' own.
#include "png.h"

#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <new>
#include <thread>
#include <vector>

#include "deflate.h"
#include "parallel.h"

namespace rt {

namespace {

// Raw bytes of filtered rows per DEFLATE block (at least one row): small enough to stay
// in the cache between filtering and compressing, big enough to pay for a block's codes.
constexpr std::size_t kBlockBytes = std::size_t(1) << 17;
// Raw bytes from which a strip is worth a thread of its own.
constexpr std::size_t kStripBytes = std::size_t(1) << 20;

void put32(std::string& s, std::uint32_t v) {
    const char b[4] = {char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
    s.append(b, 4);
}

void filter_row(const std::uint8_t* row, std::size_t stride, std::uint8_t* out) {
    out[0] = 1;  // filter type Sub
    std::memcpy(out + 1, row, std::min<std::size_t>(3, stride));
    for (std::size_t i = 3; i < stride; ++i) out[1 + i] = std::uint8_t(row[i] - row[i - 3]);
}

// One strip: rows [y0, y1) as an IDAT chunk without its CRC, and the checksums.
struct Strip {
    int y0 = 0, y1 = 0;
    std::string chunk;      // length (filled in at the end), "IDAT", the data
    std::uint32_t adler = 1;  // of the strip's filtered bytes
    std::size_t raw = 0;    // how many there are
    uLong crc = 0;          // of "IDAT" and the data
    bool ok = false;
};

void compress_rows(const std::uint8_t* rgb, int width, bool first, bool last, Strip& s) {
    const std::size_t stride = std::size_t(width) * 3, line = stride + 1;
    const int step = int(std::max<std::size_t>(1, kBlockBytes / line));
    std::vector<std::uint8_t> rows(line * std::size_t(std::min(step, s.y1 - s.y0)));
    s.chunk.assign("\0\0\0\0IDAT", 8);
    if (first) s.chunk += "\x78\x01";  // zlib header: deflate, 32 KiB window, fastest
    s.adler = 1;
    DeflateWriter writer(s.chunk);
    for (int y = s.y0; y < s.y1; y += step) {
        const int n = std::min(step, s.y1 - y);
        for (int k = 0; k < n; ++k) filter_row(rgb + std::size_t(y + k) * stride, stride, &rows[std::size_t(k) * line]);
        const std::size_t len = line * std::size_t(n);
        s.adler = adler32_update(s.adler, rows.data(), len);
        s.raw += len;
        writer.block(rows.data(), len, last && y + n >= s.y1);
    }
    writer.finish(last);
    s.crc = crc32(0, reinterpret_cast<const Bytef*>(s.chunk.data() + 4), uInt(s.chunk.size() - 4));
    s.ok = true;
}

// On any of the pool's threads: out of memory fails the strip, not the process.
void compress_strip(const std::uint8_t* rgb, int width, bool first, bool last, Strip& s) {
    try {
        compress_rows(rgb, width, first, last, s);
    } catch (const std::bad_alloc&) {
        s.chunk = std::string();
        s.ok = false;
    }
}

// A whole chunk of `type` with `data`.
void put_chunk(std::string& out, const char* type, const std::string& data) {
    put32(out, std::uint32_t(data.size()));
    const std::size_t at = out.size();
    out.append(type, 4);
    out += data;
    put32(out, std::uint32_t(crc32(0, reinterpret_cast<const Bytef*>(out.data() + at), uInt(out.size() - at))));
}

}  // namespace

bool encode_png(const std::uint8_t* rgb, int width, int height, std::string& out, int threads) {
    const std::size_t raw = (std::size_t(width) * 3 + 1) * std::size_t(height);
    if (threads <= 0) threads = process_pool().size();  // (the pool it runs on)
    // Strips of at least kStripBytes each, and each chunk well within 2^31 bytes (even
    // at two bytes out for every byte in).
    const std::size_t most = std::max<std::size_t>(1, raw / kStripBytes), least = raw / (std::size_t(1) << 29) + 1;
    const int n = int(std::min<std::size_t>(std::size_t(height), std::max(least, std::min<std::size_t>(most, threads))));
    std::vector<Strip> strips{static_cast<std::size_t>(n)};
    for (int k = 0; k < n; ++k) {
        Strip& s = strips[std::size_t(k)];
        s.y0 = int(std::int64_t(height) * k / n);
        s.y1 = int(std::int64_t(height) * (k + 1) / n);
    }
    process_pool().parallel_for(
            n, [&](int k) { compress_strip(rgb, width, k == 0, k == n - 1, strips[std::size_t(k)]); });
    if (!std::all_of(strips.begin(), strips.end(), [](const Strip& s) { return s.ok; })) return false;

    // The stream's Adler-32 ends the last chunk.
    uLong adler = strips[0].adler;
    for (std::size_t k = 1; k < strips.size(); ++k) adler = adler32_combine(adler, strips[k].adler, z_off_t(strips[k].raw));
    Strip& tail = strips.back();
    const std::size_t before = tail.chunk.size();
    put32(tail.chunk, std::uint32_t(adler));
    tail.crc = crc32(tail.crc, reinterpret_cast<const Bytef*>(tail.chunk.data() + before), 4);

    out.append("\x89PNG\r\n\x1a\n", 8);
    std::string ihdr;
    put32(ihdr, std::uint32_t(width));
    put32(ihdr, std::uint32_t(height));
    ihdr.append("\x08\x02\x00\x00\x00", 5);  // 8 bits, RGB, deflate, adaptive filters, no interlace
    put_chunk(out, "IHDR", ihdr);
    for (Strip& s : strips) {
        const std::uint32_t len = std::uint32_t(s.chunk.size() - 8);
        for (int b = 0; b < 4; ++b) s.chunk[std::size_t(b)] = char(len >> (24 - 8 * b));
        out += s.chunk;
        put32(out, std::uint32_t(s.crc));
    }
    put_chunk(out, "IEND", std::string());
    return true;
}

}  // namespace rt
