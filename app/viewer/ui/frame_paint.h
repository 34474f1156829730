// Painting ImGui's draw data into the current GL framebuffer: the whole frame, or
// only the boxes where it differs from the last frame painted (frame_damage.h), which
// needs a back buffer that keeps its pixels between frames (the window presents
// boxes with GLX_MESA_copy_sub_buffer, see glx_present.h).
#pragma once

#include <cstdint>
#include <vector>

#include "frame_damage.h"

struct ImDrawData;

namespace rtview {

// The window's background, where no panel or picture covers it.
constexpr float kClearColour[4] = {0.10f, 0.10f, 0.11f, 1.f};

// A texture's texels {x0, y0, x1, y1} changed (film_texture.cpp calls it for every
// upload and filter change).
void note_texture_change(std::uint64_t texture, int width, int height, const PixelBox& texels);

class FramePainter {
public:
    // With `partial`, a frame repaints only what changed; without, the whole of it.
    // With `check` too, every partial frame is read back, painted whole, read back
    // again and compared (slow: for tests), and a difference said on stderr.
    explicit FramePainter(bool partial, bool check = false) : partial_(partial), check_(check) {}
    // Paints this frame's draw data into a width x height framebuffer; returns the
    // boxes painted (none: the back buffer already shows this frame).
    const std::vector<PixelBox>& paint(ImDrawData* data, int width, int height);
    // The next frame is painted whole.
    void invalidate() { damage_.invalidate(); }
    bool partial() const { return partial_; }
    // With `check`: partial frames compared, and how many differed from whole ones.
    long checked() const { return checked_; }
    long differed() const { return differed_; }

private:
    void check(ImDrawData* data, int width, int height);

    bool partial_, check_;
    long checked_ = 0, differed_ = 0;
    FrameDamage damage_;
    std::vector<PixelBox> boxes_;
};

// The whole frame, as the headless binary paints every one.
void paint_whole(ImDrawData* data, int width, int height);

}  // namespace rtview
