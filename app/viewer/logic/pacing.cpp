// Preview pacing (see pacing.h).
#include "pacing.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <vector>

#include "film.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace rtview {

namespace {
// RGBA8 of n colours, each channel through float as the film stores it:
// rt::to_byte(float(c)), opaque. Two channels at a time where SSE2 is there: the same
// float rounding, double product, clamps (max(v, 0) is 0 for NaN, as to_byte's
// v > 0 ? v : 0) and truncation.
void colours_to_rgba(const rt::Colour* c, std::size_t n, std::uint8_t* out) {
#if defined(__SSE2__)
    const __m128d k255 = _mm_set1_pd(255.0), zero = _mm_setzero_pd();
    auto bytes = [&](__m128d v) {
        v = _mm_cvtps_pd(_mm_cvtpd_ps(v));  // through float
        return _mm_cvttpd_epi32(_mm_min_pd(_mm_max_pd(_mm_mul_pd(v, k255), zero), k255));
    };
    const __m128i alpha = _mm_set_epi32(255, 0, 0, 0);
    for (std::size_t i = 0; i < n; ++i, out += 4) {
        // x, y, z, 255 as four ints of 0..255, then as four bytes.
        __m128i v = _mm_or_si128(_mm_unpacklo_epi64(bytes(_mm_loadu_pd(&c[i].x)), bytes(_mm_set_sd(c[i].z))), alpha);
        v = _mm_packus_epi16(_mm_packs_epi32(v, v), v);
        const std::uint32_t px = std::uint32_t(_mm_cvtsi128_si32(v));
        std::memcpy(out, &px, 4);
    }
#else
    for (std::size_t i = 0; i < n; ++i, out += 4) {
        out[0] = rt::to_byte(float(c[i].x)), out[1] = rt::to_byte(float(c[i].y)), out[2] = rt::to_byte(float(c[i].z));
        out[3] = 255;
    }
#endif
}
}  // namespace

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
        thread_local std::vector<rt::PixelSample> keys;
        dirs.resize(std::size_t(w));
        colours.resize(std::size_t(w));
        basis.unit_directions(0, b, w, double(by * b), dirs.data());
        if (world.sampled(basis)) {
            keys.resize(std::size_t(w));
            for (int x = 0; x < w; ++x) keys[std::size_t(x)] = {x * b, by * b, 0};
        }
        world.trace_samples(basis, dirs.data(), keys.data(), std::size_t(w), stats, colours.data());
        if (stats.stopped) {
            stopped = true;
            return;
        }
        // Through float, as the film stores it: the same bytes as the coarse pass.
        colours_to_rgba(colours.data(), colours.size(), rgba.data() + std::size_t(by) * std::size_t(w) * 4);
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
