// Render region (see region.h).
#include "region.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <new>
#include <thread>

#include "renderer.h"

namespace rtview {

PixelRect region_from_drag(const ViewTransform& t, int pic_w, int pic_h, double ax, double ay, double bx, double by) {
    double u0 = std::floor(t.to_picture_x(std::min(ax, bx))), u1 = std::floor(t.to_picture_x(std::max(ax, bx)));
    double v0 = std::floor(t.to_picture_y(std::min(ay, by))), v1 = std::floor(t.to_picture_y(std::max(ay, by)));
    PixelRect r;
    r.x0 = int(std::clamp(u0, 0.0, double(pic_w)));
    r.y0 = int(std::clamp(v0, 0.0, double(pic_h)));
    r.x1 = int(std::clamp(u1 + 1, 0.0, double(pic_w)));
    r.y1 = int(std::clamp(v1 + 1, 0.0, double(pic_h)));
    if (r.empty()) return {};
    return r;
}

PixelRect scale_region(const PixelRect& r, int from_w, int from_h, int to_w, int to_h) {
    if (r.empty() || from_w < 1 || from_h < 1) return {};
    if (from_w == to_w && from_h == to_h) return r;
    auto sc = [](int v, int from, int to, bool up) {
        double x = double(v) * to / from;
        return std::clamp(int(up ? std::ceil(x) : std::floor(x)), 0, to);
    };
    PixelRect s{sc(r.x0, from_w, to_w, false), sc(r.y0, from_h, to_h, false), sc(r.x1, from_w, to_w, true),
                sc(r.y1, from_h, to_h, true)};
    return s.empty() ? PixelRect{} : s;
}

void paste_region(const RegionPicture& reg, rt::Image& full) {
    const PixelRect& r = reg.rect;
    if (r.empty() || r.x1 > full.width || r.y1 > full.height || r.x0 < 0 || r.y0 < 0) return;
    for (int y = r.y0; y < r.y1; ++y) {
        if (reg.row_samples[std::size_t(y - r.y0)] == 0) continue;
        const float* src = &reg.image.rgb[3 * std::size_t(y - r.y0) * r.width()];
        std::copy(src, src + 3 * r.width(), &full.rgb[3 * (std::size_t(y) * full.width + r.x0)]);
    }
}

void paste_region_rgba8(const RegionPicture& reg, const DisplaySettings& s, int width, std::vector<std::uint8_t>& rgba) {
    const PixelRect& r = reg.rect;
    if (r.empty() || r.x0 < 0 || r.y0 < 0 || r.x1 > width || rgba.size() < 4 * std::size_t(width) * r.y1) return;
    std::vector<std::uint8_t> local;
    map_to_rgba8(reg.image, s, local);
    for (int y = r.y0; y < r.y1; ++y) {
        if (reg.row_samples[std::size_t(y - r.y0)] == 0) continue;
        const std::uint8_t* src = &local[4 * std::size_t(y - r.y0) * r.width()];
        std::copy(src, src + 4 * r.width(), &rgba[4 * (std::size_t(y) * width + r.x0)]);
    }
}

RegionRenderer::RegionRenderer(int threads) {
    if (threads <= 0) threads = std::max(1, rt::process_pool().workers());
    own_pool_ = std::make_unique<rt::ThreadPool>(threads + 1);  // (the size counts a loop's caller)
    pool_ = own_pool_.get();
    max_runners_ = threads;
}

RegionRenderer::RegionRenderer(rt::ThreadPool& pool) : pool_(&pool), max_runners_(pool.workers()) {
    if (max_runners_ > 0) return;
    own_pool_ = std::make_unique<rt::ThreadPool>(2);  // no worker to share: one of its own
    pool_ = own_pool_.get();
    max_runners_ = 1;
}

RegionRenderer::~RegionRenderer() {
    std::unique_lock<std::mutex> lock(mutex_);
    ++generation_;
    stop_ = true;
    active_ = false;
    // Runners still waiting in the pool hold `this`: each ends at once, finding no work.
    idle_cv_.wait(lock, [&] { return runners_ == 0; });
}

void RegionRenderer::cancel() {
    std::unique_lock<std::mutex> lock(mutex_);
    ++generation_;
    stop_ = true;
    active_ = false;
    idle_cv_.wait(lock, [&] { return busy_ == 0; });
}

void RegionRenderer::start(std::shared_ptr<const rt::World> world, const rt::Camera& camera, int width, int height,
                           const PixelRect& rect, int max_samples, double time_limit) {
    cancel();
    std::lock_guard<std::mutex> lock(mutex_);
    if (!world || rect.empty() || rect.x0 < 0 || rect.y0 < 0 || rect.x1 > width || rect.y1 > height) return;
    stop_ = false;  // (no worker is busy: cancel() waited)
    world_ = std::move(world);
    basis_ = rt::CameraBasis::make(camera, width, height, false);
    rect_ = rect;
    max_samples_ = std::max(1, max_samples);
    deadline_ = time_limit > 0 ? std::chrono::steady_clock::now() +
                                     std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                         std::chrono::duration<double>(std::min(time_limit, 1e9)))
                               : std::chrono::steady_clock::time_point::max();
    sum_.assign(3 * std::size_t(rect.width()) * rect.height(), 0.f);
    row_samples_.assign(std::size_t(rect.height()), 0);
    samples_done_ = 0;
    pass_s0_ = 0;
    pass_s1_ = 1;
    next_row_ = rows_done_ = 0;
    active_ = true;
    done_ = false;
    error_.clear();
    ++version_;
    kick_locked();
}

bool RegionRenderer::active() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return active_;
}

bool RegionRenderer::done() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return active_ && done_;
}

std::string RegionRenderer::error() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return active_ ? error_ : std::string();
}

int RegionRenderer::samples() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return samples_done_;
}

PixelRect RegionRenderer::rect() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return active_ ? rect_ : PixelRect{};
}

void RegionRenderer::kick_locked() {
    if (!active_ || done_) return;
    const int left = rect_.height() - next_row_;
    while (runners_ < max_runners_ && runners_ - busy_ < left) {
        ++runners_;
        pool_->post([this] { run_one(); });
    }
}

void RegionRenderer::run_one() {
    thread_local std::vector<float> row;
    std::unique_lock<std::mutex> lock(mutex_);
    if (!active_ || done_ || next_row_ >= rect_.height()) {
        if (--runners_ == 0) idle_cv_.notify_all();
        return;
    }
    const std::uint64_t gen = generation_.load();
    const int r = next_row_++;
    const int s0 = pass_s0_, s1 = pass_s1_;
    const PixelRect rect = rect_;
    std::shared_ptr<const rt::World> world = world_;
    const rt::CameraBasis basis = basis_;
    const int w = rect.width();
    // This row's sums are only written by whoever holds the row, under the lock.
    row.assign(sum_.begin() + 3 * std::ptrdiff_t(r) * w, sum_.begin() + 3 * std::ptrdiff_t(r + 1) * w);
    ++busy_;
    lock.unlock();

    rt::RayStats stats;
    stats.stop.flag = &stop_;
    // Every pixel gets its first sample whatever the time, as in the renderer.
    if (s0 > 0) stats.stop.deadline = deadline_;
    bool cancelled = false;
    // One sample at a time, so that a cancel stops a pixel between its samples (and,
    // through stats.stop, inside one). The renderer's order of additions: the sum
    // so far, then samples s0..s1-1.
    bool failed = false;  // out of memory: the region stops with a message
    try {
        for (int x = 0; x < w && !cancelled; ++x) {
            for (int s = s0; s < s1; ++s) {
                if (stats.stopped || generation_.load(std::memory_order_relaxed) != gen) {
                    cancelled = true;
                    break;
                }
                if (sample_hook_) sample_hook_(rect.x0 + x, rect.y0 + r, s);
                rt::accumulate_pixel(*world, basis, rect.x0 + x, rect.y0 + r, s, s + 1, &row[3 * std::size_t(x)],
                                     stats);
            }
        }
        cancelled |= stats.stopped;
    } catch (const std::bad_alloc&) {
        failed = true;
    }
    world.reset();
    lock.lock();
    --busy_;
    finish_row_locked(r, s1, gen, failed, cancelled, row);
    --runners_;
    kick_locked();  // the next row goes behind whatever else waits for the pool
    if (busy_ == 0 || runners_ == 0) idle_cv_.notify_all();
}

// Called with mutex_ held, after row r of the pass up to s1 was traced for generation
// gen: its sums into the region if it is complete and still wanted; the region's end
// if it failed or ran out of time.
void RegionRenderer::finish_row_locked(int r, int s1, std::uint64_t gen, bool failed, bool cancelled,
                                       const std::vector<float>& row) {
    if (generation_.load() != gen) return;
    if (failed) {
        error_ = "out of memory while rendering the region";
        done_ = true;
        return;
    }
    const auto now = std::chrono::steady_clock::now();
    if (cancelled) {
        // Out of time in the middle of a pass: the rows committed keep their samples.
        if (now >= deadline_) done_ = true;
        return;
    }
    const int w = rect_.width();
    std::copy(row.begin(), row.end(), sum_.begin() + 3 * std::ptrdiff_t(r) * w);
    row_samples_[std::size_t(r)] = s1;
    ++version_;
    if (++rows_done_ < rect_.height()) return;
    // The pass is complete: the next one doubles the samples, as the renderer's do.
    samples_done_ = s1;
    if (s1 >= max_samples_ || now >= deadline_) {
        done_ = true;
        return;
    }
    next_pass_locked(s1);
}

void RegionRenderer::next_pass_locked(int s1) {
    pass_s0_ = s1;
    pass_s1_ = std::min(max_samples_, s1 + std::max(1, std::min(s1, 16)));
    next_row_ = rows_done_ = 0;
}

bool RegionRenderer::raise_samples(int max_samples) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!active_ || !error_.empty() || deadline_ != std::chrono::steady_clock::time_point::max() ||
        max_samples <= max_samples_)
        return false;
    max_samples_ = max_samples;
    if (done_) {
        // Finished: on with the next pass (a region running on takes the new limit
        // when its pass ends).
        done_ = false;
        next_pass_locked(samples_done_);
        kick_locked();
    }
    return true;
}

bool RegionRenderer::snapshot(RegionPicture& out, std::uint64_t& version) const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!active_ || version == version_) return false;
    version = version_;
    out.rect = rect_;
    out.samples = samples_done_;
    out.row_samples = row_samples_;
    const std::size_t n = std::size_t(rect_.width()) * rect_.height();
    out.image.width = rect_.width();
    out.image.height = rect_.height();
    out.image.rgb.resize(3 * n);
    for (int r = 0; r < rect_.height(); ++r) {
        const int k = row_samples_[std::size_t(r)];
        // As Film::pixel resolves: one sample as is, more divided in double.
        const double inv = k > 1 ? 1.0 / k : 1.0;
        for (std::size_t i = std::size_t(r) * rect_.width(); i < std::size_t(r + 1) * rect_.width(); ++i)
            for (int c = 0; c < 3; ++c)
                out.image.rgb[3 * i + c] = k > 1 ? float(sum_[3 * i + c] * inv) : sum_[3 * i + c];
    }
    return true;
}

}  // namespace rtview
