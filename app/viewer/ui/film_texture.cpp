// Film texture upload and framebuffer read-back (see film_texture.h).
#include "film_texture.h"

#include <GL/gl.h>

#include <algorithm>
#include <cstring>

#include "frame_paint.h"
#include "image_io.h"

namespace rtview {

FilmTexture::~FilmTexture() { release(); }

void FilmTexture::release() {
    if (tex_) glDeleteTextures(1, &tex_);
    tex_ = 0;
    width_ = height_ = 0;
    nearest_ = -1;
}

void FilmTexture::upload(const std::vector<std::uint8_t>& rgba, int width, int height, const std::array<int, 4>& rect) {
    if (width < 1 || height < 1 || rgba.size() < std::size_t(width) * height * 4) return;
    if (!tex_) {
        glGenTextures(1, &tex_);
        glBindTexture(GL_TEXTURE_2D, tex_);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        nearest_ = -1;
    }
    glBindTexture(GL_TEXTURE_2D, tex_);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    if (width != width_ || height != height_) {
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
        width_ = width;
        height_ = height;
        note_texture_change(tex_, width, height, {0, 0, width, height});
    } else if (rect[0] < rect[2] && rect[1] < rect[3]) {
        // Same size: update what changed in place.
        int x0 = std::max(rect[0], 0), y0 = std::max(rect[1], 0);
        int x1 = std::min(rect[2], width), y1 = std::min(rect[3], height);
        if (x0 < x1 && y0 < y1) {
            glPixelStorei(GL_UNPACK_ROW_LENGTH, width);
            glTexSubImage2D(GL_TEXTURE_2D, 0, x0, y0, x1 - x0, y1 - y0, GL_RGBA, GL_UNSIGNED_BYTE,
                            rgba.data() + 4 * (std::size_t(y0) * width + x0));
            glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
            note_texture_change(tex_, width, height, {x0, y0, x1, y1});
        }
    }
    if (nearest_ < 0) set_nearest(true);
}

void FilmTexture::set_nearest(bool nearest) {
    if (!tex_ || nearest_ == int(nearest)) return;
    glBindTexture(GL_TEXTURE_2D, tex_);
    GLint f = nearest ? GL_NEAREST : GL_LINEAR;
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, f);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, f);
    nearest_ = int(nearest);
    note_texture_change(tex_, width_, height_, {0, 0, width_, height_});
}

std::vector<std::uint8_t> read_framebuffer(int width, int height) {
    std::vector<std::uint8_t> rgb(std::size_t(width) * height * 3);
    if (rgb.empty()) return rgb;
    glFinish();
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
    // GL's origin is the bottom-left corner; images start at the top.
    std::size_t row = std::size_t(width) * 3;
    std::vector<std::uint8_t> tmp(row);
    for (int y = 0; y < height / 2; ++y) {
        std::uint8_t* a = rgb.data() + row * y;
        std::uint8_t* b = rgb.data() + row * (height - 1 - y);
        std::memcpy(tmp.data(), a, row);
        std::memcpy(a, b, row);
        std::memcpy(b, tmp.data(), row);
    }
    return rgb;
}

rt::Status save_framebuffer(const std::string& path, int width, int height) {
    const rt::ImageFormat f = rt::format_from_path(path);
    if (f == rt::ImageFormat::Unknown || rt::is_float_format(f))
        return rt::Status::error("'" + path + "': a screenshot is a .png or .ppm", rt::kExitUsage);
    return rt::write_rgb8(path, width, height, read_framebuffer(width, height));
}

}  // namespace rtview
