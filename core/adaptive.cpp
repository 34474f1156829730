// Adaptive anti-aliasing (adaptive.h). The decision reads clamped mean colours: what a
// pixel shows is its mean cut to 0..1, so differences beyond that cannot be seen.
#include "adaptive.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

#include "renderer.h"

namespace rt {

namespace {

// The share of the threshold the standard error of a refined pixel's mean must stay
// under: a pixel whose samples spread keeps refining until its mean is known to within
// a quarter of the threshold.
constexpr double kErrorShare = 0.25;

// The neighbours a pixel is compared with: left, right, above, below (as POV-Ray's
// anti-aliasing compares each pixel with the one to its left and the one above). The
// diagonals were tried: they mark more pixels for little gain (2.5-7.5 % more rays for
// the same error on the benchmark scenes).
constexpr std::pair<int, int> kNeighbours[4] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};

inline float clamp01(float v) { return v > 0 ? (v < 1 ? v : 1) : 0; }  // NaN: 0

inline float squared(const float* c) {
    const float r = clamp01(c[0]), g = clamp01(c[1]), b = clamp01(c[2]);
    return r * r + g * g + b * b;
}

// What the decision compares: a pixel's clamped mean (its sum times 1/n, each channel
// clamped), and the distance of two colours, (|dr| + |dg|) + |db| in float. Every pixel
// has a sample by the time anything is decided; 1/1 is exactly 1. Counts are at most
// 65536, so they go to float through int (one instruction, in a loop made wide).
inline float inverse(std::uint32_t n) { return 1.0f / float(std::max(int(n), 1)); }
// The same value, for one pixel at a time, where most have one sample: no division.
inline float inverse_one(std::uint32_t n) { return n <= 1 ? 1.0f : 1.0f / float(int(n)); }
inline void clamped_mean(const Film& film, std::size_t idx, float* rgb) {
    const float inv = inverse_one(film.count[idx]);
    const float* s = &film.sum[3 * idx];
    rgb[0] = clamp01(s[0] * inv), rgb[1] = clamp01(s[1] * inv), rgb[2] = clamp01(s[2] * inv);
}
inline float distance(float r0, float g0, float b0, float r1, float g1, float b1) {
    return std::abs(r0 - r1) + std::abs(g0 - g1) + std::abs(b0 - b1);
}

// Whether the standard error of the mean of pixel idx, with n >= 2 samples, is
// `limit` or more. mean: its clamped mean.
bool spread(const Film& film, std::size_t idx, std::uint32_t n, const float* mean, double limit) {
    const double m2 = double(mean[0]) * mean[0] + double(mean[1]) * mean[1] + double(mean[2]) * mean[2];
    const double variance = std::max(0.0, double(film.squares[idx]) / n - m2);
    return variance / (n - 1) >= limit * limit;
}

// The decision for one pixel; contrast() gives its largest distance to a neighbour,
// asked for only when it can matter. Samples that all agree still leave about 1/n of
// the pixel unseen, where an edge could hide and move the mean by up to contrast / n:
// so a pixel that stands out keeps refining until n * threshold passes its contrast,
// even if its samples agree. (Clamped colours are at most 3 apart.)
template <class Contrast>
inline bool decide(const Film& film, std::size_t idx, const float* mean, Contrast contrast, float threshold,
                   int max_samples, double limit) {
    const std::uint32_t n = film.count[idx];
    if (n >= std::uint32_t(max_samples)) return false;
    if (n > 1 && spread(film, idx, n, mean, limit)) return true;
    const float needed = threshold * float(int(n));
    return needed <= 3 && contrast() >= needed;
}

// The first decision: every pixel of rows [y0, y1), a row at a time, over planes of
// clamped means (r, g and b apart, so that the distances to each neighbour are one
// loop the compiler makes wide).
std::size_t decide_all(const Film& film, float threshold, int max_samples, double limit, int y0, int y1,
                       std::uint8_t* active) {
    const int w = film.width, h = film.height;
    thread_local std::vector<float> planes, best;
    planes.resize(9 * std::size_t(w));  // rows y-1, y, y+1 (by y % 3): r, g, b planes of w
    best.resize(std::size_t(w));
    int held[3] = {-1, -1, -1};
    auto plane = [&](int y) -> const float* {
        if (y < 0 || y >= h) return nullptr;
        float* p = planes.data() + 3 * std::size_t(w) * std::size_t(y % 3);
        if (held[y % 3] != y) {
            // clamped_mean(), pixel by pixel, in loops without branches; a row of one
            // sample a pixel (every row, the first time) without the divisions.
            const std::uint32_t* count = &film.count[std::size_t(y) * w];
            const float* sum = &film.sum[3 * std::size_t(y) * w];
            std::uint32_t several = 0;
            for (int x = 0; x < w; ++x) several |= count[x] - 1;
            if (several == 0) {
                for (int x = 0; x < w; ++x)
                    p[x] = clamp01(sum[3 * x]), p[w + x] = clamp01(sum[3 * x + 1]), p[2 * w + x] = clamp01(sum[3 * x + 2]);
            } else {
                for (int x = 0; x < w; ++x) {
                    const float inv = inverse(count[x]);
                    p[x] = clamp01(sum[3 * x] * inv);
                    p[w + x] = clamp01(sum[3 * x + 1] * inv);
                    p[2 * w + x] = clamp01(sum[3 * x + 2] * inv);
                }
            }
            held[y % 3] = y;
        }
        return p;
    };
    std::size_t marked = 0;
    for (int y = y0; y < y1; ++y) {
        const float* me = plane(y);
        std::fill(best.begin(), best.end(), 0.0f);
        float* b = best.data();
        for (const auto& [dx, dy] : kNeighbours) {
            const float* o = plane(y + dy);
            if (!o) continue;
            const int lo = std::max(0, -dx), hi = std::min(w, w - dx);
            const float *r = me, *g = me + w, *bl = me + 2 * w, *orr = o + dx, *og = o + w + dx, *ob = o + 2 * w + dx;
            for (int x = lo; x < hi; ++x) {
                const float d = distance(r[x], g[x], bl[x], orr[x], og[x], ob[x]);
                b[x] = b[x] > d ? b[x] : d;
            }
        }
        // decide(), pixel by pixel (with every contrast at hand): the contrast test in a
        // loop without branches, then the spread of the few with more than one sample.
        std::uint8_t* act = active + std::size_t(y) * w;
        const std::uint32_t* count = &film.count[std::size_t(y) * w];
        const std::uint32_t max = std::uint32_t(max_samples);
        int several = 0;
        for (int x = 0; x < w; ++x) {
            act[x] = std::uint8_t((count[x] < max) & (b[x] >= threshold * float(int(count[x]))));
            several |= int(count[x] > 1);
        }
        for (int x = 0; x < w && several; ++x) {
            if (act[x] || count[x] <= 1 || count[x] >= max) continue;
            const float mean[3] = {me[x], me[w + x], me[2 * w + x]};
            act[x] = spread(film, std::size_t(y) * w + x, count[x], mean, limit);
        }
        for (int x = 0; x < w; ++x) marked += act[x];
    }
    return marked;
}

// Whether any byte of [p, p + n) is set, eight at a time.
bool any_set(const std::uint8_t* p, int n) {
    int i = 0;
    for (; i + 8 <= n; i += 8) {
        std::uint64_t v;
        std::memcpy(&v, p + i, 8);
        if (v) return true;
    }
    for (; i < n; ++i)
        if (p[i]) return true;
    return false;
}

// The largest distance from pixel (x, y)'s clamped mean to one of its neighbours'.
float contrast_at(const Film& film, int x, int y, const float* me) {
    float best = 0;
    for (const auto& [dx, dy] : kNeighbours) {
        const int nx = x + dx, ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= film.width || ny >= film.height) continue;
        float o[3];
        clamped_mean(film, std::size_t(ny) * film.width + nx, o);
        const float d = distance(me[0], me[1], me[2], o[0], o[1], o[2]);
        best = best > d ? best : d;
    }
    return best;
}

// A later decision: only a changed pixel and its four neighbours can decide anything
// but 0 (see decide_rows); each is decided alone, reading its neighbours' means.
std::size_t decide_near(const Film& film, float threshold, int max_samples, double limit,
                        const std::uint8_t* changed, int y0, int y1, std::uint8_t* active) {
    const int w = film.width, h = film.height;
    std::size_t marked = 0;
    for (int y = y0; y < y1; ++y) {
        std::uint8_t* act = active + std::size_t(y) * w;
        std::fill(act, act + w, std::uint8_t(0));
        int lo = w, hi = -1;  // the columns marked to decide
        for (int r = std::max(0, y - 1); r <= std::min(h - 1, y + 1); ++r) {
            const std::uint8_t* c = changed + std::size_t(r) * w;
            for (int x0 = 0; x0 < w; x0 += 8) {
                if (x0 + 8 <= w && !any_set(c + x0, 8)) continue;
                for (int cx = x0; cx < std::min(w, x0 + 8); ++cx) {
                    if (!c[cx]) continue;
                    // The pixels of row y whose decision reads this one: below or above
                    // it, or (in its own row) it and its left and right neighbours.
                    // Mark them as seen with 2; they are decided below.
                    const int reach = r == y ? 1 : 0;
                    for (int x = std::max(0, cx - reach); x <= std::min(w - 1, cx + reach); ++x) act[x] |= 2;
                    lo = std::min(lo, cx - reach), hi = std::max(hi, cx + reach);
                }
            }
        }
        for (int x = std::max(0, lo); x <= std::min(w - 1, hi); ++x) {
            if (!act[x]) continue;
            const std::size_t idx = std::size_t(y) * w + x;
            float me[3];
            clamped_mean(film, idx, me);
            act[x] = decide(
                film, idx, me, [&] { return contrast_at(film, x, y, me); }, threshold, max_samples, limit);
            marked += act[x];
        }
    }
    return marked;
}

}  // namespace

std::size_t decide_rows(const Film& film, double threshold, int max_samples, const std::uint8_t* changed, int y0,
                        int y1, std::uint8_t* active) {
    const double limit = threshold * kErrorShare;
    if (!changed) return decide_all(film, float(threshold), max_samples, limit, y0, y1, active);
    return decide_near(film, float(threshold), max_samples, limit, changed, y0, y1, active);
}

void refine_rect(const World& world, const CameraBasis& camera, int x0, int y0, int w, int h,
                 const std::uint32_t* n0, const std::uint32_t* n1, float* sums, float* squares, RayStats& stats) {
    thread_local std::vector<Vec3> dirs;
    thread_local std::vector<Colour> colours;
    thread_local std::vector<PixelSample> keys;
    dirs.clear();
    keys.clear();
    const bool sampled = world.sampled(camera);
    const std::size_t n = std::size_t(w) * std::size_t(h);
    for (std::size_t k = 0; k < n; ++k) {
        const int x = x0 + int(k % std::size_t(w)), y = y0 + int(k / std::size_t(w));
        for (std::uint32_t s = n0[k]; s < n1[k]; ++s) {
            double dx, dy;
            sample_offset(x, y, int(s), dx, dy);
            dirs.push_back(normalize(camera.direction(x + dx, y + dy)));
            if (sampled) keys.push_back({x, y, int(s)});
        }
    }
    if (dirs.empty()) return;
    colours.resize(dirs.size());
    world.trace_samples(camera, dirs.data(), keys.data(), dirs.size(), stats, colours.data());
    const Colour* c = colours.data();
    for (std::size_t k = 0; k < n; ++k) {
        if (n1[k] <= n0[k]) continue;
        float* sum = sums + 3 * k;
        float sq = n0[k] <= 1 ? squared(sum) : squares[k];
        for (std::uint32_t s = n0[k]; s < n1[k]; ++s, ++c) {
            const float f[3] = {float(c->x), float(c->y), float(c->z)};
            sum[0] += f[0], sum[1] += f[1], sum[2] += f[2];
            sq += squared(f);
        }
        squares[k] = sq;
    }
}

void refine_row(const World& world, const CameraBasis& camera, int x0, int y, int n, const std::uint32_t* n0,
                const std::uint32_t* n1, float* sums, float* squares, RayStats& stats) {
    refine_rect(world, camera, x0, y, n, 1, n0, n1, sums, squares, stats);
}

}  // namespace rt
