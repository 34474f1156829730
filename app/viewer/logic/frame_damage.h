// What of the window a frame must repaint: the parts where its drawing differs from
// the last frame's, and where a texture it shows changed. A software rasteriser
// (Mesa's llvmpipe) spends its time per pixel drawn: at 2560x1600 a whole frame costs
// it some 40 ms of processor time, while a frame of a render in progress changes
// only the status bar and the picture's new rows. Repainting those alone (the rest of
// the back buffer kept) gives the same pixels, since a pixel's value depends only on
// the triangles that cover it, in order.
//
// A frame is described as the triangles of its draw lists in drawing order, each
// vertex with its clip rectangle and texture, in framebuffer pixels (top row 0). Lists
// are matched by their window's name: a list that came (a tooltip, a popup) or went
// is repainted whole; within a list kept, the triangles after the common beginning and
// before the common end changed, and their boxes (the old ones' and the new ones')
// are repainted. Lists kept in another order repaint the window. Textures whose contents changed (uploaded rows) are mapped through the
// triangles that show them.
#pragma once

#include <cstdint>
#include <vector>

namespace rtview {

// Pixels [x0, x1) x [y0, y1), top row 0.
struct PixelBox {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool empty() const { return x1 <= x0 || y1 <= y0; }
    std::int64_t area() const { return empty() ? 0 : std::int64_t(x1 - x0) * (y1 - y0); }
    bool operator==(const PixelBox& o) const { return x0 == o.x0 && y0 == o.y0 && x1 == o.x1 && y1 == o.y1; }
};

// One vertex of a triangle as drawn: position, texture coordinates, colour, the clip
// rectangle {x0, y0, x1, y1} and the texture.
struct DrawVertex {
    float x = 0, y = 0, u = 0, v = 0;
    std::uint32_t colour = 0;
    float clip[4] = {0, 0, 0, 0};
    std::uint64_t texture = 0;
    bool operator==(const DrawVertex& o) const;
};

// A draw list: its window's name (hashed) and triangles, three vertices each.
struct DrawTriangles : std::vector<DrawVertex> {
    using std::vector<DrawVertex>::vector;
    std::uint64_t id = 0;
};

// Texels of a texture that changed, in texture coordinates (0..1), already widened by
// what filtering spreads them over.
struct TextureChange {
    std::uint64_t texture = 0;
    float u0 = 0, v0 = 0, u1 = 0, v1 = 0;
};

class FrameDamage {
public:
    // This frame (width x height pixels, its lists in drawing order) against the last
    // one: the boxes to repaint (none: the screen shows this frame already; one box
    // of the whole window: everything). Keeps this frame for the next comparison.
    std::vector<PixelBox> compare(std::vector<DrawTriangles> lists, int width, int height,
                                  const std::vector<TextureChange>& changes);
    // The next frame is repainted whole (the window was exposed, a font texture made).
    void invalidate() { valid_ = false; }

    // Beyond this share of the window, or this many boxes, one box of the whole.
    static constexpr double kWholeShare = 0.6;
    static constexpr int kMaxBoxes = 6;

private:
    std::vector<DrawTriangles> last_;
    int width_ = 0, height_ = 0;
    bool valid_ = false;
};

// The boxes merged where they overlap or touch, clipped to the window; the whole
// window when they cover most of it or are too many.
std::vector<PixelBox> merge_boxes(std::vector<PixelBox> boxes, int width, int height);
// The pixels a triangle (three vertices) may cover, within its clip rectangle.
PixelBox triangle_box(const DrawVertex* t);
// The pixels of a triangle that show texels {u0, v0, u1, v1} of its texture.
PixelBox texel_box(const DrawVertex* t, const TextureChange& c);

}  // namespace rtview
