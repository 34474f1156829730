// Preview pacing (see pacing.h).
#include "pacing.h"

#include <algorithm>
#include <cmath>

#include "film.h"

namespace rtview {

void PreviewPacer::measured(double rays, double seconds) {
    if (!(rays > 0) || !(seconds >= 0) || !std::isfinite(seconds)) return;
    double sample = seconds / rays;
    if (per_ray_ <= 0) {
        per_ray_ = sample;
        return;
    }
    // Faster passes are believed at once (the load went away); slower ones halfway,
    // so one hiccup does not make the preview blocky for long.
    per_ray_ = sample < per_ray_ ? sample : 0.5 * per_ray_ + 0.5 * sample;
}

int PreviewPacer::coarse_block(int width, int height, double budget) const {
    if (per_ray_ <= 0 || budget <= 0) return 8;
    double pixels = double(std::max(width, 1)) * std::max(height, 1);
    for (int b = 2; b < 64; b *= 2)
        if (pixels / (double(b) * b) * per_ray_ <= budget) return b;
    return 64;
}

void trace_preview(const rt::World& world, const rt::Camera& camera, int film_w, int film_h, int block,
                   std::vector<std::uint8_t>& rgba, int& width, int& height) {
    int b = std::max(1, block);
    rt::CameraBasis basis = rt::CameraBasis::make(camera, film_w, film_h, false);
    width = (film_w + b - 1) / b;
    height = (film_h + b - 1) / b;
    rgba.resize(std::size_t(width) * std::size_t(height) * 4);
    rt::RayStats stats;
    std::uint8_t* out = rgba.data();
    for (int by = 0; by < height; ++by)
        for (int bx = 0; bx < width; ++bx, out += 4) {
            rt::Colour c = world.trace_unit(basis.origin, rt::normalize(basis.direction(bx * b, by * b)), stats);
            // Through float, as the film stores it: the same bytes as the coarse pass.
            out[0] = rt::to_byte(float(c.x)), out[1] = rt::to_byte(float(c.y)), out[2] = rt::to_byte(float(c.z));
            out[3] = 255;
        }
}

}  // namespace rtview
