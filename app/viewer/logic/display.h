// Display mapping of the film: exposure in stops, a clip or soft tone curve and a
// striped overlay on clipped pixels, from linear film values to RGBA8 for the
// texture. Display only: saved renders keep the renderer's own rounding.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "film.h"

namespace rtview {

enum class ToneCurve { Clip, Soft };

struct DisplaySettings {
    double exposure = 0;  // stops: linear values are multiplied by 2^exposure
    ToneCurve curve = ToneCurve::Clip;
    bool show_clipped = false;  // stripes over pixels with a channel above 1 after exposure

    // The renderer's own bytes: the film texture can come from the renderer's
    // tile-incremental snapshot_rgba8 without a float copy of the film.
    bool identity() const { return exposure == 0 && curve == ToneCurve::Clip && !show_clipped; }
    bool operator==(const DisplaySettings& o) const {
        return exposure == o.exposure && curve == o.curve && show_clipped == o.show_clipped;
    }
    bool operator!=(const DisplaySettings& o) const { return !(*this == o); }
};

constexpr double kMaxExposure = 20;  // stops either way
// The soft curve is the identity up to this value, then bends towards 1.
constexpr double kSoftKnee = 0.5;
// Clipped-pixel stripes: this colour on every other diagonal band of this width.
constexpr std::uint8_t kClipMarker[3] = {255, 0, 200};
constexpr int kClipStripe = 4;

// 2^stops, the factor on linear values.
double exposure_gain(double stops);
// Display value (0..1 for the 8-bit rounding) of an exposed linear value.
double tone(double v, ToneCurve curve);
// One channel: tone(linear * gain) with the renderer's rounding (truncation, NaN 0).
std::uint8_t display_byte(double linear, double gain, ToneCurve curve);
// Whether a pixel loses information in the clip curve: a channel above 1 after the gain.
bool is_clipped(float r, float g, float b, double gain);
// Whether pixel (x, y) lies on a stripe of the clipped-pixel overlay.
inline bool on_stripe(int x, int y) { return ((x + y) / kClipStripe) % 2 == 0; }

// Maps rect {x0, y0, x1, y1} of `img` into `rgba` (4 bytes a pixel, img's size; it
// is resized, keeping its contents, when it has another size).
void map_to_rgba8(const rt::Image& img, const DisplaySettings& settings, const std::array<int, 4>& rect,
                  std::vector<std::uint8_t>& rgba);
inline void map_to_rgba8(const rt::Image& img, const DisplaySettings& settings, std::vector<std::uint8_t>& rgba) {
    map_to_rgba8(img, settings, {0, 0, img.width, img.height}, rgba);
}

// What the picture shows differently from the saved image, for a badge on it:
// "exposure +2.0  soft curve  clipped marked"; empty when the display is neutral.
std::string display_badge(const DisplaySettings& settings);

// Counts of the pixels whose channels exceed 1 after the gain (for the status line).
std::size_t count_clipped(const rt::Image& img, double gain);

}  // namespace rtview
