// The PNG reader of png_read.h. The chunks are walked as stb_image walks them (the
// CRCs unread, ancillary chunks skipped); the IDAT chunks' data is inflated by
// libdeflate into one buffer of the filtered rows: from the file's own bytes when there
// is one chunk, piece by piece when each chunk ends in a sync flush, else strung
// together. An RGB image is unfiltered in that buffer, each row moved down over the
// filter bytes before it, so the buffer becomes the texels without a second copy; the
// other kinds are unfiltered row by row and spread to three bytes a texel. The stream's
// Adler-32 is summed row by row just before each row is unfiltered (one pass over the
// buffer for both, where a separate sum would read all of it from memory once more).
#include "png_read.h"

#include <libdeflate.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "texture.h"

namespace rt {

void PngFree::operator()(std::uint8_t* p) const { std::free(p); }

namespace {

std::uint32_t be32(const unsigned char* p) {
    return std::uint32_t(p[0]) << 24 | std::uint32_t(p[1]) << 16 | std::uint32_t(p[2]) << 8 | p[3];
}

int paeth(int a, int b, int c) {
    const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
    if (pa <= pb && pa <= pc) return a;
    return pb <= pc ? b : c;
}

// The Sub filter of an RGB row from its start: how many bytes it did (the rest is the
// caller's). Five pixels (15 bytes) a step: the prefix sums of the step's pixels by
// three shifted adds, plus the step before's last pixel in every pixel's place. Byte
// 15 of each 16-byte store is the source's own, so with dst below src (unfilter()'s
// in-place use) nothing is written where src is still to be read.
std::size_t sub_rgb(const std::uint8_t* src, std::uint8_t* dst, std::size_t stride) {
    std::size_t i = 0;
#if defined(__SSE2__)
    const __m128i keep = _mm_setr_epi8(0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, -1);
    const __m128i low3 = _mm_setr_epi8(-1, -1, -1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0);
    __m128i carry = _mm_setzero_si128();
    for (; i + 16 <= stride; i += 15) {
        const __m128i raw = _mm_loadu_si128(reinterpret_cast<const __m128i*>(src + i));
        __m128i x = _mm_andnot_si128(keep, raw);
        x = _mm_add_epi8(x, _mm_slli_si128(x, 3));
        x = _mm_add_epi8(x, _mm_slli_si128(x, 6));
        x = _mm_add_epi8(x, _mm_slli_si128(x, 12));
        x = _mm_add_epi8(x, carry);
        _mm_storeu_si128(reinterpret_cast<__m128i*>(dst + i),
                         _mm_or_si128(_mm_andnot_si128(keep, x), _mm_and_si128(keep, raw)));
        __m128i last = _mm_and_si128(_mm_srli_si128(x, 12), low3);
        last = _mm_or_si128(last, _mm_slli_si128(last, 3));
        last = _mm_or_si128(last, _mm_slli_si128(last, 6));
        carry = _mm_or_si128(last, _mm_slli_si128(last, 12));
    }
#else
    (void)src, (void)dst, (void)stride;
#endif
    return i;
}

// One row of `stride` bytes with filter f unfiltered from src into dst, prev the
// unfiltered row above (null for the first row: zeros), bpp bytes a pixel. dst may
// lie below src in the same buffer (dst <= src): each byte of src is read before the
// byte of dst at the same index is written, and never after. False for a filter type
// above 4.
bool unfilter(unsigned f, const std::uint8_t* src, const std::uint8_t* prev, std::uint8_t* dst, std::size_t stride,
              std::size_t bpp) {
    const std::size_t first = bpp < stride ? bpp : stride;
    switch (f) {
    case 0:
        std::memmove(dst, src, stride);
        return true;
    case 1: {
        const std::size_t done = bpp == 3 ? sub_rgb(src, dst, stride) : 0;
        for (std::size_t i = done; i < first; ++i) dst[i] = src[i];
        for (std::size_t i = std::max(done, bpp); i < stride; ++i) dst[i] = std::uint8_t(src[i] + dst[i - bpp]);
        return true;
    }
    case 2:
        if (!prev) {
            std::memmove(dst, src, stride);
        } else {
            for (std::size_t i = 0; i < stride; ++i) dst[i] = std::uint8_t(src[i] + prev[i]);
        }
        return true;
    case 3:
        if (!prev) {
            for (std::size_t i = 0; i < first; ++i) dst[i] = src[i];
            for (std::size_t i = bpp; i < stride; ++i) dst[i] = std::uint8_t(src[i] + (dst[i - bpp] >> 1));
        } else {
            for (std::size_t i = 0; i < first; ++i) dst[i] = std::uint8_t(src[i] + (prev[i] >> 1));
            for (std::size_t i = bpp; i < stride; ++i)
                dst[i] = std::uint8_t(src[i] + ((dst[i - bpp] + prev[i]) >> 1));
        }
        return true;
    case 4:
        if (!prev) {  // Paeth of (a, 0, 0) is a: Sub
            for (std::size_t i = 0; i < first; ++i) dst[i] = src[i];
            for (std::size_t i = bpp; i < stride; ++i) dst[i] = std::uint8_t(src[i] + dst[i - bpp]);
        } else {
            for (std::size_t i = 0; i < first; ++i) dst[i] = std::uint8_t(src[i] + prev[i]);
            for (std::size_t i = bpp; i < stride; ++i)
                dst[i] = std::uint8_t(src[i] + paeth(dst[i - bpp], prev[i], prev[i - bpp]));
        }
        return true;
    default:
        return false;
    }
}

struct Decompressor {
    libdeflate_decompressor* d = libdeflate_alloc_decompressor();
    ~Decompressor() {
        if (d) libdeflate_free_decompressor(d);
    }
};

using Buffer = std::unique_ptr<std::uint8_t, PngFree>;

Buffer allocate(std::size_t n) { return Buffer(static_cast<std::uint8_t*>(std::malloc(n ? n : 1))); }

// What the chunks say: the header's fields, the palette and where the IDAT chunks'
// data lies in the file. False for a file this reader leaves to stb_image.
struct Chunks {
    std::uint32_t width = 0, height = 0;
    unsigned colour = 0;
    std::uint8_t palette[256 * 3] = {};  // indices past the PLTE's entries read black
    std::vector<std::string_view> idat;  // each chunk's data, in the file's order
};

bool read_chunks(const unsigned char* b, std::size_t size, Chunks& out) {
    if (size < 8 || std::memcmp(b, "\x89PNG\r\n\x1a\n", 8) != 0) return false;
    bool have_palette = false, seen_idat = false;
    std::size_t i = 8;
    for (bool first = true; i + 12 <= size; first = false) {
        const std::uint32_t len = be32(b + i);
        const unsigned char* type = b + i + 4;
        if (len > size - i - 12) return false;
        const unsigned char* c = b + i + 8;
        const auto is = [&](const char* t) { return std::memcmp(type, t, 4) == 0; };
        if (first != is("IHDR")) return false;
        if (is("IHDR")) {
            if (len != 13) return false;
            out.width = be32(c), out.height = be32(c + 4), out.colour = c[9];
            // 8 bits; grey, RGB, palette, grey+alpha, RGBA; deflate; filter method 0;
            // not interlaced.
            const unsigned k = out.colour;
            if (c[8] != 8 || !(k == 0 || k == 2 || k == 3 || k == 4 || k == 6) || c[10] != 0 || c[11] != 0 ||
                c[12] != 0)
                return false;
        } else if (is("PLTE")) {
            if (have_palette || seen_idat || len == 0 || len > 256 * 3 || len % 3 != 0) return false;
            std::memcpy(out.palette, c, len);
            have_palette = true;
        } else if (is("IDAT")) {
            if (out.colour == 3 && !have_palette) return false;
            seen_idat = true;
            out.idat.emplace_back(reinterpret_cast<const char*>(c), len);
        } else if (is("IEND")) {
            return seen_idat && out.width > 0 && out.height > 0 &&
                   out.width <= std::uint32_t(TextureLimits::max_side) &&
                   out.height <= std::uint32_t(TextureLimits::max_side) &&
                   std::uint64_t(out.width) * out.height <= TextureLimits::max_texels;
        } else if (is("tRNS") || !(type[0] & 0x20)) {
            return false;  // transparency, or a critical chunk this reader does not know
        }
        i += 12 + std::size_t(len);
    }
    return false;  // no IEND
}

// The rows r (each after its filter byte, `line` bytes apart) of a grey, grey+alpha,
// RGBA or palette image, n bytes a pixel, unfiltered and spread to 3 bytes a texel;
// `adler` summed over the filtered rows.
Buffer spread(const Chunks& k, std::uint8_t* r, std::size_t n, std::size_t line, std::uint32_t& adler) {
    const std::size_t width = k.width, stride = width * n;
    Buffer out = allocate(width * k.height * 3);
    if (!out) return nullptr;
    for (std::size_t y = 0; y < k.height; ++y) {
        // Unfiltered in place (dst == src) after the row above, whose bytes stay.
        std::uint8_t* row = r + y * line + 1;
        adler = std::uint32_t(libdeflate_adler32(adler, row - 1, line));
        if (!unfilter(row[-1], row, y ? row - line : nullptr, row, stride, n)) return nullptr;
        std::uint8_t* o = out.get() + y * width * 3;
        for (std::size_t x = 0; x < width; ++x, o += 3) {
            const std::uint8_t* p = row + x * n;
            if (k.colour == 3) {
                std::memcpy(o, k.palette + 3 * std::size_t(p[0]), 3);
            } else if (n <= 2) {
                o[0] = o[1] = o[2] = p[0];
            } else {
                o[0] = p[0], o[1] = p[1], o[2] = p[2];
            }
        }
    }
    return out;
}

// A zlib header libdeflate's zlib reader takes: deflate with a window of at most 32 KB,
// its check bits right, no preset dictionary.
bool zlib_header(std::string_view z) {
    if (z.size() < 2) return false;
    const unsigned cmf = std::uint8_t(z[0]), flg = std::uint8_t(z[1]);
    return (cmf & 15) == 8 && (cmf >> 4) <= 7 && (cmf * 256 + flg) % 31 == 0 && !(flg & 0x20);
}

// Whether a stream filled its rows exactly, and the Adler-32 it ends in.
struct Inflated {
    bool ok = false;
    std::uint32_t adler = 0;  // the one the stream ends in
};

// Inflates `z` (a zlib stream) into out, which it must fill exactly.
Inflated inflate_whole(libdeflate_decompressor* d, std::string_view z, std::uint8_t* out, std::size_t size) {
    std::size_t used = 0, got = 0;
    // The stream must fill the rows exactly (stb_image takes a longer one; it is
    // left to it) and end in its Adler-32 (checked by the caller, which stb_image does not).
    if (!zlib_header(z) ||
        libdeflate_deflate_decompress_ex(d, z.data() + 2, z.size() - 2, out, size, &used, &got) != LIBDEFLATE_SUCCESS ||
        got != size || z.size() - 2 - used < 4)
        return {};
    return {true, be32(reinterpret_cast<const unsigned char*>(z.data()) + 2 + used)};
}

// Whether chunk data c ends as a sync flush does (the length fields of an empty stored block).
bool sync_flushed(std::string_view c) {
    return c.size() >= 4 && c.substr(c.size() - 4) == std::string_view("\0\0\xff\xff", 4);
}

// The stream inflated without stringing its chunks together, where every chunk but the
// last ends in a sync flush (an empty stored block, byte-aligned: png.cpp's strips,
// as in the bench's textures) and no piece refers back into the one before: each
// piece but the last is copied, with an empty final block after it ("03 00"), to the
// end of `out` (space its own output cannot reach yet) and inflated from there; the
// last straight from the file. A piece must be taken whole, up to that final block, or
// nothing is: a "00 00 ff ff" that was not a flush stops it (and the caller's Adler-32
// check catches the rest).
Inflated inflate_pieces(libdeflate_decompressor* d, const Chunks& k, std::uint8_t* out, std::size_t size) {
    const std::vector<std::string_view>& c = k.idat;
    if (c.size() < 2 || c[0].size() < 2 || !zlib_header(c[0])) return {};
    for (std::size_t i = 0; i + 1 < c.size(); ++i)
        if (!sync_flushed(c[i])) return {};
    std::size_t at = 0;  // where the next piece's output goes
    for (std::size_t i = 0; i + 1 < c.size(); ++i) {
        const std::string_view piece = i == 0 ? c[0].substr(2) : c[i];
        const std::size_t len = piece.size() + 2;
        if (len > size - at) return {};
        std::uint8_t* copy = out + size - len;
        std::memcpy(copy, piece.data(), piece.size());
        copy[len - 2] = 3, copy[len - 1] = 0;
        std::size_t used = 0, got = 0;
        const libdeflate_result r =
                libdeflate_deflate_decompress_ex(d, copy, len, out + at, size - len - at, &used, &got);
        if (r != LIBDEFLATE_SUCCESS || used != len) return {};
        at += got;
    }
    const std::string_view last = c.back();
    std::size_t used = 0, got = 0;
    if (libdeflate_deflate_decompress_ex(d, last.data(), last.size(), out + at, size - at, &used, &got) !=
                LIBDEFLATE_SUCCESS ||
        got != size - at || last.size() - used < 4)
        return {};
    return {true, be32(reinterpret_cast<const unsigned char*>(last.data()) + used)};
}

// The IDAT chunks' stream inflated into out (size bytes, to be filled exactly): in
// pieces where it can be, else the file's own bytes when there is one chunk, else the
// chunks' data strung together.
Inflated inflate_idat(libdeflate_decompressor* d, const Chunks& k, std::uint8_t* out, std::size_t size) {
    if (k.idat.size() == 1) return inflate_whole(d, k.idat[0], out, size);
    if (Inflated pieces = inflate_pieces(d, k, out, size); pieces.ok) return pieces;
    std::string joined;
    std::size_t total = 0;
    for (std::string_view c : k.idat) total += c.size();
    joined.reserve(total);
    for (std::string_view c : k.idat) joined += c;
    return inflate_whole(d, joined, out, size);
}

}  // namespace

std::unique_ptr<std::uint8_t, PngFree> read_png8(std::string_view bytes, int& w, int& h) {
    Chunks k;
    if (!read_chunks(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(), k)) return nullptr;
    const std::size_t n = k.colour == 0 ? 1 : k.colour == 2 ? 3 : k.colour == 3 ? 1 : k.colour == 4 ? 2 : 4;
    const std::size_t stride = std::size_t(k.width) * n, line = stride + 1, raw_size = line * k.height;
    Decompressor inflater;
    if (!inflater.d) return nullptr;
    Buffer raw = allocate(raw_size);
    if (!raw) return nullptr;
    const Inflated z = inflate_idat(inflater.d, k, raw.get(), raw_size);
    if (!z.ok) return nullptr;
    std::uint8_t* r = raw.get();
    std::uint32_t adler = 1;
    if (k.colour != 2) {
        raw = spread(k, r, n, line, adler);
    } else {
        // In place: row y's bytes move down by y + 1 (its and the rows' above filter bytes).
        for (std::size_t y = 0; y < k.height; ++y) {
            std::uint8_t* dst = r + y * stride;
            adler = std::uint32_t(libdeflate_adler32(adler, r + y * line, line));
            if (!unfilter(r[y * line], r + y * line + 1, y ? dst - stride : nullptr, dst, stride, 3)) return nullptr;
        }
    }
    if (adler != z.adler) return nullptr;
    if (raw) w = int(k.width), h = int(k.height);
    return raw;
}

}  // namespace rt
