// Preview pacing (see pacing.h).
#include "pacing.h"

#include <algorithm>
#include <atomic>
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

PreviewResult trace_preview(const rt::World& world, const rt::Camera& camera, int film_w, int film_h, int block,
                            std::vector<std::uint8_t>& rgba, int& width, int& height, rt::ThreadPool* pool,
                            const rt::TraceStop& stop) {
    const int b = std::max(1, block);
    const rt::CameraBasis basis = rt::CameraBasis::make(camera, film_w, film_h, false);
    width = (film_w + b - 1) / b;
    height = (film_h + b - 1) / b;
    const int w = width;
    rgba.resize(std::size_t(width) * std::size_t(height) * 4);
    // done[y]: row y was traced to its end before any stop.
    std::vector<std::uint8_t> done(std::size_t(height), 0);
    std::atomic<bool> stopped{false};
    std::atomic<std::uint64_t> traced{0};
    auto row = [&](int by) {
        if (stopped.load(std::memory_order_relaxed)) return;
        rt::RayStats stats;
        stats.stop = stop;
        // The row in one call, as the renderer traces its rows (packets where the ISA
        // has them): the same rays, the same colours as one at a time.
        thread_local std::vector<rt::Vec3> dirs;
        thread_local std::vector<rt::Colour> colours;
        dirs.resize(std::size_t(w));
        colours.resize(std::size_t(w));
        basis.unit_directions(0, b, w, double(by * b), dirs.data());
        world.trace_units(basis.origin, dirs.data(), std::size_t(w), stats, colours.data());
        if (stats.stopped) {
            stopped = true;
            return;
        }
        std::uint8_t* out = rgba.data() + std::size_t(by) * std::size_t(w) * 4;
        for (const rt::Colour& c : colours) {
            // Through float, as the film stores it: the same bytes as the coarse pass.
            out[0] = rt::to_byte(float(c.x)), out[1] = rt::to_byte(float(c.y)), out[2] = rt::to_byte(float(c.z));
            out[3] = 255;
            out += 4;
        }
        done[std::size_t(by)] = 1;
        traced.fetch_add(std::uint64_t(w), std::memory_order_relaxed);
    };
    if (pool)
        pool->parallel_for(height, row);
    else
        for (int by = 0; by < height; ++by) row(by);
    PreviewResult r{traced.load(), stopped.load()};
    if (r.stopped) {
        const std::size_t bytes = std::size_t(w) * 4;
        for (int by = 0, last = -1; by < height; ++by) {
            std::uint8_t* dst = rgba.data() + std::size_t(by) * bytes;
            if (done[std::size_t(by)])
                last = by;
            else if (last >= 0)
                std::copy_n(rgba.data() + std::size_t(last) * bytes, bytes, dst);
            else
                for (std::size_t i = 0; i < bytes; ++i) dst[i] = (i % 4 == 3) ? 255 : 0;
        }
    }
    return r;
}

}  // namespace rtview
