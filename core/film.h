// Float accumulation buffer: per-pixel colour sums and sample counts, plus a preview
// layer that coarse passes fill until the first full-resolution sample arrives.
#pragma once

#include <cstdint>
#include <vector>

#include "math.h"

namespace rt {

struct Image {
    int width = 0, height = 0;
    std::vector<float> rgb;  // linear colour, 3 floats per pixel, top row first
    Colour at(int x, int y) const {
        const float* p = &rgb[3 * (std::size_t(y) * width + x)];
        return {p[0], p[1], p[2]};
    }
};

// The original's output rounding: truncation, clamped to 0..255; NaN gives 0.
inline std::uint8_t to_byte(double c) {
    if (!(c > 0)) return 0;
    if (c >= 1) return 255;
    return static_cast<std::uint8_t>(255.0 * c);
}

struct Film {
    int width = 0, height = 0;
    std::vector<float> sum;         // 3 per pixel
    std::vector<std::uint32_t> count;
    std::vector<float> preview;     // 3 per pixel, used while count == 0

    void reset(int w, int h) {
        width = w;
        height = h;
        sum.assign(std::size_t(w) * h * 3, 0.f);
        count.assign(std::size_t(w) * h, 0);
        preview.assign(std::size_t(w) * h * 3, 0.f);
    }
    Colour pixel(std::size_t idx) const {
        if (count[idx] == 0) return {preview[3 * idx], preview[3 * idx + 1], preview[3 * idx + 2]};
        double inv = 1.0 / count[idx];
        return {sum[3 * idx] * inv, sum[3 * idx + 1] * inv, sum[3 * idx + 2] * inv};
    }
    Image resolve() const {
        Image img;
        img.width = width;
        img.height = height;
        img.rgb.resize(std::size_t(width) * height * 3);
        for (std::size_t i = 0, n = std::size_t(width) * height; i < n; ++i) {
            Colour c = pixel(i);
            img.rgb[3 * i] = float(c.x);
            img.rgb[3 * i + 1] = float(c.y);
            img.rgb[3 * i + 2] = float(c.z);
        }
        return img;
    }
};

}  // namespace rt
