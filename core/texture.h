// Image textures for the materials' `texture` key and the models' map_Kd: PNG and
// JPEG files (read with stb_image) decoded once into linear-RGB texels, sampled
// bilinearly and repeating; a store that decodes each file once however many
// materials name it, and again only when it changes on disk.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "file_id.h"
#include "math.h"

namespace rt {

struct TextureLimits {
    static constexpr std::uint64_t max_file_size = std::uint64_t(1) << 28;  // bytes
    static constexpr int max_side = 16384;                                  // pixels, either side
    // Texels of one image (12 bytes each once decoded): 1.5 GB at most.
    static constexpr std::uint64_t max_texels = std::uint64_t(1) << 27;
    static constexpr std::size_t max_files = 10000;  // distinct texture files in a scene
    // Texels of all the textures of one scene (or one model's MTL files): 3 GB at most.
    static constexpr std::uint64_t max_scene_texels = std::uint64_t(1) << 28;
};

class Texture;
std::shared_ptr<Texture> read_texture(const std::string& path, std::string& error);

// A decoded image: width x height texels, rows from the top, linear RGB (the file's
// sRGB values decoded; grey spread to the three channels, alpha dropped).
class Texture {
public:
    Texture(int width, int height, std::vector<float> rgb, std::string path = {});
    int width() const { return width_; }
    int height() const { return height_; }
    const std::string& path() const { return path_; }  // as resolved; "" when made from data
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
    std::size_t memory_bytes() const { return rgb_.size() * sizeof(float); }
    // The texels, 3 floats each, rows from the top (to send a texture elsewhere).
    const std::vector<float>& texels() const { return rgb_; }

private:
    friend std::shared_ptr<Texture> read_texture(const std::string& path, std::string& error);
    int width_, height_;
    std::vector<float> rgb_;
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
// a device or a FIFO is refused at once, never waited on).
std::shared_ptr<Texture> read_texture(const std::string& path, std::string& error);

// The textures read so far, by resolved path; each kept only while something holds it.
// Safe to use from several threads.
class TextureStore {
public:
    struct Loaded {
        std::shared_ptr<const Texture> texture;  // null on error
        std::string error;
    };
    Loaded load(const std::string& path);

private:
    struct Entry {
        FileId id;
        std::weak_ptr<const Texture> texture;
        std::string error;  // the last reading's, when it failed
        bool failed = false;
    };
    std::mutex mutex_;
    std::map<std::string, Entry> entries_;
};

// sRGB-encoded v in [0, 1] to linear (IEC 61966-2-1).
double srgb_to_linear(double v);

}  // namespace rt
