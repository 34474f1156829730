// What a render to a file asks for, as `raytracer`, `raytracer-mpi` and the viewer's
// final render take it, with the limits every front end accepts, and the one place
// where it becomes the renderer's settings: the three make the same picture.
#pragma once

#include <optional>

#include "renderer.h"

namespace rt {

// The limits of the render options (the command lines, the viewer's fields).
constexpr int kMaxSamples = 65536;          // samples per pixel
constexpr int kMaxThreads = 256;            // render threads of one process
constexpr int kDefaultMaxDepth = 20;        // the original's recursion limit
constexpr int kMaxRecursion = 1000;         // the highest --max-depth
constexpr int kMinTile = 8, kMaxTile = 256, kDefaultTile = 32;  // tile side, pixels
constexpr double kMaxTimeLimit = 1e7;       // seconds
// The limits of --aa-threshold: the sum of the red, green and blue differences of two
// colours in 0-1 units, as POV-Ray's Antialias_Threshold measures them.
constexpr double kMaxAaThreshold = 3.0;
// The most samples a pixel gets when only a threshold is given.
constexpr int kDefaultAaMaxSamples = 16;

struct RenderRequest {
    std::optional<int> samples;          // 1..kMaxSamples; unset: see max_samples()
    double time_limit = 0;               // seconds, 0: none (else up to kMaxTimeLimit)
    std::optional<double> aa_threshold;  // adaptive anti-aliasing, 0..kMaxAaThreshold
    int threads = 0;                     // 0: all hardware threads
    int max_depth = kDefaultMaxDepth;    // 1..kMaxRecursion
    int tile = kDefaultTile;             // kMinTile..kMaxTile (raytracer-mpi's tiles)
    bool mirror = false;
};

// The samples per pixel the render stops at: the ones asked for; with a time limit and
// none asked for, as many as fit (kMaxSamples); a threshold alone, kDefaultAaMaxSamples;
// else the original's one.
int max_samples(const RenderRequest& r);

// What the renderer is asked for a width x height picture: no preview passes (nobody
// watches one), and without a time limit one pass holding every sample (nothing is
// gained by stopping between passes, and the pass fraction is then the progress).
RenderSettings final_settings(const RenderRequest& r, int width, int height);

}  // namespace rt
