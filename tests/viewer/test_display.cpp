// Display mapping: exposure and tone curves on known values, the clipped overlay, and
// that the default settings give the renderer's own bytes.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "display.h"

using namespace rtview;

TEST_CASE("exposure is a factor of two per stop") {
    CHECK(exposure_gain(0) == 1);
    CHECK(exposure_gain(1) == 2);
    CHECK(exposure_gain(-2) == 0.25);
    CHECK(exposure_gain(0.5) == doctest::Approx(std::sqrt(2.0)));
    CHECK(exposure_gain(1000) == std::exp2(kMaxExposure));  // clamped
    // Known bytes: 255 * v truncated.
    CHECK(display_byte(0.25, exposure_gain(1), ToneCurve::Clip) == 127);   // 0.5
    CHECK(display_byte(1.0, exposure_gain(-1), ToneCurve::Clip) == 127);   // 0.5
    CHECK(display_byte(0.1, exposure_gain(3), ToneCurve::Clip) == 204);    // 0.8
    CHECK(display_byte(300, exposure_gain(-9), ToneCurve::Clip) == 149);   // 0.5859375
    CHECK(display_byte(2.0, 1, ToneCurve::Clip) == 255);
    CHECK(display_byte(-1, 1, ToneCurve::Clip) == 0);
    CHECK(display_byte(std::numeric_limits<double>::quiet_NaN(), 1, ToneCurve::Clip) == 0);
}

TEST_CASE("at 0 stops the clip curve is the renderer's rounding") {
    for (int k = -10; k <= 600; ++k) {
        double v = k / 511.0;
        CHECK(display_byte(v, 1, ToneCurve::Clip) == rt::to_byte(v));
    }
    DisplaySettings d;
    CHECK(d.identity());
    d.exposure = 0.5;
    CHECK_FALSE(d.identity());
}

TEST_CASE("the soft curve leaves values below the knee alone and bends above it") {
    CHECK(tone(0.25, ToneCurve::Soft) == 0.25);
    CHECK(tone(kSoftKnee, ToneCurve::Soft) == kSoftKnee);
    // t = (v - 0.5) / 0.5; 0.5 + 0.5 t / (1 + t)
    CHECK(tone(1.0, ToneCurve::Soft) == doctest::Approx(0.75));
    CHECK(tone(2.0, ToneCurve::Soft) == doctest::Approx(0.875));
    CHECK(tone(5.0, ToneCurve::Soft) == doctest::Approx(0.95));
    CHECK(tone(1e12, ToneCurve::Soft) < 1);
    // Smooth at the knee: the slope on both sides is 1.
    double h = 1e-6;
    CHECK((tone(kSoftKnee + h, ToneCurve::Soft) - kSoftKnee) / h == doctest::Approx(1).epsilon(1e-4));
    // Monotone: brighter input never shows darker.
    double last = 0;
    for (double v = 0; v < 50; v += 0.01) {
        double t = tone(v, ToneCurve::Soft);
        CHECK(t >= last);
        last = t;
    }
    CHECK(display_byte(1.0, 1, ToneCurve::Soft) == 191);  // 255 * 0.75 = 191.25
    CHECK(display_byte(5.0, 1, ToneCurve::Soft) == 242);  // 242.25
}

TEST_CASE("the overlay stripes clipped pixels only, and only with it on") {
    rt::Image img;
    img.width = 8;
    img.height = 8;
    img.rgb.assign(8 * 8 * 3, 0.5f);
    img.rgb[3 * (2 * 8 + 1) + 1] = 1.5f;  // (1, 2): green over 1, on a stripe
    img.rgb[3 * (2 * 8 + 3) + 1] = 1.5f;  // (3, 2): the same between stripes
    img.rgb[3 * (6 * 8 + 6)] = 0.9f;      // (6, 6): below 1, over it at +1 stop
    CHECK(is_clipped(0.5f, 1.5f, 0.5f, 1));
    CHECK_FALSE(is_clipped(1.0f, 1.0f, 1.0f, 1));  // exactly 1 loses nothing
    CHECK(count_clipped(img, 1) == 2);
    CHECK(count_clipped(img, 2) == 3);  // 0.5 * 2 = 1 is not over; 1.5 and 0.9 are
    DisplaySettings d;
    std::vector<std::uint8_t> rgba;
    map_to_rgba8(img, d, rgba);
    REQUIRE(rgba.size() == 8 * 8 * 4);
    std::size_t p = 4 * (2 * 8 + 1);
    CHECK(rgba[p] == 127);
    CHECK(rgba[p + 1] == 255);
    CHECK(rgba[p + 3] == 255);
    d.show_clipped = true;
    map_to_rgba8(img, d, rgba);
    REQUIRE(on_stripe(1, 2));
    REQUIRE_FALSE(on_stripe(3, 2));
    CHECK(rgba[p] == kClipMarker[0]);
    CHECK(rgba[p + 1] == kClipMarker[1]);
    CHECK(rgba[p + 2] == kClipMarker[2]);
    std::size_t between = 4 * (2 * 8 + 3);
    CHECK(rgba[between] == 127);
    CHECK(rgba[between + 1] == 255);
    std::size_t q = 4 * (0 * 8 + 0);  // not clipped
    CHECK(rgba[q] == 127);
    CHECK(rgba[q + 1] == 127);
}

TEST_CASE("mapping a rectangle leaves the rest of the texture as it was") {
    rt::Image img;
    img.width = 4;
    img.height = 3;
    img.rgb.assign(4 * 3 * 3, 0.25f);
    std::vector<std::uint8_t> rgba(4 * 3 * 4, 7);
    DisplaySettings d;
    d.exposure = 1;
    map_to_rgba8(img, d, {1, 1, 3, 2}, rgba);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 4; ++x) {
            bool inside = x >= 1 && x < 3 && y == 1;
            CHECK(rgba[4 * (y * 4 + x)] == (inside ? 127 : 7));
        }
}

TEST_CASE("the badge names every way the picture is shown otherwise than saved, and only then") {
    DisplaySettings d;
    CHECK(display_badge(d).empty());
    d.exposure = 2;
    CHECK(display_badge(d) == "exposure +2.0");
    d.exposure = -1.5;
    d.curve = ToneCurve::Soft;
    CHECK(display_badge(d) == "exposure -1.5  soft curve");
    d.exposure = 0;
    d.show_clipped = true;
    CHECK(display_badge(d) == "soft curve  clipped marked");
    d.curve = ToneCurve::Clip;
    d.show_clipped = false;
    CHECK(display_badge(d).empty() == d.identity());
}
