// Zoom and pan of the picture: the pixel readout's window -> picture pixel mapping at
// several zooms and letterboxings, checked against the placement worked out by hand.
#include <doctest/doctest.h>

#include <cmath>

#include "image_view.h"

using namespace rtview;

namespace {

// The pixel under a window point, or (-1, -1) outside the picture.
std::array<int, 2> at(const ImageView& v, const Rect& area, int w, int h, double px, double py, double fb = 0) {
    int x = -1, y = -1;
    if (!picture_pixel_at(v.transform(area, w, h, fb), w, h, px, py, x, y)) return {-1, -1};
    return {x, y};
}

using P = std::array<int, 2>;

}  // namespace

TEST_CASE("fitted: letterboxed top and bottom") {
    // 1000x250 in 800x600 at y 20: 0.8 window units a pixel, bars of 200 above and below.
    Rect area{0, 20, 800, 600};
    ImageView v;
    CHECK(v.fitted());
    ViewTransform t = v.transform(area, 1000, 250);
    CHECK(t.x0 == 0);
    CHECK(t.y0 == 220);
    CHECK(t.sx == doctest::Approx(0.8));
    CHECK(at(v, area, 1000, 250, 0.1, 220.1) == P{0, 0});
    CHECK(at(v, area, 1000, 250, 8.1, 220.1) == P{10, 0});        // 8.1 / 0.8 = 10.1
    CHECK(at(v, area, 1000, 250, 799.9, 419.9) == P{999, 249});
    CHECK(at(v, area, 1000, 250, 400, 219.5) == P{-1, -1});       // in the bar above
    CHECK(at(v, area, 1000, 250, 400, 420.5) == P{-1, -1});       // in the bar below
    CHECK(v.ratio(area, 1000, 250, 1) == doctest::Approx(0.8));
}

TEST_CASE("fitted: pillarboxed left and right") {
    // 100x400 in 500x500 at (10, 10): 1.25 a pixel, 125 wide from x = 197.
    Rect area{10, 10, 500, 500};
    ImageView v;
    CHECK(at(v, area, 100, 400, 197 + 1.25 * 37 + 0.1, 10 + 1.25 * 399 + 0.5) == P{37, 399});
    CHECK(at(v, area, 100, 400, 196.9, 100) == P{-1, -1});
    CHECK(at(v, area, 100, 400, 322.1, 100) == P{-1, -1});
}

TEST_CASE("1:1 keeps the pixel under the cursor and puts texels on whole pixels") {
    Rect area{0, 0, 800, 600};
    ImageView v;  // 320x240 fitted at 2.5 a pixel
    CHECK(at(v, area, 320, 240, 400.3, 300.3) == P{160, 120});
    v.one_to_one(area, 320, 240, 1, 400.3, 300.3);
    CHECK_FALSE(v.fitted());
    ViewTransform t = v.transform(area, 320, 240);
    CHECK(t.sx == 1);
    CHECK(t.x0 == 240);  // round(400.3 - 160.12)
    CHECK(t.y0 == 180);
    CHECK(at(v, area, 320, 240, 400.3, 300.3) == P{160, 120});
    CHECK(at(v, area, 320, 240, 240.5, 180.5) == P{0, 0});
    CHECK(at(v, area, 320, 240, 559.5, 419.5) == P{319, 239});
    CHECK(at(v, area, 320, 240, 239.5, 300) == P{-1, -1});
    CHECK(v.ratio(area, 320, 240, 1) == 1);
}

TEST_CASE("1:1 on a hi-DPI screen is one picture pixel per framebuffer pixel") {
    // Window units are half a framebuffer pixel's size apart: 0.5 units a pixel.
    Rect area{0, 30, 600, 400};
    ImageView v;
    v.one_to_one(area, 2000, 1000, 2, 300, 230);
    ViewTransform t = v.transform(area, 2000, 1000);
    CHECK(t.sx == 0.5);
    CHECK(v.ratio(area, 2000, 1000, 2) == 1);
    CHECK(std::fmod(t.x0 * 2, 1.0) == 0);  // on a framebuffer pixel boundary
    // Fitted, 2000 px spanned 600 units: the point (300, 230) was pixel (1000, 500).
    CHECK(at(v, area, 2000, 1000, 300, 230) == P{1000, 500});
    CHECK(at(v, area, 2000, 1000, 300.5, 230) == P{1001, 500});
    CHECK(at(v, area, 2000, 1000, 300 + 0.5 * 10, 230 - 0.5 * 7) == P{1010, 493});
}

TEST_CASE("wheel zoom steps through 1:1 and magnifies about the cursor") {
    // 1600x1200 in 800x600: larger than the area from 1:1 up, so nothing is centred.
    Rect area{0, 0, 800, 600};
    ImageView v;
    v.one_to_one(area, 1600, 1200, 1, 400, 300);
    P under = at(v, area, 1600, 1200, 410.5, 305.5);
    v.zoom_steps(area, 1600, 1200, 1, 410.5, 305.5, 4);
    CHECK(v.ratio(area, 1600, 1200, 1) == doctest::Approx(2));
    v.zoom_steps(area, 1600, 1200, 1, 410.5, 305.5, 8);
    CHECK(v.ratio(area, 1600, 1200, 1) == doctest::Approx(8));
    CHECK(at(v, area, 1600, 1200, 410.5, 305.5) == under);
    // At 8x a pixel is 8 units wide: 8 units right is the next pixel.
    CHECK(at(v, area, 1600, 1200, 410.5 + 8, 305.5) == P{under[0] + 1, under[1]});
    CHECK(at(v, area, 1600, 1200, 410.5, 305.5 - 16) == P{under[0], under[1] - 2});
    v.zoom_steps(area, 1600, 1200, 1, 410.5, 305.5, -12);
    CHECK(v.ratio(area, 1600, 1200, 1) == doctest::Approx(1));
    // From a fitted 2.5 the first step in lands on the ladder at 2^(6/4).
    ImageView f;
    f.zoom_steps(area, 320, 240, 1, 400, 300, 1);
    CHECK(f.ratio(area, 320, 240, 1) == doctest::Approx(std::exp2(1.5)));
    f.fit();
    CHECK(f.ratio(area, 320, 240, 1) == doctest::Approx(2.5));
}

TEST_CASE("a picture that fits is shown whole and centred, at any zoom and wherever the cursor is") {
    // 640x480 in 845x633 (the default scene beside the sidebar): zoomed in about a
    // corner and panned, then 1:1 with the cursor near that corner.
    Rect area{0, 21, 845, 633};
    ImageView v;
    v.zoom_steps(area, 640, 480, 1, 60, 80, 6);
    CHECK(v.ratio(area, 640, 480, 1) > 2);
    v.pan(area, 640, 480, 200, -150);
    v.one_to_one(area, 640, 480, 1, 60, 80);
    ViewTransform t = v.transform(area, 640, 480, 1);
    CHECK(t.sx == 1);
    CHECK(t.x0 == std::round((845 - 640) / 2.0));
    CHECK(t.y0 == std::round(21 + (633 - 480) / 2.0));
    CHECK(at(v, area, 640, 480, t.x0 + 0.5, t.y0 + 0.5, 1) == P{0, 0});
    CHECK(at(v, area, 640, 480, t.x0 + 639.5, t.y0 + 479.5, 1) == P{639, 479});
    // A pan cannot move it off centre; nor can zooming out about a corner.
    v.pan(area, 640, 480, -70, 40);
    CHECK(v.transform(area, 640, 480, 1).x0 == t.x0);
    v.zoom_steps(area, 640, 480, 1, 5, 30, -2);
    ViewTransform s = v.transform(area, 640, 480);
    CHECK(s.x0 + 640 * s.sx / 2 == doctest::Approx(845 / 2.0));
    CHECK(s.y0 + 480 * s.sy / 2 == doctest::Approx(21 + 633 / 2.0));
}

TEST_CASE("zoomed past the area on one axis, the picture fills it there and stays centred on the other") {
    // 1000x250 in 800x600 at 2x: 2000 wide (fills the width), 500 high (centred).
    Rect area{0, 0, 800, 600};
    ImageView v;
    v.zoom_about(area, 1000, 250, 1, 795, 300, 2.5);  // from fitted 0.8 about the right edge
    CHECK(v.ratio(area, 1000, 250, 1) == doctest::Approx(2));
    ViewTransform t = v.transform(area, 1000, 250);
    CHECK(t.y0 == doctest::Approx(50));
    CHECK(t.x0 == doctest::Approx(795 - 993.75 * 2));  // the pixel under the cursor stays there
    // Panned left past its right edge: it stops there, with no gap beside it.
    v.pan(area, 1000, 250, -100, 0);
    CHECK(v.transform(area, 1000, 250).x0 == doctest::Approx(800 - 2000));
    CHECK(at(v, area, 1000, 250, 799.5, 300) == P{999, 125});
}

TEST_CASE("pan moves the picture up to its edges, and back at once") {
    Rect area{0, 0, 800, 600};
    ImageView v;
    v.one_to_one(area, 1600, 1200, 1, 400, 300);
    P before = at(v, area, 1600, 1200, 400.5, 300.5);
    v.pan(area, 1600, 1200, 10, -3);
    CHECK(at(v, area, 1600, 1200, 400.5, 300.5) == P{before[0] - 10, before[1] + 3});
    v.pan(area, 1600, 1200, 1e6, 1e6);
    // The top-left corner of the picture at the area's: no background beside it.
    CHECK(at(v, area, 1600, 1200, 0.5, 0.5) == P{0, 0});
    v.pan(area, 1600, 1200, -10, -20);
    CHECK(at(v, area, 1600, 1200, 0.5, 0.5) == P{10, 20});
    v.pan(area, 1600, 1200, -1e6, -1e6);
    CHECK(at(v, area, 1600, 1200, 799.5, 599.5) == P{1599, 1199});
}

TEST_CASE("the visible part of the picture, as pixels and as texture coordinates") {
    Rect area{0, 0, 800, 600};
    ImageView v;
    Rect win;
    std::array<double, 4> uv;
    visible_uv(v.transform(area, 320, 240), area, 320, 240, win, uv);
    CHECK(win.w == 800);
    CHECK(uv == std::array<double, 4>{0, 0, 1, 1});
    // At 10x about the centre: 80x60 pixels around (160, 120).
    v.zoom_about(area, 320, 240, 1, 400, 300, 4);
    CHECK(v.ratio(area, 320, 240, 1) == doctest::Approx(10));
    std::array<int, 4> px = visible_pixels(v.transform(area, 320, 240), area, 320, 240);
    CHECK(px == std::array<int, 4>{120, 90, 200, 150});
    visible_uv(v.transform(area, 320, 240), area, 320, 240, win, uv);
    CHECK(win.w == doctest::Approx(800));
    CHECK(uv[0] == doctest::Approx(120.0 / 320));
    CHECK(uv[3] == doctest::Approx(150.0 / 240));
}
