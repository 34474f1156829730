// The film as one OpenGL texture, and reading the finished frame back for
// screenshots. Plain GL 1.1 calls: they resolve against libGL in the window binary
// and against libOSMesa in the headless one.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "status.h"

namespace rtview {

class FilmTexture {
public:
    FilmTexture() = default;
    ~FilmTexture();
    FilmTexture(const FilmTexture&) = delete;
    FilmTexture& operator=(const FilmTexture&) = delete;

    // RGBA8, top row first (ImGui draws with the texture's v = 0 at the top). When the
    // texture already has this size, only the rectangle {x0, y0, x1, y1} is sent.
    void upload(const std::vector<std::uint8_t>& rgba, int width, int height, const std::array<int, 4>& rect);
    // Nearest filtering when shown 1:1, so every screen pixel is exactly one film pixel.
    void set_nearest(bool nearest);
    void release();
    bool valid() const { return tex_ != 0 && width_ > 0; }
    void* id() const { return reinterpret_cast<void*>(static_cast<std::uintptr_t>(tex_)); }
    int width() const { return width_; }
    int height() const { return height_; }

private:
    unsigned tex_ = 0;
    int width_ = 0, height_ = 0;
    int nearest_ = -1;
};

// RGB8 of the current read framebuffer, top row first.
std::vector<std::uint8_t> read_framebuffer(int width, int height);
// Reads the framebuffer and writes PNG or PPM (by extension).
rt::Status save_framebuffer(const std::string& path, int width, int height);

}  // namespace rtview
