// Preview pacing (see pacing.h).
#include "pacing.h"

#include <algorithm>
#include <cmath>
#include <vector>

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

int PreviewPacer::preview_block(int width, int height, double budget) const {
    if (per_ray_ <= 0 || budget <= 0) return 8;
    for (int b = 1; b < 64; ++b)
        if (std::ceil(std::max(width, 1) / double(b)) * std::ceil(std::max(height, 1) / double(b)) * per_ray_ <= budget)
            return b;
    return 64;
}

PreviewResult trace_preview(rt::Renderer& renderer, std::shared_ptr<const rt::World> world, const rt::Camera& camera,
                            int film_w, int film_h, int block, double time_limit, std::vector<std::uint8_t>& rgba,
                            int& width, int& height) {
    rt::RenderSettings st;
    st.width = film_w;
    st.height = film_h;
    st.camera = camera;
    st.step = std::max(1, block);
    st.coarse = false;
    st.tile_size = 16;  // (a stop loses the tiles in progress: small ones)
    st.time_limit = time_limit;
    st.hard_time_limit = true;
    renderer.start(std::move(world), st);
    renderer.wait();
    const rt::Image film = renderer.snapshot();
    std::vector<std::uint32_t> counts;
    renderer.sample_counts(counts, width, height);
    width = film.width;
    height = film.height;
    const std::size_t n = std::size_t(width) * std::size_t(height);
    rgba.resize(4 * n);
    PreviewResult r;
    for (std::size_t i = 0; i < n && counts.size() == n; ++i) {
        std::uint8_t* out = &rgba[4 * i];
        if (counts[i] > 0) {
            // The film's float, as the coarse pass's pixels show it.
            out[0] = rt::to_byte(film.rgb[3 * i]), out[1] = rt::to_byte(film.rgb[3 * i + 1]);
            out[2] = rt::to_byte(film.rgb[3 * i + 2]), out[3] = 255;
            ++r.traced;
        } else if (i >= std::size_t(width)) {
            std::copy_n(&rgba[4 * (i - std::size_t(width))], 4, out);  // stopped: the pixel above
        } else {
            out[0] = out[1] = out[2] = 0, out[3] = 255;
        }
    }
    r.stopped = r.traced < n;
    return r;
}

}  // namespace rtview
