// Display mapping (see display.h).
#include "display.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rtview {

double exposure_gain(double stops) { return std::exp2(std::clamp(stops, -kMaxExposure, kMaxExposure)); }

double tone(double v, ToneCurve curve) {
    if (!(v > 0)) return 0;  // also NaN
    if (curve == ToneCurve::Clip || v <= kSoftKnee) return std::min(v, 1.0);
    // A rational shoulder: slope 1 at the knee (no visible seam), 1 only at infinity,
    // so 20 times white still differs from 5 times white.
    double t = (v - kSoftKnee) / (1 - kSoftKnee);
    return kSoftKnee + (1 - kSoftKnee) * t / (1 + t);
}

std::uint8_t display_byte(double linear, double gain, ToneCurve curve) {
    return rt::to_byte(tone(linear * gain, curve));
}

bool is_clipped(float r, float g, float b, double gain) { return r * gain > 1 || g * gain > 1 || b * gain > 1; }

void map_to_rgba8(const rt::Image& img, const DisplaySettings& s, const std::array<int, 4>& rect,
                  std::vector<std::uint8_t>& rgba) {
    const std::size_t n = std::size_t(img.width) * img.height;
    if (rgba.size() != 4 * n) rgba.resize(4 * n);
    const int x0 = std::max(rect[0], 0), y0 = std::max(rect[1], 0);
    const int x1 = std::min(rect[2], img.width), y1 = std::min(rect[3], img.height);
    const double gain = exposure_gain(s.exposure);
    for (int y = y0; y < y1; ++y) {
        std::size_t idx = std::size_t(y) * img.width + x0;
        const float* c = &img.rgb[3 * idx];
        std::uint8_t* p = &rgba[4 * idx];
        for (int x = x0; x < x1; ++x, c += 3, p += 4) {
            if (s.show_clipped && on_stripe(x, y) && is_clipped(c[0], c[1], c[2], gain)) {
                p[0] = kClipMarker[0], p[1] = kClipMarker[1], p[2] = kClipMarker[2];
            } else {
                p[0] = display_byte(c[0], gain, s.curve);
                p[1] = display_byte(c[1], gain, s.curve);
                p[2] = display_byte(c[2], gain, s.curve);
            }
            p[3] = 255;
        }
    }
}

std::size_t count_clipped(const rt::Image& img, double gain) {
    std::size_t n = 0;
    const std::size_t pixels = std::size_t(img.width) * img.height;
    for (std::size_t i = 0; i < pixels; ++i)
        n += is_clipped(img.rgb[3 * i], img.rgb[3 * i + 1], img.rgb[3 * i + 2], gain);
    return n;
}

std::string display_badge(const DisplaySettings& settings) {
    std::string s;
    auto add = [&s](const std::string& part) { s += (s.empty() ? "" : "  ") + part; };
    if (settings.exposure != 0) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "exposure %+.1f", settings.exposure);
        add(buf);
    }
    if (settings.curve == ToneCurve::Soft) add("soft curve");
    if (settings.show_clipped) add("clipped marked");
    return s;
}

}  // namespace rtview
