// The window's layout arithmetic: the picture frame's film, the sidebar's width and
// status text flowed into rows at spaces.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "layout.h"

using namespace rtview;

TEST_CASE("the picture frame renders the scene's picture_size, however it is shown") {
    int w = 0, h = 0;
    picture_film_size(640, 480, w, h);
    CHECK((w == 640 && h == 480));
    picture_film_size(1, 16384, w, h);
    CHECK((w == 1 && h == 16384));
    // Past the viewer's film limit: the largest film of the same aspect within it.
    picture_film_size(16384, 16384, w, h);
    CHECK((w == 4096 && h == 4096));
    picture_film_size(16384, 8000, w, h);
    CHECK(std::int64_t(w) * h <= kMaxFilmPixels);
    CHECK(w > 5800);
    CHECK(double(w) / h == doctest::Approx(16384.0 / 8000).epsilon(0.001));
    picture_film_size(0, -3, w, h);
    CHECK((w == 1 && h == 1));
}

TEST_CASE("the sidebar leaves the picture most of the window at a large UI scale") {
    // 1280 wide at 2x, fields that would want 738: a third of the window, widened only
    // to 40 % (it was 58 %).
    const float w = sidebar_width(1280, 2, 738, 0);
    CHECK(w <= 1280 * 0.4f);
    CHECK(w >= 1280 * 0.34f - 1);
    // At 1x the fields fit in a third of the window, as before.
    CHECK(sidebar_width(1280, 1, 400, 0) == std::floor(1280 * 0.34f));
    // In a wide window it grows no wider than its contents want.
    CHECK(sidebar_width(3000, 1, 400, 0) == 470);
}

TEST_CASE("a width the user dragged is kept as a share of the window, within limits") {
    CHECK(sidebar_width(1280, 1, 400, 0.25) == 320);
    CHECK(sidebar_width(1280, 2, 738, 0.25) == 320);  // the UI scale does not change the share
    // Chosen at 2560 wide, the same share at 1280 (an absolute width took 75 % there).
    CHECK(sidebar_width(2560, 2, 738, 0.3) == 768);
    CHECK(sidebar_width(1280, 2, 738, 0.3) == 384);
    // A drag's width comes back whole from its share.
    for (float w = 200; w <= 700; w += 1) CHECK(sidebar_width(1280, 1, 400, w / 1280) == w);
    // Never so narrow that it is gone (Tab hides it) nor so wide the picture is: the
    // picture keeps 40 % of the window.
    CHECK(sidebar_width(1280, 1, 400, 0.01) == sidebar_min_width(1280, 1));
    CHECK(sidebar_width(1280, 1, 400, 0.95) == sidebar_max_width(1280, 1));
    CHECK(sidebar_max_width(1280, 1) <= 1280 * 0.6f);
    CHECK(sidebar_min_width(1280, 1) >= 100);
    // A small window at 2x (640 wide): the picture keeps most of it.
    CHECK(sidebar_width(640, 2, 738, 0) <= 640 * 0.4f);
    CHECK(sidebar_width(640, 2, 738, 0.9) <= 640 * 0.6f);
    // A tiny window still gives both some room.
    CHECK(sidebar_min_width(200, 3) <= sidebar_max_width(200, 3));
    CHECK(sidebar_width(200, 3, 900, 0) <= 200);
}

namespace {

// Every character one unit wide.
float chars(std::string_view t) { return float(t.size()); }

}  // namespace

TEST_CASE("status text wraps at spaces, never inside a number") {
    const std::string text = "x 354 y 332   RGB 0.927 0.900 0.899   48 spp";
    std::vector<std::string> rows = wrap_words(text, 24, chars);
    REQUIRE(rows.size() == 2);
    CHECK(rows[0] == "x 354 y 332   RGB 0.927");
    CHECK(rows[1] == "0.900 0.899   48 spp");
    for (const std::string& r : rows) CHECK(r.size() <= 24);
    // Each number whole on some row.
    for (const char* n : {"0.927", "0.900", "0.899"}) CHECK((rows[0].find(n) != std::string::npos || rows[1].find(n) != std::string::npos));
    // Fits: one row, as it was.
    CHECK(wrap_words(text, 100, chars) == std::vector<std::string>{text});
    CHECK(wrap_words("", 10, chars) == std::vector<std::string>{""});
}

TEST_CASE("a word wider than a row is cut, as there is no space to break at") {
    std::vector<std::string> rows = wrap_words("Cannot write /a/very/long/path/name.png", 12, chars);
    for (const std::string& r : rows) CHECK(chars(r) <= 12);
    std::string joined;
    for (const std::string& r : rows) joined += r;
    CHECK(joined == "Cannot write/a/very/long/path/name.png");  // only the space between rows is gone
    // Narrower than one character: one character a row, never an endless loop.
    CHECK(wrap_words("abc", 0.5f, chars).size() == 3);
}
