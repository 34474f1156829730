// The final render (see final_render.h). The settings are raytracer's
// (rt::final_settings): any difference would show up as different bytes in the file.
// tests/viewer/test_final_render.cpp compares the two.
#include "final_render.h"

#include <algorithm>
#include <cstdio>
#include <vector>

#include "image_io.h"

namespace rtview {

namespace {
rt::Status usage(std::string message) { return rt::Status::error(std::move(message), rt::kExitUsage); }
}  // namespace

rt::RenderRequest final_render_request(int samples, double time_limit, double aa_threshold) {
    rt::RenderRequest r;
    if (samples > 0) r.samples = samples;
    r.time_limit = time_limit;
    if (aa_threshold >= 0) r.aa_threshold = aa_threshold;
    return r;
}

FinalRender::FinalRender(rt::ThreadPool& pool) : renderer_(pool) {}

FinalRender::~FinalRender() { renderer_.cancel(); }

rt::Status FinalRender::start(const rt::Scene& scene, const std::string& out_path, const rt::RenderRequest& request,
                              const rt::World* previous) {
    cancel();
    if (rt::format_from_path(out_path) == rt::ImageFormat::Unknown)
        return usage("'" + out_path + "': the name must end in .png, .ppm, .pfm or .exr");
    if (scene.width < 1 || scene.height < 1) return usage("the scene has no picture size");
    std::shared_ptr<const rt::World> world = rt::compile_world(scene, previous);
    settings_ = rt::final_settings(request, scene.width, scene.height);
    width_ = scene.width;
    height_ = scene.height;
    out_ = out_path;
    renderer_.start(world, settings_);
    time_left_.clear();
    active_ = true;
    return {};
}

void FinalRender::cancel() {
    if (!active_) return;
    renderer_.cancel();
    active_ = false;
}

bool FinalRender::done() const { return active_ && renderer_.progress().done; }

double FinalRender::fraction() const {
    if (!active_) return 0;
    rt::RenderProgress p = renderer_.progress();
    if (p.done) return 1;
    double f = rt::progress_fraction(p, settings_.max_samples);
    if (settings_.time_limit > 0) f = std::max(f, p.elapsed / settings_.time_limit);
    return std::clamp(f, 0.0, 1.0);
}

void TimeLeft::add(double elapsed, double fraction) {
    if (!points_.empty() && elapsed <= points_.back().first) return;
    points_.emplace_back(elapsed, fraction);
    // Keep the points of the last kWindow seconds, and one before them.
    while (points_.size() > 2 && points_[1].first <= elapsed - kWindow) points_.pop_front();
}

double TimeLeft::seconds() const {
    if (points_.size() < 2) return -1;
    const auto& [t1, f1] = points_.back();
    // From the oldest point kept (kWindow ago, or the start) to now.
    const auto& [t0, f0] = points_.front();
    if (t1 - t0 < 0.5 || f1 < 0.02 || !(f1 > f0)) return -1;
    return (1 - f1) * (t1 - t0) / (f1 - f0);
}

double FinalRender::time_left() {
    if (!active_) return -1;
    time_left_.add(renderer_.progress().elapsed, fraction());
    return time_left_.seconds();
}

std::string FinalRender::summary() const {
    const rt::RenderProgress p = renderer_.progress();
    char buf[200];
    if (p.refining < 0) {
        std::snprintf(buf, sizeof buf, "%dx%d, %d samples per pixel, %.1f s", p.width, p.height, p.samples, p.elapsed);
        return buf;
    }
    // Adaptive: the pixels got from one sample to max_samples each.
    std::vector<std::uint32_t> counts;
    int w = 0, h = 0;
    renderer_.sample_counts(counts, w, h);
    std::uint64_t sum = 0;
    std::uint32_t most = 0;
    for (std::uint32_t c : counts) sum += c, most = std::max(most, c);
    const double mean = counts.empty() ? 0.0 : double(sum) / double(counts.size());
    std::snprintf(buf, sizeof buf, "%dx%d, adaptive: up to %u samples per pixel, %.1f on average, %.1f s", p.width,
                  p.height, unsigned(most), mean, p.elapsed);
    return buf;
}

rt::Status FinalRender::write() {
    if (!active_) return usage("no render to write");
    rt::RenderProgress p = renderer_.progress();
    if (!p.done) return usage("the render is not finished");
    if (!p.error.empty()) {
        active_ = false;
        return usage(p.error);
    }
    if (rt::is_float_format(rt::format_from_path(out_))) {
        // The film's floats (New: .pfm, .exr), as raytracer writes them.
        const rt::Image img = renderer_.snapshot();
        active_ = false;
        if (img.width != width_ || img.height != height_ || p.samples < 1)
            return usage("the renderer returned an incomplete picture");
        return rt::write_image(out_, img);
    }
    rt::ZeroedArray<std::uint8_t> pixels;
    int w = 0, h = 0;
    renderer_.snapshot_rgb8(pixels, w, h);
    active_ = false;
    if (w != width_ || h != height_ || p.samples < 1) return usage("the renderer returned an incomplete picture");
    return rt::write_rgb8(out_, w, h, pixels.data(), pixels.size());
}

}  // namespace rtview
