// A frame's repaint boxes against the last frame (see frame_damage.h).
#include "frame_damage.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <set>

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
// beginning and before the common end, old and new. Where as many changed as were
// there (a colour, a highlight), each pair that differs is a box of its own.
void changed_boxes(const DrawTriangles& before, const DrawTriangles& now, std::vector<PixelBox>& out) {
    const std::size_t n0 = before.size() / 3, n1 = now.size() / 3, n = std::min(n0, n1);
    std::size_t head = 0, tail = 0;
    while (head < n && same_triangle(before, head, now, head)) ++head;
    if (head == n0 && head == n1) return;
    while (tail < n - head && same_triangle(before, n0 - 1 - tail, now, n1 - 1 - tail)) ++tail;
    if (n0 != n1) {
        out.push_back(unite(triangles_box(before, head, n0 - tail), triangles_box(now, head, n1 - tail)));
        return;
    }
    for (std::size_t i = head; i < n0 - tail; ++i)
        if (!same_triangle(before, i, now, i)) out.push_back(unite(triangle_box(&before[3 * i]), triangle_box(&now[3 * i])));
}

void texture_boxes(const DrawTriangles& list, const std::vector<TextureChange>& changes, std::vector<PixelBox>& out) {
    for (std::size_t i = 0; i + 2 < list.size(); i += 3)
        for (const TextureChange& c : changes)
            if (list[i].texture == c.texture) {
                const PixelBox b = texel_box(&list[i], c);
                if (!b.empty()) out.push_back(b);
            }
}

// The boxes of the lists that changed, came or went; false if the lists kept are not
// in the same order, or two share a name.
bool list_boxes(const std::vector<DrawTriangles>& before, const std::vector<DrawTriangles>& now,
                std::vector<PixelBox>& out) {
    std::map<std::uint64_t, std::size_t> old_at;  // id -> index in `before`
    for (std::size_t i = 0; i < before.size(); ++i)
        if (!old_at.emplace(before[i].id, i).second) return false;
    std::set<std::uint64_t> seen;
    std::size_t last_old = 0;
    bool any = false;
    for (const DrawTriangles& l : now) {
        if (!seen.insert(l.id).second) return false;
        auto it = old_at.find(l.id);
        if (it == old_at.end()) {
            out.push_back(triangles_box(l, 0, l.size() / 3));  // came
            continue;
        }
        if (any && it->second < last_old) return false;  // reordered
        last_old = it->second, any = true;
        changed_boxes(before[it->second], l, out);
    }
    for (const DrawTriangles& l : before)
        if (!seen.count(l.id)) out.push_back(triangles_box(l, 0, l.size() / 3));  // went
    return true;
}

// At most FrameDamage::kMaxBoxes boxes: the two whose union adds the fewest pixels
// joined, again and again (too many to weigh: all of them in one).
void reduce_boxes(std::vector<PixelBox>& boxes) {
    if (boxes.size() > 64) {
        PixelBox all;
        for (const PixelBox& b : boxes) all = unite(all, b);
        boxes.assign(1, all);
    }
    while (int(boxes.size()) > FrameDamage::kMaxBoxes) {
        std::size_t bi = 0, bj = 1;
        std::int64_t best = -1;
        for (std::size_t i = 0; i < boxes.size(); ++i)
            for (std::size_t j = i + 1; j < boxes.size(); ++j) {
                const std::int64_t added = unite(boxes[i], boxes[j]).area() - boxes[i].area() - boxes[j].area();
                if (best < 0 || added < best) best = added, bi = i, bj = j;
            }
        boxes[bi] = unite(boxes[bi], boxes[bj]);
        boxes.erase(boxes.begin() + std::ptrdiff_t(bj));
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
    reduce_boxes(out);
    std::int64_t area = 0;
    for (const PixelBox& b : out) area += b.area();
    if (double(area) > FrameDamage::kWholeShare * double(window.area())) out.assign(1, window);
    return out;
}

std::vector<PixelBox> FrameDamage::compare(std::vector<DrawTriangles> lists, int width, int height,
                                           const std::vector<TextureChange>& changes) {
    std::vector<PixelBox> boxes;
    const bool whole = !valid_ || width != width_ || height != height_ || !list_boxes(last_, lists, boxes);
    if (!whole)
        for (const DrawTriangles& l : lists) texture_boxes(l, changes, boxes);
    last_ = std::move(lists);
    width_ = width;
    height_ = height;
    valid_ = true;
    if (whole) return {PixelBox{0, 0, width, height}};
    return merge_boxes(std::move(boxes), width, height);
}

}  // namespace rtview
