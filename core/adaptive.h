// Adaptive anti-aliasing: after every pixel's first sample, passes add samples only to
// the pixels whose estimate has not settled. Between two passes, decide_rows() reads
// the film (counts, sums, sums of squares) and marks the pixels to refine; a pass then
// takes each marked pixel from n to refine_count(n) samples with refine_row(). Both are
// pure functions of the film, so the picture is the same whoever renders which pixel.
#pragma once

#include <cstddef>
#include <cstdint>

#include "camera.h"
#include "film.h"
#include "world.h"

namespace rt {

// The sample count a pixel being refined goes to from n: 6, then twice as many, at most
// max. (Of 4 to 8 first, 6 reached the bench scenes' target errors with the fewest rays:
// fewer samples too often all fall on one side of an edge and stop, more are wasted on
// pixels that only border one.)
inline std::uint32_t refine_count(std::uint32_t n, std::uint32_t max) {
    const std::uint32_t next = n < 6 ? 6 : 2 * n;
    return next < max ? next : max;
}

// Pixels of rows [y0, y1) to refine in the next pass: active[idx] = 1 (else 0) where
// the pixel has n < max_samples samples and
//   - its colour (clamped mean) differs from a neighbour's (left, right, above or
//     below) by n * threshold or more: with one sample, it stands out; with n, an
//     edge could still hide in the 1/n of it that its samples missed, or
//   - n > 1 and the standard error of the mean of its samples is threshold / 4 or more.
// Every pixel has at least one sample. `changed` marks the pixels refined by the last
// pass (null: decide every pixel, as the first time): only those and their neighbours
// can decide differently, all others stay 0. Returns the number of pixels marked.
std::size_t decide_rows(const Film& film, double threshold, int max_samples, const std::uint8_t* changed, int y0,
                        int y1, std::uint8_t* active);

// Continues the pixels (x0 + k, y), k < n, whose n1[k] > n0[k] with samples
// [n0[k], n1[k]), in sample order, into sums[3k..3k+2] (as accumulate_pixel adds them)
// and squares[k] (the sum of the squared colours, clamped to 0..1, that decide_rows
// reads; for n0[k] == 1 it starts from the first sample, the sum itself). The traces
// go in batches through World::trace_units, which gives trace_camera's colours.
void refine_row(const World& world, const CameraBasis& camera, int x0, int y, int n, const std::uint32_t* n0,
                const std::uint32_t* n1, float* sums, float* squares, RayStats& stats);
// The same for the w x h pixels from (x0, y0), the arrays row by row, all their samples
// traced in one batch.
void refine_rect(const World& world, const CameraBasis& camera, int x0, int y0, int w, int h,
                 const std::uint32_t* n0, const std::uint32_t* n1, float* sums, float* squares, RayStats& stats);

}  // namespace rt
