// Preview pacing: how coarse a preview of a moving view must be so that it lands
// within a frame budget, from the measured cost of recent previews (dynamic
// resolution). No window, no GL: unit-tested.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <vector>

#include "camera.h"
#include "renderer.h"
#include "world.h"

namespace rtview {

inline double seconds_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

class PreviewPacer {
public:
    // The first preview of a film of `rays` primary rays took `seconds` (from start to
    // the end of the pass). Recent passes weigh most; a single slow outlier (another
    // process took the CPU for a moment) moves the estimate only part of the way.
    void measured(double rays, double seconds);
    // Seconds per primary ray, as estimated (0 before any measurement).
    double seconds_per_ray() const { return per_ray_; }

    // Block size (a power of 2, 2..64) of the first coarse pass of a w x h film so that
    // it is expected within `budget` seconds. Before any measurement: 8.
    int coarse_block(int width, int height, double budget) const;
    // The same for the viewer's own preview, whose blocks need not be powers of 2:
    // the smallest block, 1..64, expected within `budget`. Before any measurement: 8.
    int preview_block(int width, int height, double budget) const;

private:
    double per_ray_ = 0;
};

// A preview of a film_w x film_h picture of `world` through `camera`: one ray per
// `block` x `block` block, through its corner pixel (the rays of the renderer's coarse
// pass of that block size), as RGBA8 of ceil(w / block) x ceil(h / block) pixels: a
// request to `renderer` (RenderSettings::step), which renders it on its pool's workers
// while this thread waits. It stops after `time_limit` seconds (0: none), even in the
// middle of a ray tree (a deep one can take minutes): the pixels not traced then repeat
// the one above them, and the result says how many pixels were traced.
struct PreviewResult {
    std::uint64_t traced = 0;  // pixels traced
    bool stopped = false;      // the time limit ended it before every pixel was traced
};
PreviewResult trace_preview(rt::Renderer& renderer, std::shared_ptr<const rt::World> world, const rt::Camera& camera,
                            int film_w, int film_h, int block, double time_limit, std::vector<std::uint8_t>& rgba,
                            int& width, int& height);

}  // namespace rtview
