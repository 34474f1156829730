// The selection outline: an object-id buffer of the primary hits (what pick() finds
// along each texel's sample ray, at the block size of the picture on screen) and the
// borders between the selected item's texels and the rest, as line segments for an
// overlay. Only the texels whose ray can reach the item (its projected bounds) are
// traced. No GL: unit-tested.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "camera.h"
#include "scene_edits.h"
#include "world.h"

namespace rtview {

// A pick result as one number (rt::pick_id): 0 nothing, else (index + 1) * 4 + kind
// (1 object, 2 plane, 3 lamp glow).
std::uint32_t id_code(const rt::PickResult& r);
std::uint32_t id_code(const SceneItem& item);

// Ids of the texels [x0, x1) x [y0, y1) of a film traced one ray per block x block
// block (the rays of the preview and coarse passes of that block; block 1: the
// pixels' own sample-0 rays). Texels outside the window are 0.
struct IdBuffer {
    int block = 1;
    int width = 0, height = 0;  // texels: ceil(film / block)
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    std::vector<std::uint32_t> ids;  // width * height
    std::uint32_t at(int x, int y) const {
        return x < 0 || y < 0 || x >= width || y >= height ? 0 : ids[std::size_t(y) * std::size_t(width) + std::size_t(x)];
    }
};

// The texel window (at `block`) that can see `item`: its bounds' projection plus a
// texel, or the whole film when that cannot be told (planes, bounds behind the eye).
// Empty (x0 == x1) when the item is wholly off screen or does not exist.
void item_window(const rt::World& world, const rt::Camera& camera, int film_w, int film_h, int block,
                 const SceneItem& item, int& x0, int& y0, int& x1, int& y1);

// A selected CSG operand's outline is its own silhouette, not the whole CSG's (a
// subtracted operand shows as the hole it carves and the part of it that is hidden):
// a world of that operand alone, as object 0, whose ids the outline traces. Null when
// `sel` names no operand of an object of `scene`.
std::shared_ptr<const rt::World> operand_world(const rt::Scene& scene, const ItemRef& sel);

// Fills `out` for that window: an id pass of rt::Renderer (RenderPass::Ids) cropped to
// it, on the process pool's workers while this thread waits. Returns the number of
// rays traced.
std::size_t trace_ids(const rt::World& world, const rt::Camera& camera, int film_w, int film_h, int block, int x0,
                      int y0, int x1, int y1, IdBuffer& out);

// A horizontal or vertical segment between texel corners (texel units).
struct Edge {
    int x0, y0, x1, y1;
};
// The borders of the region of texels holding `code`, joined into runs.
std::vector<Edge> outline_edges(const IdBuffer& ids, std::uint32_t code);

// A segment in texel units, where corners are cut at fractions of a texel.
struct Segment {
    float x0, y0, x1, y1;
};
// An outline's edges as drawn: each corner where exactly two edges meet at a right
// angle is cut by a diagonal from half a texel before it (at most half of the shorter
// edge) to as far after it. A staircase of single texels becomes a straight diagonal,
// a box gets chamfered corners, a curve loses its steps; junctions of three or four
// edges (the border between two selected things) stay as they are.
std::vector<Segment> smooth_corners(const std::vector<Edge>& edges);

}  // namespace rtview
