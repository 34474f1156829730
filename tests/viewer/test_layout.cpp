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

TEST_CASE("one line of status text: cut at its end with '...', never wider than the bar") {
    const std::string text = "Wrote screenshot /home/u/raytracer-view-20261207.png";
    CHECK(elide_end(text, 100, chars) == text);
    CHECK(elide_end(text, float(text.size()), chars) == text);
    const std::string cut = elide_end(text, 20, chars);
    CHECK(cut == "Wrote screenshot...");  // the space before the dots goes
    CHECK(chars(cut) <= 20);
    CHECK(elide_end(text, 2, chars).empty());  // not even "..." fits
    CHECK(elide_end(text, 3, chars) == "...");
    // Cut inside a word: back to the word's start; a number is never cut.
    CHECK(elide_end(text, 25, chars) == "Wrote screenshot...");
    CHECK(elide_end("5.21 Mrays/s", 7, chars) == "5.21...");
    CHECK(elide_end("5.21 Mrays/s", 6, chars) == "...");
    CHECK(elide_end("raytracer-view", 8, chars) == "raytr...");
    // Never inside a character of two bytes: "é" is 2 bytes, counted as 2 units here.
    const std::string accents = "\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9";
    const std::string a = elide_end(accents, 7, chars);
    CHECK(a == "\xc3\xa9\xc3\xa9...");
    for (std::size_t w = 3; w < 12; ++w) {
        const std::string e = elide_end(accents, float(w), chars);
        CHECK(chars(e) <= float(w));
        CHECK((e.size() < 3 || e.compare(e.size() - 3, 3, "...") == 0 || e == accents));
        // Only whole characters before the dots: an even number of bytes.
        if (e != accents && !e.empty()) CHECK((e.size() - 3) % 2 == 0);
    }
}

TEST_CASE("a readout's groups are kept whole or left out, the line ends in '...'") {
    const std::vector<std::pair<std::string, std::string>> pieces = {
        {"", "x 354 y 332"}, {"   ", "RGB 0.927 0.900 0.899"}, {"   ", "48 spp"}};
    CHECK(elide_pieces(pieces, 100, chars) == "x 354 y 332   RGB 0.927 0.900 0.899   48 spp");
    CHECK(elide_pieces(pieces, 40, chars) == "x 354 y 332   RGB 0.927 0.900 0.899...");
    CHECK(elide_pieces(pieces, 30, chars) == "x 354 y 332...");
    // Not even the first group: it is cut by characters.
    CHECK(elide_pieces(pieces, 8, chars) == "x 354...");
    for (float w = 0; w < 60; ++w) CHECK(chars(elide_pieces(pieces, w, chars)) <= std::max(w, 0.f));
}

TEST_CASE("a long message is cut in its middle: its start and its file name stay") {
    const std::string text = "Wrote screenshot /home/user/pictures/raytracer-view-20261207.png";
    CHECK(elide_middle(text, 200, chars) == text);
    const std::string m = elide_middle(text, 40, chars);
    CHECK(chars(m) <= 40);
    CHECK(chars(m) >= 39);  // as much as fits
    CHECK(m.rfind("Wrote scree", 0) == 0);
    CHECK(m.find("...") != std::string::npos);
    CHECK(m.substr(m.size() - 13) == "-20261207.png");
    CHECK(elide_middle(text, 2, chars).empty());
    for (float w = 3; w < 70; ++w) CHECK(chars(elide_middle(text, w, chars)) <= w);
}
