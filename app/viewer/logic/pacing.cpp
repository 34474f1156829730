// Preview pacing (see pacing.h).
#include "pacing.h"

#include <algorithm>
#include <cmath>

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

}  // namespace rtview
