// The PNG texture reader (core/png_read.h) against stb_image: every colour type it
// takes, odd sizes, all five filters, several IDAT chunks, the renderer's own PNGs; the
// files it leaves to stb_image (and that decode_texture still decodes as stb_image
// does, or refuses with its reason).
#include <doctest/doctest.h>
#include <stb/stb_image.h>
#include <zlib.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "png.h"
#include "png_read.h"
#include "test_textures.h"
#include "texture.h"

using namespace rt;
using rt_test::png_chunk;
using rt_test::png_ihdr;

namespace {

// Channels of each PNG colour type.
int channels(int colour) { return colour == 0 ? 1 : colour == 2 ? 3 : colour == 3 ? 1 : colour == 4 ? 2 : 4; }

int paeth(int a, int b, int c) {
    const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

// A PNG of `samples` (rows as the format stores them, without filter bytes), row y
// filtered with filter (y + shift) % 5 by the format's definition, the zlib stream
// cut into IDAT chunks of `idat` bytes; `chunks_before` go before the first IDAT.
std::string png_filtered(int w, int h, int colour, const std::vector<unsigned char>& samples, int shift = 0,
                         std::size_t idat = 100, const std::string& chunks_before = "", int level = 6) {
    const std::size_t bpp = std::size_t(channels(colour)), stride = std::size_t(w) * bpp;
    std::string raw;
    for (int y = 0; y < h; ++y) {
        const int f = (y + shift) % 5;
        raw += char(f);
        const unsigned char* row = samples.data() + std::size_t(y) * stride;
        const unsigned char* up = y ? row - stride : nullptr;
        for (std::size_t i = 0; i < stride; ++i) {
            const int a = i >= bpp ? row[i - bpp] : 0, b = up ? up[i] : 0, c = up && i >= bpp ? up[i - bpp] : 0;
            const int pred = f == 0 ? 0 : f == 1 ? a : f == 2 ? b : f == 3 ? (a + b) / 2 : paeth(a, b, c);
            raw += char((row[i] - pred) & 0xff);
        }
    }
    uLongf n = compressBound(uLong(raw.size()));
    std::string z(n, '\0');
    compress2(reinterpret_cast<Bytef*>(&z[0]), &n, reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size()), level);
    z.resize(n);
    std::string out = "\x89PNG\r\n\x1a\n";
    png_chunk(out, "IHDR", png_ihdr(std::uint32_t(w), std::uint32_t(h), 8, colour));
    out += chunks_before;
    for (std::size_t at = 0; at < z.size(); at += idat) png_chunk(out, "IDAT", z.substr(at, idat));
    png_chunk(out, "IEND", "");
    return out;
}

std::uint32_t be32_of(const std::string& s, std::size_t at) {
    const auto b = [&](std::size_t k) { return std::uint32_t(std::uint8_t(s[at + k])); };
    return b(0) << 24 | b(1) << 16 | b(2) << 8 | b(3);
}

// Bytes that look like a picture: gradients, edges and noise, so every filter has work.
std::vector<unsigned char> pattern(std::size_t n, unsigned seed, unsigned modulo = 256) {
    std::vector<unsigned char> v(n);
    unsigned s = seed * 2654435761u + 1;
    for (std::size_t i = 0; i < n; ++i) {
        s = s * 1664525u + 1013904223u;
        const unsigned smooth = unsigned(i * 7 / 5) + (i % 13 < 6 ? 40u : 0u);
        v[i] = static_cast<unsigned char>((i % 3 == 0 ? (s >> 24) : smooth) % modulo);
    }
    return v;
}

struct StbImage {
    std::unique_ptr<stbi_uc, void (*)(void*)> p{nullptr, stbi_image_free};
    int w = 0, h = 0;
};

StbImage stb(const std::string& bytes) {
    StbImage s;
    int c = 0;
    s.p.reset(stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), int(bytes.size()), &s.w, &s.h,
                                    &c, 3));
    return s;
}

// The reader takes `bytes` and gives stb_image's texels, byte for byte; so does
// decode_texture.
void same_as_stb(const std::string& bytes) {
    const StbImage want = stb(bytes);
    REQUIRE(bool(want.p));
    int w = 0, h = 0;
    std::unique_ptr<std::uint8_t, PngFree> got = read_png8(bytes, w, h);
    REQUIRE(bool(got));
    REQUIRE(w == want.w);
    REQUIRE(h == want.h);
    const std::size_t n = std::size_t(w) * std::size_t(h) * 3;
    CHECK(std::memcmp(got.get(), want.p.get(), n) == 0);
    std::string error;
    std::shared_ptr<Texture> t = decode_texture(bytes, error);
    REQUIRE(bool(t));
    REQUIRE(t->srgb8() != nullptr);
    CHECK(std::memcmp(t->srgb8(), want.p.get(), n) == 0);
}

}  // namespace

TEST_CASE("png reader: every colour type, odd sizes, all five filters: stb_image's texels byte for byte") {
    const int sizes[][2] = {{1, 1}, {1, 7}, {7, 1}, {5, 3}, {13, 11}, {31, 17}, {64, 9}};
    for (int colour : {0, 2, 3, 4, 6})
        for (const auto& sz : sizes)
            for (int shift = 0; shift < 5; ++shift) {
                CAPTURE(colour);
                CAPTURE(sz[0]);
                CAPTURE(sz[1]);
                CAPTURE(shift);
                const int w = sz[0], h = sz[1];
                const std::size_t n = std::size_t(w) * std::size_t(h) * std::size_t(channels(colour));
                std::string plte;
                unsigned modulo = 256;
                if (colour == 3) {
                    // 200 entries, every index below that
                    std::string entries;
                    for (int k = 0; k < 200 * 3; ++k) entries += char((k * 37 + 11) & 0xff);
                    png_chunk(plte, "PLTE", entries);
                    modulo = 200;
                }
                same_as_stb(png_filtered(w, h, colour, pattern(n, unsigned(w * 100 + h + shift), modulo), shift,
                                         std::size_t(7 + shift * 50), plte));
            }
}

TEST_CASE("png reader: ancillary chunks skipped, one IDAT or many, stored and fixed-code streams") {
    const std::vector<unsigned char> rgb = pattern(23 * 19 * 3, 5);
    std::string text;
    png_chunk(text, "tEXt", std::string("Comment\0made in a test", 22));
    png_chunk(text, "gAMA", std::string("\0\0\xb1\x8f", 4));
    same_as_stb(png_filtered(23, 19, 2, rgb, 0, 100000, text));
    same_as_stb(png_filtered(23, 19, 2, rgb, 1, 1));
    same_as_stb(png_filtered(23, 19, 2, rgb, 2, 64, "", 0));  // stored blocks
    same_as_stb(png_filtered(23, 19, 2, rgb, 3, 64, "", 1));
}

TEST_CASE("png reader: the renderer's own PNGs (strips of sync-flushed streams, as the bench textures)") {
    const int w = 1031, h = 1029;  // three strips of about 1 MB
    std::vector<unsigned char> rgb = pattern(std::size_t(w) * h * 3, 9);
    std::string png;
    REQUIRE(encode_png(rgb.data(), w, h, png, 3));
    same_as_stb(png);
    int rw = 0, rh = 0;
    auto got = read_png8(png, rw, rh);
    REQUIRE(bool(got));
    CHECK(std::memcmp(got.get(), rgb.data(), rgb.size()) == 0);
}

// The zlib stream of a PNG made by png_filtered (its IDAT chunks' data strung
// together) made again into IDAT chunks of `idat` bytes.
std::string with_stream(int w, int h, int colour, const std::string& z, std::size_t idat) {
    std::string out = "\x89PNG\r\n\x1a\n";
    png_chunk(out, "IHDR", png_ihdr(std::uint32_t(w), std::uint32_t(h), 8, colour));
    for (std::size_t at = 0; at < z.size(); at += idat) png_chunk(out, "IDAT", z.substr(at, idat));
    png_chunk(out, "IEND", "");
    return out;
}

TEST_CASE("png reader: the stream's header and Adler-32 are checked, in one IDAT or many, for every kind of row") {
    for (int colour : {0, 2, 4, 6}) {
        CAPTURE(colour);
        const int w = 11, h = 6;
        const std::vector<unsigned char> px = pattern(std::size_t(w * h * channels(colour)), unsigned(colour) + 20);
        const std::string one = png_filtered(w, h, colour, px, 1, 1u << 20);
        // The stream: the single IDAT's data (after the signature, IHDR and the chunk's
        // length and type; before its CRC, IEND's 12 bytes).
        const std::string z = one.substr(8 + 25 + 8, one.size() - (8 + 25 + 8) - 4 - 12);
        for (std::size_t idat : {std::size_t(1) << 20, std::size_t(9)}) {
            CAPTURE(idat);
            int rw = 0, rh = 0;
            same_as_stb(with_stream(w, h, colour, z, idat));
            // Any bit of the Adler-32 wrong: left to stb_image (which does not look).
            for (std::size_t k = z.size() - 4; k < z.size(); ++k) {
                std::string bad = z;
                bad[k] = char(bad[k] ^ 0x10);
                CHECK_FALSE(bool(read_png8(with_stream(w, h, colour, bad, idat), rw, rh)));
            }
            // Without its Adler-32, or with part of it: left too.
            for (std::size_t cut : {1, 4})
                CHECK_FALSE(bool(read_png8(with_stream(w, h, colour, z.substr(0, z.size() - cut), idat), rw, rh)));
            // Bytes after it are not looked at (as libdeflate's zlib reader did).
            CHECK(bool(read_png8(with_stream(w, h, colour, z + "junk", idat), rw, rh)));
            // A preset dictionary (its check bits made right), a window over 32 KB, a
            // method other than deflate, wrong check bits: left.
            const auto header = [&](unsigned cmf, unsigned flg) {
                flg = (flg & ~31u) | (31 - (cmf * 256 + (flg & ~31u)) % 31) % 31;
                std::string other = z;
                other[0] = char(cmf), other[1] = char(flg);
                return with_stream(w, h, colour, other, idat);
            };
            CHECK(bool(read_png8(header(0x78, 0x80), rw, rh)));  // another level: taken
            CHECK_FALSE(bool(read_png8(header(0x78, 0x20), rw, rh)));
            CHECK_FALSE(bool(read_png8(header(0x88, 0x00), rw, rh)));
            CHECK_FALSE(bool(read_png8(header(0x77, 0x00), rw, rh)));
            std::string check = z;
            check[1] = char(check[1] ^ 1);
            CHECK_FALSE(bool(read_png8(with_stream(w, h, colour, check, idat), rw, rh)));
        }
    }
}

// The filtered rows `raw` as a zlib stream in parts: deflated at `level`, each part
// but the last ended by `flush` (Z_SYNC_FLUSH or Z_FULL_FLUSH), each part an IDAT chunk.
std::string png_parts(int w, int h, const std::string& raw, const std::vector<std::size_t>& cuts, int flush,
                      int level = 6) {
    z_stream zs{};
    REQUIRE(deflateInit(&zs, level) == Z_OK);
    std::vector<std::string> parts;
    std::size_t from = 0;
    for (std::size_t k = 0; k <= cuts.size(); ++k) {
        const std::size_t to = k < cuts.size() ? cuts[k] : raw.size();
        std::string part(deflateBound(&zs, uLong(to - from)) + 64, '\0');
        zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(raw.data() + from));
        zs.avail_in = uInt(to - from);
        zs.next_out = reinterpret_cast<Bytef*>(&part[0]);
        zs.avail_out = uInt(part.size());
        const int rc = deflate(&zs, k < cuts.size() ? flush : Z_FINISH);
        REQUIRE((rc == Z_OK || rc == Z_STREAM_END || rc == Z_BUF_ERROR));  // (the last: an empty part flushed again)
        part.resize(part.size() - zs.avail_out);
        parts.push_back(part);
        from = to;
    }
    deflateEnd(&zs);
    std::string out = "\x89PNG\r\n\x1a\n";
    png_chunk(out, "IHDR", png_ihdr(std::uint32_t(w), std::uint32_t(h), 8, 2));
    for (const std::string& part : parts) png_chunk(out, "IDAT", part);
    png_chunk(out, "IEND", "");
    return out;
}

// Rows of filter type 0 (none) holding `px`, w RGB pixels each.
std::string unfiltered_rows(int w, int h, const std::vector<unsigned char>& px) {
    std::string raw;
    for (int y = 0; y < h; ++y) {
        raw += '\0';
        raw.append(reinterpret_cast<const char*>(px.data()) + std::size_t(y) * w * 3, std::size_t(w) * 3);
    }
    return raw;
}

TEST_CASE("png reader: chunks ending in sync flushes inflated piece by piece, or strung together where they cannot be") {
    const int w = 40, h = 30;
    const std::size_t line = std::size_t(w) * 3 + 1;
    // Smooth (each piece's copy fits after the output so far), and noise (it does not:
    // strung together).
    std::vector<unsigned char> px(std::size_t(w) * h * 3), noise = pattern(px.size(), 31);
    for (std::size_t i = 0; i < px.size(); ++i) px[i] = static_cast<unsigned char>(i / 3 % 40 + i / 360);
    for (const std::vector<unsigned char>* p : {&px, &noise}) {
        // The pieces independent (a full flush forgets the window).
        same_as_stb(png_parts(w, h, unfiltered_rows(w, h, *p), {line * 7, line * 19}, Z_FULL_FLUSH));
        // Empty chunks (no flush at their end: strung together), and cuts in the middle
        // of a row with a last piece too small to leave room for the copy of the one
        // before it (strung together too).
        same_as_stb(png_parts(w, h, unfiltered_rows(w, h, *p), {0, 5, 5, line * 29 + 3}, Z_FULL_FLUSH));
        same_as_stb(png_parts(w, h, unfiltered_rows(w, h, *p), {5, line * 29 + 3}, Z_FULL_FLUSH));
    }
    px = pattern(px.size(), 31);
    // The same rows over again: after a sync flush, the second piece copies from the
    // first (its window is kept), which a piece alone cannot; strung together instead.
    std::vector<unsigned char> twice(px.begin(), px.begin() + std::ptrdiff_t(px.size() / 2));
    twice.insert(twice.end(), twice.begin(), twice.end());
    same_as_stb(png_parts(w, h, unfiltered_rows(w, h, twice), {line * 15}, Z_SYNC_FLUSH));
    // Stored blocks whose data holds "00 00 ff ff" where a chunk ends, not a flush: the
    // piece would read on past it, and is not taken.
    {
        std::vector<unsigned char> marks(px.size(), 0);
        for (std::size_t i = 0; i + 4 <= marks.size(); i += 40) marks[i + 2] = marks[i + 3] = 0xff;
        const std::string raw = unfiltered_rows(w, h, marks);
        std::string png = png_parts(w, h, raw, {}, Z_FULL_FLUSH, 0);
        const std::size_t data = 8 + 25 + 8;  // the one IDAT's data
        const std::size_t len = be32_of(png, 8 + 25);
        const std::string z = png.substr(data, len);
        // Cut after a "00 00 ff ff" of the pixels, well inside the stored block.
        const std::size_t cut = z.find(std::string("\0\0\xff\xff", 4), 200) + 4;
        REQUIRE(cut < z.size() - 100);
        std::string split = "\x89PNG\r\n\x1a\n";
        png_chunk(split, "IHDR", png_ihdr(std::uint32_t(w), std::uint32_t(h), 8, 2));
        png_chunk(split, "IDAT", z.substr(0, cut));
        png_chunk(split, "IDAT", z.substr(cut));
        png_chunk(split, "IEND", "");
        same_as_stb(split);
    }
    // In pieces too, a wrong Adler-32 or none: left to stb_image.
    {
        const std::string good = png_parts(w, h, unfiltered_rows(w, h, px), {line * 10}, Z_FULL_FLUSH);
        const std::size_t adler = good.size() - 12 - 4 - 4;  // the last IDAT's last 4 data bytes
        std::string bad = good;
        bad[adler + 3] = char(bad[adler + 3] ^ 1);
        int rw = 0, rh = 0;
        REQUIRE(bool(read_png8(good, rw, rh)));
        CHECK_FALSE(bool(read_png8(bad, rw, rh)));
    }
}

TEST_CASE("png reader: what it leaves to stb_image, which decodes or refuses it as before") {
    const std::vector<unsigned char> rgb = pattern(9 * 7 * 3, 3);
    const std::string good = png_filtered(9, 7, 2, rgb, 4);
    int w = 0, h = 0;
    REQUIRE(bool(read_png8(good, w, h)));

    const auto left = [&](const std::string& bytes) {
        int lw = 0, lh = 0;
        CHECK_FALSE(bool(read_png8(bytes, lw, lh)));
    };
    // Transparency: stb_image's own reading.
    std::string trns;
    png_chunk(trns, "tRNS", std::string("\0\1\0\2\0\3", 6));
    const std::string with_trns = png_filtered(9, 7, 2, rgb, 0, 100, trns);
    left(with_trns);
    {
        const StbImage want = stb(with_trns);
        REQUIRE(bool(want.p));
        std::string error;
        auto t = decode_texture(with_trns, error);
        REQUIRE(bool(t));
        CHECK(std::memcmp(t->srgb8(), want.p.get(), 9 * 7 * 3) == 0);
    }
    // A wrong Adler-32 (stb_image does not check it: it decodes the image).
    {
        std::string z = good;
        const std::size_t iend = z.size() - 12, adler = iend - 4 - 4;  // last 4 data bytes of the IDAT
        z[adler] = char(z[adler] ^ 0x55);
        left(z);
        std::string error;
        auto t = decode_texture(z, error);
        const StbImage want = stb(z);
        CHECK(bool(t) == bool(want.p));
        if (t && want.p) CHECK(std::memcmp(t->srgb8(), want.p.get(), 9 * 7 * 3) == 0);
    }
    // 16 bits, interlaced, an unknown critical chunk, a filter type of 5, too few rows,
    // no IEND: none is this reader's.
    left(rt_test::png_raw(3, 2, 16, 2, std::vector<unsigned char>(3 * 2 * 6, 7)));
    {
        std::string z = good;
        z[8 + 8 + 12] = 1;  // IHDR's interlace byte
        left(z);
    }
    {
        std::string unknown;
        png_chunk(unknown, "ABCD", "x");
        const std::string z = png_filtered(9, 7, 2, rgb, 0, 100, unknown);
        left(z);
        std::string error;
        CHECK_FALSE(bool(decode_texture(z, error)));
        CHECK(error.find("cannot be decoded") != std::string::npos);
    }
    {
        std::string raw(7 * 28, '\0');  // 7 rows of 28 bytes, the first with filter type 5
        raw[0] = 5;
        uLongf n = compressBound(uLong(raw.size()));
        std::string zz(n, '\0');
        compress(reinterpret_cast<Bytef*>(&zz[0]), &n, reinterpret_cast<const Bytef*>(raw.data()), uLong(28 * 7));
        zz.resize(n);
        std::string z = "\x89PNG\r\n\x1a\n";
        png_chunk(z, "IHDR", png_ihdr(9, 7, 8, 2));
        png_chunk(z, "IDAT", zz);
        png_chunk(z, "IEND", "");
        left(z);
        std::string error;
        CHECK_FALSE(bool(decode_texture(z, error)));
        CHECK(error.find("invalid filter") != std::string::npos);
        // Too short a stream: 6 rows of 7.
        zz.assign(compressBound(uLong(28 * 6)), '\0');
        n = uLongf(zz.size());
        std::string rows(28 * 6, '\0');
        compress(reinterpret_cast<Bytef*>(&zz[0]), &n, reinterpret_cast<const Bytef*>(rows.data()), uLong(rows.size()));
        zz.resize(n);
        z = "\x89PNG\r\n\x1a\n";
        png_chunk(z, "IHDR", png_ihdr(9, 7, 8, 2));
        png_chunk(z, "IDAT", zz);
        png_chunk(z, "IEND", "");
        left(z);
        CHECK_FALSE(bool(decode_texture(z, error)));
        CHECK(error.find("not enough pixels") != std::string::npos);
    }
    left(good.substr(0, good.size() - 12));  // no IEND
    left(good.substr(0, 40));
    left("");
    // A palette image without a PLTE before its data.
    left(png_filtered(4, 4, 3, std::vector<unsigned char>(16, 1)));
}

TEST_CASE("png reader: the small PNGs of tests/textures (every colour type, rows in all five filters)") {
    for (const char* name : {"grey", "rgb", "palette", "grey-alpha", "rgba"}) {
        CAPTURE(name);
        std::string bytes, error;
        FILE* f = std::fopen((std::string(RT_SOURCE_DIR "/tests/textures/filters-") + name + ".png").c_str(), "rb");
        REQUIRE(f != nullptr);
        char buf[4096];
        for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;) bytes.append(buf, n);
        std::fclose(f);
        same_as_stb(bytes);
    }
}

// Found by fuzz_texture: the file ends in a chunk header (its CRC cut off) claiming
// 2 GB of IDAT, which stb_image allocated before it read any. Refused at the header.
TEST_CASE("png reader: a last chunk header claiming more than the file holds is refused before stb_image") {
    std::string found;
    FILE* f = std::fopen(RT_SOURCE_DIR "/tests/fuzz/regressions/png-last-header-claims-2gb", "rb");
    REQUIRE(f != nullptr);
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;) found.append(buf, n);
    std::fclose(f);
    std::string error;
    CHECK_FALSE(bool(decode_texture(found, error)));
    CHECK(error.find("truncated") != std::string::npos);
    // A file whose IEND lacks only its CRC is still read, as stb_image reads it.
    const std::string good = png_filtered(5, 4, 2, pattern(5 * 4 * 3, 2));
    CHECK(bool(decode_texture(good.substr(0, good.size() - 4), error)));
}
