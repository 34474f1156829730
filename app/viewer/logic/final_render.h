// The final render: the scene at its own picture_size on the same rt::Renderer and
// with the same settings as the `raytracer` command line, so that the file it writes
// is byte for byte what `raytracer --samples N SCENE OUT` writes. Used by the
// window's "Render to file..." and by `raytracer-view --headless SCENE --render OUT`.
#pragma once

#include <deque>
#include <memory>
#include <string>

#include "render_request.h"
#include "renderer.h"
#include "scene.h"
#include "status.h"
#include "world.h"

namespace rtview {

// The viewer's render settings (samples 0, aa_threshold < 0: not given) as the
// command line's `--samples samples --time-limit time_limit --aa-threshold
// aa_threshold`; rt::final_settings makes of it what `raytracer` renders.
rt::RenderRequest final_render_request(int samples, double time_limit, double aa_threshold = -1);

// The time a render will still take, from its progress over the last few seconds (a
// render's pace changes: adaptive passes slow down as they near the end, so the pace
// since the start promises too little). add() its elapsed time and fraction done as
// it goes; seconds() < 0 until there is a pace to go by.
class TimeLeft {
public:
    static constexpr double kWindow = 5;  // seconds of progress the pace is taken over
    void add(double elapsed, double fraction);
    double seconds() const;
    void clear() { points_.clear(); }

private:
    std::deque<std::pair<double, double>> points_;  // (elapsed, fraction), oldest first
};

class FinalRender {
public:
    explicit FinalRender(rt::ThreadPool& pool);  // on a shared pool (see rt::Renderer)
    ~FinalRender();
    FinalRender(const FinalRender&) = delete;
    FinalRender& operator=(const FinalRender&) = delete;

    // Starts rendering `scene` (its own camera and picture size) for `out_path`, as
    // `request` asks (its threads, max_depth and tile are not used: the pool's
    // threads, the scene's recursion limit). `previous`, if it has the same geometry,
    // lends its BVH. On an error (a bad output name) starts nothing.
    rt::Status start(const rt::Scene& scene, const std::string& out_path, const rt::RenderRequest& request,
                     const rt::World* previous = nullptr);
    void cancel();
    bool active() const { return active_; }
    bool done() const;
    // 0..1, as the command line's progress bar counts it.
    double fraction() const;
    // Seconds still to go (TimeLeft), < 0 while unknown; call it as the progress is
    // shown (each call adds a point).
    double time_left();
    rt::RenderProgress progress() const { return renderer_.progress(); }
    const std::string& out_path() const { return out_; }
    // Once done(): writes the picture atomically (PNG or PPM by the name) and ends
    // the render. On failure the target is untouched.
    rt::Status write();
    // What the finished render gave, for the message after it is written: "WxH, N
    // samples per pixel, T s"; adaptive, the most a pixel got and the average.
    std::string summary() const;
    // Blocks until done (for the headless binary). False if cancelled meanwhile.
    bool wait_for(double seconds) { return renderer_.wait_for(seconds); }

private:
    rt::Renderer renderer_;
    rt::RenderSettings settings_;
    std::string out_;
    int width_ = 0, height_ = 0;
    bool active_ = false;
    TimeLeft time_left_;
};

}  // namespace rtview
