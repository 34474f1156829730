// Render region: a rectangle of the picture that keeps refining while the rest keeps
// its last picture. The rectangle comes from a drag in window coordinates; its pixels
// are a crop of rt::Renderer's (RenderSettings::crop), so a region pixel at N samples
// is the full render's pixel at N samples.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "display.h"
#include "film.h"
#include "image_view.h"
#include "parallel.h"
#include "renderer.h"
#include "world.h"

namespace rtview {

using PixelRect = rt::PixelWindow;  // [x0, x1) x [y0, y1) of the picture

// The picture pixels a drag from (ax, ay) to (bx, by) covers: both end pixels
// included, cut to the picture; empty if it misses the picture.
PixelRect region_from_drag(const ViewTransform& t, int film_w, int film_h, double ax, double ay, double bx, double by);

// The region's pixels as rendered so far.
struct RegionPicture {
    PixelRect rect;
    rt::Image image;               // rect.width() x rect.height(), resolved linear colour
    std::vector<int> row_samples;  // per row of the rect, its pixels' fewest samples; 0: keep the old picture
    int samples = 0;               // complete everywhere in the rect
};
// Copies the rows that have samples into `full` (the whole picture, same size as the
// world the region was rendered for).
void paste_region(const RegionPicture& region, rt::Image& full);
// The same into display bytes of a picture `width` wide.
void paste_region_rgba8(const RegionPicture& region, const DisplaySettings& settings, int width,
                        std::vector<std::uint8_t>& rgba);

class RegionRenderer {
public:
    // Renders on `pool`'s workers, shared (at least one); the pool must outlive it.
    explicit RegionRenderer(rt::ThreadPool& pool) : renderer_(pool) {}

    // Renders `rect` of a width x height film of `world` seen through `camera`, up to
    // max_samples, in the renderer's passes (1, 1, 2, 4, ... samples), stopping after
    // time_limit seconds (0: none): once every pixel has its first sample, at once, even
    // in the middle of a pass (the tiles finished keep their samples).
    void start(std::shared_ptr<const rt::World> world, const rt::Camera& camera, int width, int height,
               const PixelRect& rect, int max_samples, double time_limit = 0);
    // Raises the region's max_samples: it goes on from the samples it has (the same
    // pixels as a region started with that many). False (nothing done) if no region
    // renders, it failed, has a time limit, or already has that many.
    bool raise_samples(int max_samples);
    // Returns when no worker touches the region any more (rt::Renderer::cancel).
    void cancel();
    // Between start() and cancel() (readable from any thread).
    bool active() const { return active_.load(); }
    bool done() const;
    // Why the region stopped unfinished (a worker ran out of memory), or empty.
    std::string error() const;
    int samples() const;
    PixelRect rect() const { return active() ? rect_ : PixelRect{}; }
    // A copy of the region if it changed since `version` (which it then updates).
    bool snapshot(RegionPicture& out, std::uint64_t& version) const;
    // The renderer of the region (tests set its task_hook while no region renders).
    rt::Renderer& renderer() { return renderer_; }

private:
    rt::Renderer renderer_;
    PixelRect rect_;
    std::atomic<bool> active_{false};
};

}  // namespace rtview
