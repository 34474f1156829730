// FrameDamage: what of the window a frame repaints against the last frame.
#include <doctest/doctest.h>

#include <vector>

#include "frame_damage.h"

using rtview::DrawTriangles;
using rtview::DrawVertex;
using rtview::FrameDamage;
using rtview::PixelBox;
using rtview::TextureChange;

namespace {

constexpr int W = 1000, H = 800;

DrawVertex vertex(float x, float y, float u, float v, std::uint64_t texture, std::uint32_t colour) {
    DrawVertex d;
    d.x = x, d.y = y, d.u = u, d.v = v, d.colour = colour, d.texture = texture;
    d.clip[0] = 0, d.clip[1] = 0, d.clip[2] = W, d.clip[3] = H;
    return d;
}

// A rectangle as two triangles, the way ImGui draws one: uv {0, 0} at its top left,
// {1, 1} at its bottom right.
void rect(DrawTriangles& l, float x0, float y0, float x1, float y1, std::uint64_t texture = 1, std::uint32_t colour = 0xffffffff) {
    const DrawVertex a = vertex(x0, y0, 0, 0, texture, colour), b = vertex(x1, y0, 1, 0, texture, colour),
                     c = vertex(x1, y1, 1, 1, texture, colour), d = vertex(x0, y1, 0, 1, texture, colour);
    for (const DrawVertex& v : {a, b, c, a, c, d}) l.push_back(v);
}

// A window: a background, and a row of "glyphs" 10 pixels apart.
DrawTriangles panel(int changed_glyph = -1) {
    DrawTriangles l;
    rect(l, 600, 0, 1000, 800);
    for (int i = 0; i < 20; ++i) rect(l, 610 + 10 * i, 100, 618 + 10 * i, 112, 1, i == changed_glyph ? 0xff0000ff : 0xffffffff);
    return l;
}

// A list of a window of its own.
DrawTriangles named(DrawTriangles l, std::uint64_t id) {
    l.id = id;
    return l;
}

bool inside(const PixelBox& inner, const PixelBox& outer) {
    return inner.x0 >= outer.x0 && inner.y0 >= outer.y0 && inner.x1 <= outer.x1 && inner.y1 <= outer.y1;
}

}  // namespace

TEST_CASE("the first frame is painted whole; the same frame again paints nothing") {
    FrameDamage d;
    auto first = d.compare({panel()}, W, H, {});
    REQUIRE(first.size() == 1);
    CHECK(first[0] == PixelBox{0, 0, W, H});
    CHECK(d.compare({panel()}, W, H, {}).empty());
}

TEST_CASE("a changed glyph repaints its own pixels, not the window around it") {
    FrameDamage d;
    d.compare({panel()}, W, H, {});
    auto boxes = d.compare({panel(5)}, W, H, {});
    REQUIRE(boxes.size() == 1);
    // Glyph 5 covers x 660..668, y 100..112: repainted with a pixel's margin.
    CHECK(inside(PixelBox{660, 100, 668, 112}, boxes[0]));
    CHECK(inside(boxes[0], PixelBox{657, 97, 671, 115}));
    // Back to the first: the same pixels again.
    auto back = d.compare({panel()}, W, H, {});
    REQUIRE(back.size() == 1);
    CHECK(back[0] == boxes[0]);
}

TEST_CASE("two glyphs far apart that change colour repaint two small boxes") {
    FrameDamage d;
    DrawTriangles a = panel(), b = panel();
    for (int k = 0; k < 6; ++k) b[6 * 1 + k].colour = 0xff00ff00, b[6 * 19 + k].colour = 0xff00ff00;  // glyphs 0 and 18
    d.compare({a}, W, H, {});
    auto boxes = d.compare({b}, W, H, {});
    REQUIRE(boxes.size() == 2);
    CHECK(inside(PixelBox{610, 100, 618, 112}, boxes[0]));
    CHECK(inside(PixelBox{790, 100, 798, 112}, boxes[1]));
    CHECK(boxes[0].area() + boxes[1].area() < 600);
}

TEST_CASE("a list that loses its last triangles repaints where they were") {
    FrameDamage d;
    DrawTriangles full = panel();
    d.compare({full}, W, H, {});
    DrawTriangles shorter(full.begin(), full.end() - 6);  // the last glyph gone
    auto boxes = d.compare({shorter}, W, H, {});
    REQUIRE(boxes.size() == 1);
    CHECK(inside(PixelBox{800, 100, 808, 112}, boxes[0]));
    CHECK(boxes[0].area() < 400);
}

TEST_CASE("changed texels repaint where the triangles showing them put them") {
    FrameDamage d;
    DrawTriangles picture;
    rect(picture, 100, 200, 300, 300, 7);  // a 200x100 picture of texture 7
    d.compare({named(picture, 1), named(panel(), 2)}, W, H, {});
    // Texels u 0.5..0.75, v 0..0.1 changed: x 200..250, y 200..210 on the screen.
    TextureChange c{7, 0.5f, 0.f, 0.75f, 0.1f};
    auto boxes = d.compare({named(picture, 1), named(panel(), 2)}, W, H, {c});
    REQUIRE(boxes.size() == 1);
    CHECK(inside(PixelBox{200, 200, 250, 210}, boxes[0]));
    CHECK(inside(boxes[0], PixelBox{198, 198, 252, 212}));
    // Another texture's change is not this picture's.
    CHECK(d.compare({named(picture, 1), named(panel(), 2)}, W, H, {TextureChange{8, 0, 0, 1, 1}}).empty());
}

TEST_CASE("a triangle's pixels stay within its clip rectangle") {
    DrawTriangles l;
    rect(l, 0, 0, 500, 500);
    for (DrawVertex& v : l) v.clip[0] = 100, v.clip[1] = 120, v.clip[2] = 200, v.clip[3] = 220;
    const PixelBox b = rtview::triangle_box(&l[0]);
    CHECK(inside(b, PixelBox{100, 120, 200, 220}));
}

TEST_CASE("a list that comes (a tooltip) or goes repaints its own pixels; lists reordered, the window") {
    FrameDamage d;
    DrawTriangles tip;
    rect(tip, 50, 60, 150, 90);
    d.compare({named(panel(), 1)}, W, H, {});
    auto came = d.compare({named(panel(), 1), named(tip, 2)}, W, H, {});
    REQUIRE(came.size() == 1);
    CHECK(inside(PixelBox{50, 60, 150, 90}, came[0]));
    CHECK(inside(came[0], PixelBox{48, 58, 152, 92}));
    auto went = d.compare({named(panel(), 1)}, W, H, {});
    REQUIRE(went.size() == 1);
    CHECK(went[0] == came[0]);
    d.compare({named(panel(), 1), named(tip, 2)}, W, H, {});
    auto reordered = d.compare({named(tip, 2), named(panel(), 1)}, W, H, {});
    REQUIRE(reordered.size() == 1);
    CHECK(reordered[0] == PixelBox{0, 0, W, H});
}

TEST_CASE("a new size, lists sharing a name or an exposed window repaints everything") {
    FrameDamage d;
    d.compare({panel()}, W, H, {});
    auto resized = d.compare({panel()}, W + 10, H, {});
    REQUIRE(resized.size() == 1);
    CHECK(resized[0] == PixelBox{0, 0, W + 10, H});
    auto more = d.compare({panel(), panel()}, W + 10, H, {});
    REQUIRE(more.size() == 1);
    CHECK(more[0] == PixelBox{0, 0, W + 10, H});
    d.invalidate();
    auto exposed = d.compare({panel(), panel()}, W + 10, H, {});
    REQUIRE(exposed.size() == 1);
    CHECK(exposed[0] == PixelBox{0, 0, W + 10, H});
}

TEST_CASE("boxes merge where they touch; too many or too much make one of the window") {
    auto two = rtview::merge_boxes({{0, 0, 10, 10}, {10, 5, 20, 15}, {100, 100, 110, 110}}, W, H);
    REQUIRE(two.size() == 2);
    CHECK(two[0] == PixelBox{0, 0, 20, 15});
    CHECK(two[1] == PixelBox{100, 100, 110, 110});
    // Clipped to the window; empty ones dropped.
    auto clipped = rtview::merge_boxes({{-5, -5, 10, 10}, {50, 50, 50, 60}}, W, H);
    REQUIRE(clipped.size() == 1);
    CHECK(clipped[0] == PixelBox{0, 0, 10, 10});
    // One too many: the two nearest join (the fewest pixels added).
    std::vector<PixelBox> many;
    for (int i = 0; i < FrameDamage::kMaxBoxes; ++i) many.push_back({0, 100 * i, 10, 100 * i + 10});
    many.push_back({0, 15, 10, 25});
    auto fewer = rtview::merge_boxes(many, W, H);
    REQUIRE(int(fewer.size()) == FrameDamage::kMaxBoxes);
    CHECK(fewer[0] == PixelBox{0, 0, 10, 25});
    // Far too many to weigh: one box around them all.
    std::vector<PixelBox> lots;
    for (int i = 0; i < 100; ++i) lots.push_back({20 * (i % 10), 20 * (i / 10), 20 * (i % 10) + 5, 20 * (i / 10) + 5});
    auto one = rtview::merge_boxes(lots, W, H);
    REQUIRE(one.size() == 1);
    CHECK(one[0] == PixelBox{0, 0, 185, 185});
    auto whole = rtview::merge_boxes({{0, 0, W, 500}, {0, 600, 10, 610}}, W, H);
    REQUIRE(whole.size() == 1);
    CHECK(whole[0] == PixelBox{0, 0, W, H});
}
