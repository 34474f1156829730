// Texture files (see texture.h). Only PNG and JPEG are let through to stb_image (by
// their signatures: its other formats, TGA above all, would take almost any bytes),
// and only after stbi_info has read the header and the size it claims is within the
// limits, so a hostile header cannot make it allocate.
#include "texture.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <stb/stb_image.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <climits>
#include <cmath>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>

#include "parallel.h"
#include "png_read.h"

namespace rt {

double srgb_to_linear(double v) {
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

const float* Texture::srgb8_table() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int i = 0; i < 256; ++i) t[std::size_t(i)] = float(srgb_to_linear(i / 255.0));
        return t;
    }();
    return table.data();
}

Texture::Texture(int width, int height, std::vector<float> rgb, std::string path)
    : width_(std::max(width, 1)), height_(std::max(height, 1)), rgb_(std::move(rgb)), path_(std::move(path)) {
    rgb_.resize(texel_count() * 3, 0.0f);
}

Texture::Texture(int width, int height, std::vector<std::uint8_t> srgb, std::string path)
    : width_(std::max(width, 1)), height_(std::max(height, 1)), path_(std::move(path)) {
    auto bytes = std::make_shared<std::vector<std::uint8_t>>(std::move(srgb));
    bytes->resize(texel_count() * 3, 0);  // (level 0 is linear 0: black, as for floats)
    srgb_ = std::shared_ptr<const std::uint8_t>(bytes, bytes->data());
}

Texture::Texture(int width, int height, std::uint8_t* srgb, void (*free)(void*))
    : width_(std::max(width, 1)), height_(std::max(height, 1)),
      srgb_(srgb, [free](const std::uint8_t* p) { free(const_cast<std::uint8_t*>(p)); }) {}

// The decoding of a texture read with `later`.
struct Texture::Later {
    std::mutex mutex;
    std::condition_variable done;
    int state = 0;      // 0: not begun, 1: being decoded, 2: done
    std::string bytes;  // the file's (until decoded)
    std::string error;  // why it could not be (once done)
};

Texture::Texture(int width, int height, std::shared_ptr<Later> later)
    : width_(width), height_(height), later_(std::move(later)), ready_(false) {}

namespace {
std::shared_ptr<Texture> decode_checked(std::string_view bytes, long long w, long long h, std::string& error);
}

// Decodes t's bytes unless another thread has begun to.
void Texture::decode_later(const std::shared_ptr<Texture>& t) {
    Later& l = *t->later_;
    {
        std::lock_guard<std::mutex> lock(l.mutex);
        if (l.state != 0) return;
        l.state = 1;
    }
    std::string error;
    std::shared_ptr<Texture> d;
    try {
        d = decode_checked(l.bytes, t->width_, t->height_, error);
    } catch (...) {
        error = "cannot be decoded";
    }
    if (d) t->rgb_ = std::move(d->rgb_), t->srgb_ = std::move(d->srgb_);
    std::string().swap(l.bytes);
    t->ready_.store(true, std::memory_order_release);
    std::lock_guard<std::mutex> lock(l.mutex);
    l.error = std::move(error);
    l.state = 2;
    l.done.notify_all();
}

std::string Texture::wait() const {
    if (!later_) return {};
    std::unique_lock<std::mutex> lock(later_->mutex);
    if (later_->state == 0) {
        lock.unlock();
        // No worker has begun: decoded here. (`this` was made by read_texture, held by
        // a shared_ptr, and never const itself.)
        std::shared_ptr<Texture> self(std::shared_ptr<Texture>{}, const_cast<Texture*>(this));
        decode_later(self);
        lock.lock();
    }
    later_->done.wait(lock, [&] { return later_->state == 2; });
    return later_->error;
}

std::vector<float> Texture::texels() const {
    if (!decoded()) wait();
    if (!srgb_) return rgb_;
    const float* t = srgb8_table();
    const std::uint8_t* s = srgb_.get();
    std::vector<float> rgb(texel_count() * 3);
    for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = t[s[i]];
    return rgb;
}

Colour Texture::texel(long x, long y) const {
    if (!decoded()) wait();
    if (!srgb_ && rgb_.empty()) return {};  // could not be decoded
    x %= width_;
    y %= height_;
    if (x < 0) x += width_;
    if (y < 0) y += height_;
    const std::size_t i = 3 * (std::size_t(y) * std::size_t(width_) + std::size_t(x));
    if (srgb_) {
        const float* t = srgb8_table();
        const std::uint8_t* p = srgb_.get() + i;
        return {t[p[0]], t[p[1]], t[p[2]]};
    }
    const float* p = &rgb_[i];
    return {p[0], p[1], p[2]};
}

namespace {

// The bilinear mix of four texels (at offsets i00..i11 of the texel array) read by
// `at` (offset to Colour).
template <class At>
Colour mix4(const At& at, std::size_t i00, std::size_t i10, std::size_t i01, std::size_t i11, double ax, double ay) {
    const Colour c00 = at(i00), c10 = at(i10), c01 = at(i01), c11 = at(i11);
    return (c00 * (1 - ax) + c10 * ax) * (1 - ay) + (c01 * (1 - ax) + c11 * ax) * ay;
}

}  // namespace

Colour Texture::sample(double u, double v) const {
    if (!decoded()) wait();
    if (!srgb_ && rgb_.empty()) return {};  // could not be decoded
    if (!std::isfinite(u)) u = 0;
    if (!std::isfinite(v)) v = 0;
    // Into [0, 1] first (1 only by rounding, for a tiny negative u), so that the texel
    // coordinates below stay small: x0 in [-1, width - 1], x0 + 1 in [0, width].
    u -= std::floor(u);
    v -= std::floor(v);
    const double x = u * width_ - 0.5, y = (1 - v) * height_ - 0.5;
    const double fx = std::floor(x), fy = std::floor(y);
    const double ax = x - fx, ay = y - fy;
    long x0 = long(fx), y0 = long(fy), x1 = x0 + 1, y1 = y0 + 1;
    // Wrapped around without a division (texel() wraps any coordinate).
    if (x0 < 0) x0 += width_;
    if (y0 < 0) y0 += height_;
    if (x1 >= width_) x1 -= width_;
    if (y1 >= height_) y1 -= height_;
    const std::size_t w = std::size_t(width_);
    const std::size_t r0 = std::size_t(y0) * w, r1 = std::size_t(y1) * w;
    const std::size_t i00 = 3 * (r0 + std::size_t(x0)), i10 = 3 * (r0 + std::size_t(x1)),
                      i01 = 3 * (r1 + std::size_t(x0)), i11 = 3 * (r1 + std::size_t(x1));
    if (srgb_) {
        const float* t = srgb8_table();
        const std::uint8_t* s = srgb_.get();
        const auto at = [t, s](std::size_t i) { return Colour{t[s[i]], t[s[i + 1]], t[s[i + 2]]}; };
        return mix4(at, i00, i10, i01, i11, ax, ay);
    }
    const float* f = rgb_.data();
    const auto at = [f](std::size_t i) { return Colour{f[i], f[i + 1], f[i + 2]}; };
    return mix4(at, i00, i10, i01, i11, ax, ay);
}

bool Texture::unchanged_on_disk() const { return FileId::unchanged(path_, id_); }

namespace {

bool is_png(std::string_view b) { return b.size() >= 8 && std::memcmp(b.data(), "\x89PNG\r\n\x1a\n", 8) == 0; }
bool is_jpeg(std::string_view b) {
    return b.size() >= 3 && std::memcmp(b.data(), "\xff\xd8\xff", 3) == 0;
}

std::string reason() {
    const char* r = stbi_failure_reason();
    return r ? r : "unknown";
}

// Whether every Huffman table of a JPEG's DHT segments holds at most 256 codes. The
// stb_image of Debian 12 does not check that, and writes past its tables for one that
// claims more (found by fuzz_texture): such files are refused before it sees them.
// Only the segment structure is followed, to the entropy-coded data's markers; what
// else is wrong is left to stb_image.
// Also refused: a scan using a Huffman table no DHT segment before it defined, which
// stb_image would decode with tables of whatever its memory held.
bool jpeg_tables_ok(std::string_view b) {
    const auto byte = [&](std::size_t i) { return i < b.size() ? static_cast<unsigned char>(b[i]) : 0u; };
    bool defined[2][4] = {};  // [DC, AC][table]
    bool progressive = false;
    std::size_t i = 2;  // past SOI
    while (i + 4 <= b.size()) {
        if (byte(i) != 0xff) {
            ++i;  // entropy-coded data (or junk): look for the next marker
            continue;
        }
        const unsigned m = byte(i + 1);
        // Fill bytes, stuffed zeros and restart markers stand alone.
        if (m == 0xff || m == 0x00 || (m >= 0xd0 && m <= 0xd8) || m == 0x01) {
            i += m == 0xff ? 1 : 2;
            continue;
        }
        if (m == 0xd9) return true;  // EOI
        const std::size_t len = std::size_t(byte(i + 2)) << 8 | byte(i + 3);
        if (len < 2) return true;
        if (m == 0xc2) progressive = true;
        if (m == 0xc4) {
            // As stb_image reads it: tables while the segment's length lasts, each
            // one's 16 counts read even past the segment's end (0 past the file's).
            long left = long(len) - 2;
            std::size_t t = i + 4;
            while (left > 0) {
                const unsigned q = byte(t);
                if ((q >> 4) > 1 || (q & 15) > 3) return true;  // stb_image refuses it
                std::size_t n = 0;
                for (std::size_t k = 1; k <= 16; ++k) n += byte(t + k);
                if (n > 256) return false;
                defined[q >> 4][q & 15] = true;
                t += 17 + n;
                left -= long(17 + n);
            }
            if (left != 0) return true;  // stb_image stops at such a segment
        }
        if (m == 0xda) {
            // The tables each component of the scan decodes with: baseline scans
            // both; progressive ones the DC table in a first DC scan, the AC table
            // in an AC scan.
            const unsigned n = byte(i + 4);
            const std::size_t after = i + 5 + 2 * std::size_t(n);
            const unsigned ss = byte(after), ah = byte(after + 2) >> 4;
            for (unsigned c = 0; c < n && c < 4; ++c) {
                const unsigned t = byte(i + 6 + 2 * c), dc = t >> 4, ac = t & 15;
                if (dc > 3 || ac > 3) return true;  // stb_image refuses it
                const bool need_dc = !progressive || (ss == 0 && ah == 0), need_ac = !progressive || ss != 0;
                if ((need_dc && !defined[0][dc]) || (need_ac && !defined[1][ac])) return false;
            }
        }
        i += 2 + len;
    }
    return true;
}

// Whether every chunk of a PNG up to IEND lies within the file. stb_image allocates
// the room a data chunk claims (up to 2 GB) before it reads the chunk, so a few bytes
// claiming a huge one are refused before it sees them (found by fuzz_texture).
// That holds for the last chunk's header too when its CRC is cut off (found by
// fuzz_texture: 8 bytes claiming 2 GB of IDAT at the file's end).
bool png_chunks_ok(std::string_view b) {
    std::size_t i = 8;
    while (i + 8 <= b.size()) {
        std::uint64_t len = 0;
        for (std::size_t k = 0; k < 4; ++k) len = len << 8 | static_cast<unsigned char>(b[i + k]);
        const std::size_t rest = b.size() - i;
        if (rest >= 12 ? len > rest - 12 : len > rest - 8) return false;
        if (b.compare(i + 4, 4, "IEND") == 0) return true;
        i += 12 + std::size_t(len);
    }
    return true;  // no IEND: stb_image says what is missing
}

bool too_large(long long w, long long h) {
    return w > TextureLimits::max_side || h > TextureLimits::max_side ||
           std::uint64_t(w) * std::uint64_t(h) > TextureLimits::max_texels;
}

struct StbFree {
    void operator()(void* p) const { stbi_image_free(p); }
};

}  // namespace

bool image_size(std::string_view bytes, long long& w, long long& h) {
    w = h = 0;
    if (bytes.size() > std::size_t(INT_MAX)) return false;
    // A PNG's size is read here first: stb refuses big ones without saying the size.
    if (is_png(bytes) && bytes.size() >= 24 && bytes.compare(12, 4, "IHDR") == 0) {
        auto be32 = [&](std::size_t at) {
            std::uint32_t v = 0;
            for (std::size_t k = 0; k < 4; ++k) v = v << 8 | static_cast<unsigned char>(bytes[at + k]);
            return v;
        };
        w = be32(16), h = be32(20);
        if (too_large(w, h)) return true;
    }
    int iw = 0, ih = 0, comp = 0;
    if (!(is_png(bytes) || (is_jpeg(bytes) && jpeg_tables_ok(bytes))) ||
        !stbi_info_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), int(bytes.size()), &iw, &ih, &comp))
        return false;
    w = iw, h = ih;
    return true;
}

namespace {

// decode_texture()'s checks of the bytes before stb_image may decode them: true with
// the image's size in w and h.
bool check_image(std::string_view bytes, std::string& error, long long& w, long long& h) {
    error.clear();
    if (bytes.empty()) {
        error = "the file is empty, not an image";
        return false;
    }
    const bool png = is_png(bytes), jpeg = is_jpeg(bytes);
    if (!png && !jpeg) {
        error = "not a PNG or JPEG image";
        return false;
    }
    if (bytes.size() > std::size_t(INT_MAX)) {
        error = "file too large";
        return false;
    }
    if (png && !png_chunks_ok(bytes)) {
        error = "not a readable PNG image (truncated: a chunk runs past the end of the file)";
        return false;
    }
    if (jpeg && !jpeg_tables_ok(bytes)) {
        error = "not a readable JPEG image (a Huffman table of more than 256 codes, or a scan using one not "
                "defined)";
        return false;
    }
    const char* kind = png ? "PNG" : "JPEG";
    if (!image_size(bytes, w, h)) {
        error = std::string("not a readable ") + kind + " image (" + reason() + ")";
        return false;
    }
    if (w <= 0 || h <= 0 || too_large(w, h)) {
        error = "image of " + std::to_string(w) + " x " + std::to_string(h) + " pixels is too large (limit " +
                std::to_string(TextureLimits::max_side) + " pixels a side, " +
                std::to_string(TextureLimits::max_texels) + " pixels in all)";
        return false;
    }
    return true;
}

// The bytes that check_image() let through, of an image of w x h, decoded.
std::shared_ptr<Texture> decode_checked(std::string_view bytes, long long w, long long h, std::string& error) {
    const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
    const int len = int(bytes.size());
    const char* kind = is_png(bytes) ? "PNG" : "JPEG";
    const std::size_t n = std::size_t(w) * std::size_t(h);
    std::vector<float> rgb;
    try {
        int x = 0, y = 0, c = 0;
        // The common PNGs by the project's own reader (the same bytes, twice as fast);
        // what it does not take, stb_image decodes or refuses as before.
        if (std::unique_ptr<std::uint8_t, PngFree> p = read_png8(bytes, x, y); p && x == w && y == h) {
            auto t = std::make_shared<Texture>(int(w), int(h), p.get(), &std::free);
            p.release();
            return t;
        }
        if (stbi_is_16_bit_from_memory(data, len)) {
            std::unique_ptr<stbi_us, StbFree> p(stbi_load_16_from_memory(data, len, &x, &y, &c, 3));
            if (!p || x != w || y != h) {
                error = std::string("the ") + kind + " image cannot be decoded (" + (p ? "size changed" : reason()) + ")";
                return nullptr;
            }
            rgb.resize(3 * n);
            for (std::size_t i = 0; i < 3 * n; ++i) rgb[i] = float(srgb_to_linear(p.get()[i] / 65535.0));
        } else {
            std::unique_ptr<stbi_uc, StbFree> p(stbi_load_from_memory(data, len, &x, &y, &c, 3));
            if (!p || x != w || y != h) {
                error = std::string("the ") + kind + " image cannot be decoded (" + (p ? "size changed" : reason()) + ")";
                return nullptr;
            }
            // stb_image's own buffer, kept: the bytes as they are, no copy.
            auto t = std::make_shared<Texture>(int(w), int(h), p.get(), &stbi_image_free);
            p.release();
            return t;
        }
    } catch (const std::bad_alloc&) {
        error = "not enough memory for an image of " + std::to_string(w) + " x " + std::to_string(h) + " pixels";
        return nullptr;
    }
    return std::make_shared<Texture>(int(w), int(h), std::move(rgb));
}

}  // namespace

std::shared_ptr<Texture> decode_texture(std::string_view bytes, std::string& error) {
    long long w = 0, h = 0;
    if (!check_image(bytes, error, w, h)) return nullptr;
    return decode_checked(bytes, w, h, error);
}

std::shared_ptr<Texture> read_texture(const std::string& path, std::string& error, bool later) {
    // Non-blocking: a FIFO must not stop the open (it is refused below).
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
    if (fd < 0) {
        error = std::strerror(errno);
        return nullptr;
    }
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    struct stat st;
    if (::fstat(fd, &st) != 0) {
        error = std::strerror(errno);
        return nullptr;
    }
    if (S_ISDIR(st.st_mode)) {
        error = "is a folder, not an image file";
        return nullptr;
    }
    if (!S_ISREG(st.st_mode)) {
        error = "is not a regular file (a device, pipe or socket); textures are read from files";
        return nullptr;
    }
    if (std::uint64_t(st.st_size) > TextureLimits::max_file_size) {
        error = "file too large (" + std::to_string(st.st_size) + " bytes, limit " +
                std::to_string(TextureLimits::max_file_size) + ")";
        return nullptr;
    }
    std::string bytes;
    try {
        bytes.resize(std::size_t(st.st_size));
    } catch (const std::bad_alloc&) {
        error = "not enough memory to read it";
        return nullptr;
    }
    std::size_t got = 0;
    while (got < bytes.size()) {
        const ssize_t r = ::read(fd, &bytes[got], bytes.size() - got);
        if (r < 0 && errno == EINTR) continue;
        if (r < 0) {
            error = std::strerror(errno);
            return nullptr;
        }
        if (r == 0) break;  // shrank while being read: what is there is the file
        got += std::size_t(r);
    }
    bytes.resize(got);
    std::shared_ptr<Texture> t;
    if (later) {
        long long w = 0, h = 0;
        if (!check_image(bytes, error, w, h)) return nullptr;
        auto l = std::make_shared<Texture::Later>();
        l->bytes = std::move(bytes);
        t.reset(new Texture(int(w), int(h), std::move(l)));
    } else {
        t = decode_texture(bytes, error);
    }
    if (t) {
        t->path_ = path;
        t->id_ = FileId::of(st);
    }
    if (later && t) {
        // On a worker while the caller goes on (or now, when the pool has none). The
        // task holds the texture, so it may outlive every other holder.
        ThreadPool& pool = process_pool();
        if (pool.workers() > 0)
            pool.post([t] { Texture::decode_later(t); });
        else
            Texture::decode_later(t);
    }
    return t;
}

TextureStore::Loaded TextureStore::load(const std::string& path, bool later) {
    Loaded result;
    // A texture read with `later` by an earlier load is waited for here (unless this
    // one is a `later` too); its late failure is this load's error.
    const auto waited = [&](Loaded& r) {
        if (later || !r.texture) return;
        if (std::string e = r.texture->wait(); !e.empty()) r = {nullptr, std::move(e)};
    };
    struct stat st {};
    const FileId id = ::stat(path.c_str(), &st) == 0 ? FileId::of(st) : FileId{};
    if (cache_.find(path, id, result.texture, result.error)) {
        waited(result);
        return result;
    }
    // Decoded outside the cache's lock: another thread may read another file meanwhile.
    std::shared_ptr<Texture> t = read_texture(path, result.error, later);
    // A FIFO or device is never kept: its stat says nothing of what it would give. The
    // version kept is the one decoded, should the file have changed since the stat.
    cache_.store(path, t ? t->file_id() : id, t, result.error, id.known() && S_ISREG(st.st_mode));
    result.texture = std::move(t);
    waited(result);
    return result;
}

}  // namespace rt
