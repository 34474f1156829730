// Image textures for the materials' `texture` key and the models' map_Kd: PNG and
// JPEG files (read with stb_image) decoded once, sampled bilinearly and repeating; a
// store that decodes each file once however many materials name it, and again only
// when it changes on disk. An 8-bit image keeps its sRGB bytes (3 a texel) and reads
// them through a 256-entry table of their linear values: a quarter of the memory of
// floats, and the very same numbers.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "file_cache.h"
#include "file_id.h"
#include "math.h"

namespace rt {

struct TextureLimits {
    static constexpr std::uint64_t max_file_size = std::uint64_t(1) << 28;  // bytes
    static constexpr int max_side = 16384;                                  // pixels, either side
    // Texels of one image (3 bytes each for 8-bit images, 12 for 16-bit ones): 1.5 GB
    // at most.
    static constexpr std::uint64_t max_texels = std::uint64_t(1) << 27;
    static constexpr std::size_t max_files = 10000;  // distinct texture files in a scene
    // Texels of all the textures of one scene (or one model's MTL files): 3 GB at most.
    static constexpr std::uint64_t max_scene_texels = std::uint64_t(1) << 28;
};

class Texture;
std::shared_ptr<Texture> read_texture(const std::string& path, std::string& error, bool later);

// A decoded image: width x height texels, rows from the top, linear RGB (the file's
// sRGB values decoded; grey spread to the three channels, alpha dropped).
class Texture {
public:
    // From linear texels, 3 floats each, rows from the top (missing ones black).
    Texture(int width, int height, std::vector<float> rgb, std::string path = {});
    // From 8-bit sRGB texels, 3 bytes each, rows from the top (missing ones black).
    Texture(int width, int height, std::vector<std::uint8_t> srgb, std::string path = {});
    // The same from `srgb` (width * height * 3 bytes), kept and released with `free`.
    Texture(int width, int height, std::uint8_t* srgb, void (*free)(void*));
    Texture(const Texture&) = delete;
    Texture& operator=(const Texture&) = delete;
    int width() const { return width_; }
    int height() const { return height_; }
    const std::string& path() const { return path_; }  // as resolved; "" when made from data
    // A texture read with `later` (read_texture) is decoded on a thread of the process's
    // pool while its reader goes on: wait() returns once its texels are there (decoding
    // them on the caller's thread if no worker has begun), with "" or the reason they
    // could not be decoded (then every texel reads black). Any thread may wait, any
    // number of times; texel() and sample() wait first themselves.
    std::string wait() const;
    bool decoded() const { return ready_.load(std::memory_order_acquire); }
    // Texel (x, y), y from the top row; x and y wrap around.
    Colour texel(long x, long y) const;
    // The bilinear mix of the four texels around (u, v), the texture repeating: u runs
    // left to right and v bottom to top over [0, 1) (texel centres at (i + 1/2) / size).
    // Not-finite coordinates read as 0.
    Colour sample(double u, double v) const;
    // Whether the file is still the one read (size, modification time, inode); always
    // true for a texture made from data.
    bool unchanged_on_disk() const;
    // The file's identity as read (unknown for a texture made from data).
    const FileId& file_id() const { return id_; }
    // (These two after wait().)
    std::size_t memory_bytes() const { return srgb_ ? texel_count() * 3 : rgb_.size() * sizeof(float); }
    // The linear texels, 3 floats each, rows from the top (to send a texture elsewhere).
    std::vector<float> texels() const;
    // The sRGB bytes, 3 a texel, of an 8-bit image; null for one of floats.
    const std::uint8_t* srgb8() const { return srgb_.get(); }

    // The linear value of each 8-bit sRGB level: float(srgb_to_linear(i / 255.0)).
    static const float* srgb8_table();

private:
    friend std::shared_ptr<Texture> read_texture(const std::string& path, std::string& error, bool later);
    struct Later;  // the decoding still to do
    Texture(int width, int height, std::shared_ptr<Later> later);
    static void decode_later(const std::shared_ptr<Texture>& t);
    std::size_t texel_count() const { return std::size_t(width_) * std::size_t(height_); }
    int width_, height_;
    std::shared_ptr<Later> later_;
    std::atomic<bool> ready_{true};
    std::vector<float> rgb_;                    // linear texels (16-bit images, made from floats)
    std::shared_ptr<const std::uint8_t> srgb_;  // or 8-bit sRGB ones
    std::string path_;
    FileId id_;  // of the file as read
};

// The image file's bytes decoded (PNG or JPEG; 8 or 16 bits; grey, grey+alpha, RGB,
// RGBA). Refuses, before any texel is allocated, an image whose header claims more
// than the limits allow. Null with `error` set otherwise.
std::shared_ptr<Texture> decode_texture(std::string_view bytes, std::string& error);
// The size a PNG or JPEG header claims, read without decoding (true: w and h set;
// false: not a PNG or JPEG header stb_image can read).
bool image_size(std::string_view bytes, long long& w, long long& h);
// The same from a file: only a regular file within the size limit is read (a folder,
// a device or a FIFO is refused at once, never waited on). With `later`, only the
// file's header and structure are checked here, and the texture's texels decoded on
// the process's pool meanwhile (see Texture::wait(): it says whether they could be).
std::shared_ptr<Texture> read_texture(const std::string& path, std::string& error, bool later = false);

// The textures read so far, by resolved path; each kept only while something holds it.
// Safe to use from several threads.
class TextureStore {
public:
    struct Loaded {
        std::shared_ptr<const Texture> texture;  // null on error
        std::string error;
    };
    // With `later`, a texture whose file is sound is returned before its texels are
    // decoded (read_texture's `later`): its holder calls wait() before it trusts it.
    Loaded load(const std::string& path, bool later = false);

private:
    FileCache<Texture, std::string> cache_;
};

// sRGB-encoded v in [0, 1] to linear (IEC 61966-2-1).
double srgb_to_linear(double v);

}  // namespace rt
