// A frame's repaint boxes against the last frame (see frame_damage.h).
#include "frame_damage.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace rtview {

namespace {

bool same_triangle(const DrawTriangles& a, std::size_t i, const DrawTriangles& b, std::size_t j) {
    return a[3 * i] == b[3 * j] && a[3 * i + 1] == b[3 * j + 1] && a[3 * i + 2] == b[3 * j + 2];
}

PixelBox unite(const PixelBox& a, const PixelBox& b) {
    if (a.empty()) return b;
    if (b.empty()) return a;
    return {std::min(a.x0, b.x0), std::min(a.y0, b.y0), std::max(a.x1, b.x1), std::max(a.y1, b.y1)};
}

PixelBox intersect(const PixelBox& a, const PixelBox& b) {
    return {std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1), std::min(a.y1, b.y1)};
}

// Overlapping or side by side.
bool touch(const PixelBox& a, const PixelBox& b) {
    return a.x0 <= b.x1 && b.x0 <= a.x1 && a.y0 <= b.y1 && b.y0 <= a.y1;
}

int floor_int(float v) { return int(std::clamp(std::floor(v), -1e9f, 1e9f)); }
int ceil_int(float v) { return int(std::clamp(std::ceil(v), -1e9f, 1e9f)); }

// Pixels around the float box {x0, y0, x1, y1}, a pixel's margin included.
PixelBox around(float x0, float y0, float x1, float y1) {
    return {floor_int(x0) - 1, floor_int(y0) - 1, ceil_int(x1) + 1, ceil_int(y1) + 1};
}

PixelBox triangles_box(const DrawTriangles& t, std::size_t from, std::size_t to) {
    PixelBox b;
    for (std::size_t i = from; i < to; ++i) b = unite(b, triangle_box(&t[3 * i]));
    return b;
}

// The triangles of `now` that differ from `before`'s: those after the common
// beginning and before the common end, old and new.
PixelBox changed_box(const DrawTriangles& before, const DrawTriangles& now) {
    const std::size_t n0 = before.size() / 3, n1 = now.size() / 3, n = std::min(n0, n1);
    std::size_t head = 0, tail = 0;
    while (head < n && same_triangle(before, head, now, head)) ++head;
    if (head == n0 && head == n1) return {};
    while (tail < n - head && same_triangle(before, n0 - 1 - tail, now, n1 - 1 - tail)) ++tail;
    return unite(triangles_box(before, head, n0 - tail), triangles_box(now, head, n1 - tail));
}

void texture_boxes(const DrawTriangles& list, const std::vector<TextureChange>& changes, std::vector<PixelBox>& out) {
    for (std::size_t i = 0; i + 2 < list.size(); i += 3)
        for (const TextureChange& c : changes)
            if (list[i].texture == c.texture) {
                const PixelBox b = texel_box(&list[i], c);
                if (!b.empty()) out.push_back(b);
            }
}

}  // namespace

bool DrawVertex::operator==(const DrawVertex& o) const {
    return x == o.x && y == o.y && u == o.u && v == o.v && colour == o.colour && texture == o.texture &&
           std::memcmp(clip, o.clip, sizeof clip) == 0;
}

PixelBox triangle_box(const DrawVertex* t) {
    const float x0 = std::min({t[0].x, t[1].x, t[2].x}), x1 = std::max({t[0].x, t[1].x, t[2].x});
    const float y0 = std::min({t[0].y, t[1].y, t[2].y}), y1 = std::max({t[0].y, t[1].y, t[2].y});
    const float* c = t[0].clip;  // the scissor: no margin
    const PixelBox clip{floor_int(c[0]), floor_int(c[1]), ceil_int(c[2]), ceil_int(c[3])};
    return intersect(around(x0, y0, x1, y1), clip);
}

PixelBox texel_box(const DrawVertex* t, const TextureChange& c) {
    // Texture coordinates -> position is affine over a triangle: uv = uv0 + a f1 + b f2
    // gives position p0 + a e1 + b e2.
    const double f1u = t[1].u - t[0].u, f1v = t[1].v - t[0].v, f2u = t[2].u - t[0].u, f2v = t[2].v - t[0].v;
    const double e1x = t[1].x - t[0].x, e1y = t[1].y - t[0].y, e2x = t[2].x - t[0].x, e2y = t[2].y - t[0].y;
    const double det = f1u * f2v - f1v * f2u;
    if (std::fabs(det) < 1e-12) return triangle_box(t);  // one texel stretched: all of it
    float x0 = 1e30f, y0 = 1e30f, x1 = -1e30f, y1 = -1e30f;
    for (int k = 0; k < 4; ++k) {
        const double du = (k & 1 ? c.u1 : c.u0) - t[0].u, dv = (k & 2 ? c.v1 : c.v0) - t[0].v;
        const double a = (du * f2v - dv * f2u) / det, b = (f1u * dv - f1v * du) / det;
        const float x = float(t[0].x + a * e1x + b * e2x), y = float(t[0].y + a * e1y + b * e2y);
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
    return intersect(around(x0, y0, x1, y1), triangle_box(t));
}

std::vector<PixelBox> merge_boxes(std::vector<PixelBox> boxes, int width, int height) {
    const PixelBox window{0, 0, width, height};
    std::vector<PixelBox> out;
    for (const PixelBox& b : boxes) {
        PixelBox m = intersect(b, window);
        if (m.empty()) continue;
        // Whatever it touches joins it, and the union may touch more.
        for (std::size_t i = 0; i < out.size();) {
            if (touch(out[i], m)) {
                m = unite(m, out[i]);
                out.erase(out.begin() + std::ptrdiff_t(i));
                i = 0;
            } else {
                ++i;
            }
        }
        out.push_back(m);
    }
    if (int(out.size()) > FrameDamage::kMaxBoxes) {
        PixelBox all;
        for (const PixelBox& b : out) all = unite(all, b);
        out.assign(1, all);
    }
    std::int64_t area = 0;
    for (const PixelBox& b : out) area += b.area();
    if (double(area) > FrameDamage::kWholeShare * double(window.area())) out.assign(1, window);
    return out;
}

std::vector<PixelBox> FrameDamage::compare(std::vector<DrawTriangles> lists, int width, int height,
                                           const std::vector<TextureChange>& changes) {
    const bool whole = !valid_ || width != width_ || height != height_ || lists.size() != last_.size();
    std::vector<PixelBox> boxes;
    if (!whole) {
        for (std::size_t i = 0; i < lists.size(); ++i) {
            const PixelBox b = changed_box(last_[i], lists[i]);
            if (!b.empty()) boxes.push_back(b);
        }
        for (const DrawTriangles& l : lists) texture_boxes(l, changes, boxes);
    }
    last_ = std::move(lists);
    width_ = width;
    height_ = height;
    valid_ = true;
    if (whole) return {PixelBox{0, 0, width, height}};
    return merge_boxes(std::move(boxes), width, height);
}

}  // namespace rtview
