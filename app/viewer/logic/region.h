// Render region: a rectangle of the picture that keeps refining while the rest keeps
// its last picture. The rectangle comes from a drag in window coordinates; its pixels
// are rendered by accumulate_pixel, the renderer's own definition of a pixel, so a
// region pixel at N samples is the full render's pixel at N samples.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "display.h"
#include "film.h"
#include "image_view.h"
#include "parallel.h"
#include "world.h"

namespace rtview {

struct PixelRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // [x0, x1) x [y0, y1)
    bool empty() const { return x1 <= x0 || y1 <= y0; }
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
    bool operator==(const PixelRect& o) const { return x0 == o.x0 && y0 == o.y0 && x1 == o.x1 && y1 == o.y1; }
};

// The picture pixels a drag from (ax, ay) to (bx, by) covers: both end pixels
// included, cut to the picture; empty if it misses the picture.
PixelRect region_from_drag(const ViewTransform& t, int pic_w, int pic_h, double ax, double ay, double bx, double by);
// The same region in a film of another size (the film follows the window's size).
PixelRect scale_region(const PixelRect& r, int from_w, int from_h, int to_w, int to_h);

// The region's pixels as rendered so far.
struct RegionPicture {
    PixelRect rect;
    rt::Image image;               // rect.width() x rect.height(), resolved linear colour
    std::vector<int> row_samples;  // per row of the rect; 0: nothing yet (keep the old picture)
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
    // Renders with a pool of its own of `threads` workers (0: as many as the process pool has).
    explicit RegionRenderer(int threads = 0);
    // Renders on `pool`'s workers, shared (at least one); the pool must outlive it.
    explicit RegionRenderer(rt::ThreadPool& pool);
    ~RegionRenderer();
    RegionRenderer(const RegionRenderer&) = delete;
    RegionRenderer& operator=(const RegionRenderer&) = delete;

    // Renders `rect` of a width x height film of `world` seen through `camera`, up to
    // max_samples, in passes of 1, 1, 2, 4, ... samples, stopping after time_limit
    // seconds (0: none): once every pixel has its first sample, at once, even in the
    // middle of a pass or of a pixel (the rows finished keep their samples).
    void start(std::shared_ptr<const rt::World> world, const rt::Camera& camera, int width, int height,
               const PixelRect& rect, int max_samples, double time_limit = 0);
    // Raises the region's max_samples: it goes on from the samples it has (the same
    // pixels as a region started with that many). False (nothing done) if no region
    // renders, it failed, has a time limit, or already has that many.
    bool raise_samples(int max_samples);
    // Returns when no worker touches the region any more; a pixel's ray tree in
    // progress is stopped in the middle (as the renderer's cancel() does).
    void cancel();
    bool active() const;
    bool done() const;
    // Why the region stopped unfinished (a worker ran out of memory), or empty.
    std::string error() const;
    int samples() const;
    PixelRect rect() const;
    // A copy of the region if it changed since `version` (which it then updates).
    bool snapshot(RegionPicture& out, std::uint64_t& version) const;

    // For tests: called on the worker thread before each sample it traces, with the
    // picture pixel and the sample's number, so that a test can cancel at a known
    // point, in the middle of a pixel. Set it while no region renders; empty: none.
    void set_sample_hook(std::function<void(int x, int y, int sample)> hook) { sample_hook_ = std::move(hook); }

private:
    // As rt::Renderer's: runners posted to the pool, each taking one row.
    void kick_locked();
    void run_one();
    void finish_row_locked(int r, int s1, std::uint64_t gen, bool failed, bool cancelled, const std::vector<float>& row);
    // The pass after samples [.., s1): up to twice as many, as the renderer's.
    void next_pass_locked(int s1);
    std::unique_ptr<rt::ThreadPool> own_pool_;  // null when sharing one
    rt::ThreadPool* pool_ = nullptr;
    int max_runners_ = 1;
    int runners_ = 0;  // posted and not yet ended (under mutex_)
    mutable std::mutex mutex_;
    std::condition_variable idle_cv_;
    std::atomic<std::uint64_t> generation_{0};
    // Set with every new generation, so that the traces in progress stop (a pixel's
    // ray tree can take minutes); cleared by start() once no worker is busy.
    std::atomic<bool> stop_{false};
    int busy_ = 0;
    std::function<void(int, int, int)> sample_hook_;

    // The job (guarded by mutex_).
    std::shared_ptr<const rt::World> world_;
    rt::CameraBasis basis_;
    PixelRect rect_;
    bool active_ = false, done_ = false;
    std::string error_;
    int max_samples_ = 1;
    std::chrono::steady_clock::time_point deadline_ = std::chrono::steady_clock::time_point::max();
    int pass_s0_ = 0, pass_s1_ = 0;  // samples of the current pass
    int next_row_ = 0, rows_done_ = 0;
    int samples_done_ = 0;
    std::vector<float> sum_;  // 3 per pixel of the rect
    std::vector<int> row_samples_;
    std::uint64_t version_ = 1;
};

}  // namespace rtview
