// The render controller (see render_controller.h): world compilation, render
// restarts with preview pacing, and the film texture.
#include "render_controller.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <type_traits>
#include <variant>

#include "shapes.h"

namespace rtview {

namespace {

// Time the first preview of a moving view may take: a 30 Hz stream of input then
// still gets a new picture on nearly every frame, with room left for the UI itself.
constexpr double kPreviewBudget = 0.025;
// What the preview of a moving view may take of a frame (traced on every core while
// the UI thread waits): half of a 30 Hz input stream's 33 ms, the rest left for the
// UI. Measured on 2 cores (bench/viewer-bench.sh): things-like at 1245x700 orbits at
// 29.5 pictures a second in 4x4-5x5 blocks (6x6 at 10 ms); the default scene in 3x3.
constexpr double kUiPreviewBudget = 0.016;
// A preview that takes this long is stopped (a deep ray tree could hold the UI for
// minutes); the rows left repeat the last traced row, and the next one is coarser.
constexpr double kPreviewDeadline = 0.050;
// The view counts as resting this long after its last change: the render refines.
constexpr double kRestAfter = 0.15;

// What of a render's progress shows on screen: a new one of these means new pixels.
std::array<std::uint64_t, 5> signature(const rt::RenderProgress& p) {
    return {p.generation, std::uint64_t(p.passes), std::uint64_t(p.coarse_level), std::uint64_t(p.samples),
            std::uint64_t(p.pass_fraction * 16)};
}

}  // namespace

RenderController::RenderController(rt::ThreadPool& pool, bool interactive, int max_samples, double time_limit,
                                   double aa_threshold)
    : interactive_(interactive),
      renderer_(pool),
      preview_(pool),
      max_samples_(max_samples),
      time_limit_(time_limit),
      aa_threshold_(aa_threshold) {}

RenderController::~RenderController() {
    preview_.cancel();
    renderer_.cancel();
}

void RenderController::sync_world(const Document& doc) {
    sync_.sync(doc);
    if (!doc.has_scene()) clear();
}

void RenderController::adopt_world(std::shared_ptr<const rt::World> world, std::uint64_t content_version) {
    sync_.adopt(std::move(world), content_version);
}

void RenderController::clear() {
    at_ = nullptr;
    if (started_world_) {
        renderer_.cancel();
        started_world_ = nullptr;
    }
}

void RenderController::set_max_samples(int n) {
    if (n == max_samples_) return;
    // More samples for the picture being refined: it goes on from the ones it has.
    if (n > max_samples_ && !settings_changed_ && started_world_ && renderer_.raise_samples(n)) {
        max_samples_ = n;
        // Not finished any more: its end, its time and its last film are still to come.
        final_uploaded_ = false;
        done_generation_ = ~std::uint64_t(0);
        return;
    }
    settings_changed_ = true;
    max_samples_ = n;
}

void RenderController::set_time_limit(double s) {
    if (s != time_limit_) settings_changed_ = true;
    time_limit_ = s;
}

void RenderController::set_paused(bool p) {
    paused_ = p;
    held_ = false;
    renderer_.set_paused(p || yield_);
}

void RenderController::set_yield(bool y) {
    if (y == yield_) return;
    yield_ = y;
    renderer_.set_paused(paused_ || held_ || yield_);
}

void RenderController::update(const rt::Camera& camera, int film_w, int film_h, bool moving) {
    if (!world() || film_w < 1 || film_h < 1) return;
    rt::RenderProgress p = renderer_.progress();
    // The first coarse pass of the running render measures what a ray costs now.
    if (!measured_ && p.generation == started_generation_ && p.first_coarse_time >= 0) {
        double rays = std::ceil(double(started_w_) / started_block_) * std::ceil(double(started_h_) / started_block_);
        pacer_.measured(rays, p.first_coarse_time);
        measured_ = true;
    }
    bool changed = world_ptr() != started_world_ || !(camera == started_camera_) || film_w != started_w_ ||
                   film_h != started_h_ || settings_changed_;
    bool preview_changed = !same_world(preview_world_, world_ptr()) || !(camera == preview_camera_) || film_w != preview_w_ ||
                           film_h != preview_h_;
    if (changed && preview_changed) last_change_ = std::chrono::steady_clock::now();
    if (!changed) return;
    if (!timing_change_) {
        change_time_ = std::chrono::steady_clock::now();
        timing_change_ = true;
    }
    // The view is moving: this frame's picture is traced here and now (a coarse request
    // to the preview renderer, on the workers of the one pool, whose render jobs are held
    // meanwhile: refining a view that the next frame replaces would only take the CPU
    // the UI needs). A view that stopped for a moment counts as resting.
    if (interactive_ && moving && seconds_since(last_change_) < kRestAfter) {
        if (!held_ && !paused_) {
            renderer_.set_paused(true);
            held_ = true;
        }
        if (preview_changed) {
            // Timed from the frame that saw the change (what came before it is the
            // event loop's: bench/viewer-bench.sh measures that from outside).
            change_time_ = std::chrono::steady_clock::now();
            timing_change_ = true;
            trace_preview(camera, film_w, film_h);
        }
        return;
    }
    start(camera, film_w, film_h);
}

void RenderController::trace_preview(const rt::Camera& camera, int film_w, int film_h) {
    auto t0 = std::chrono::steady_clock::now();
    // The render threads are held while the view moves: their cores trace the preview,
    // and blocks shrink with the cores there are.
    int b = ui_pacer_.preview_block(film_w, film_h, kUiPreviewBudget);
    int pw = 0, ph = 0;
    // (The camera rays go through a buffer around the view's position where the scene is
    // small enough to make one in passing.)
    PreviewResult r = rtview::trace_preview(preview_, world_at(camera.position), camera, film_w, film_h, b,
                                            kPreviewDeadline, preview_rgba_, pw, ph);
    double took = seconds_since(t0);
    ui_pacer_.measured(double(std::max<std::uint64_t>(r.traced, 1)), took);
    preview_tex_.upload(preview_rgba_, pw, ph, {0, 0, pw, ph});
    preview_tex_.set_nearest(true);
    showing_preview_ = true;
    preview_block_ = b;
    preview_w_ = film_w;
    preview_h_ = film_h;
    preview_world_ = world_ptr();
    preview_camera_ = camera;
    if (timing_change_) first_image_after_change(r.stopped ? "preview, stopped at its deadline" : "preview", took, film_w, film_h, b);
}

std::shared_ptr<const rt::World> RenderController::world_at(const rt::Vec3& position) {
    if (!at_ || !same_world(at_world_, world_ptr()) || !(at_position_ == position)) {
        at_ = nullptr;  // (the last one's tables go before the next are made)
        at_ = rt::with_camera_at(world_ptr(), position);
        at_world_ = world_ptr();
        at_position_ = position;
    }
    return at_;
}

void RenderController::first_image_after_change(const char* source, double took, int w, int h, int block) {
    last_latency_ms_ = seconds_since(change_time_) * 1000;
    timing_change_ = false;
    if (verbose)
        std::fprintf(stderr, "raytracer-view: view change -> first image on screen %.1f ms (%s: %.1f ms, %dx%d, block %d)\n",
                     last_latency_ms_, source, took * 1000, w, h, block);
}

void RenderController::start(const rt::Camera& camera, int film_w, int film_h) {
    rt::RenderSettings st;
    st.width = film_w;
    st.height = film_h;
    st.max_samples = max_samples_;
    st.time_limit = time_limit_;
    st.aa_threshold = aa_threshold_;  // a settled pixel stops: the picture converges sooner
    st.hard_time_limit = true;  // a viewer shows what it has: the limit holds even before the first full sample
    st.camera = camera;
    // The usual 8x8 first pass, or coarser when the scene is so expensive that it
    // would not land within the budget; the render refines to full samples by itself.
    st.coarse_block = std::max(8, pacer_.coarse_block(film_w, film_h, kPreviewBudget));
    if (paused_ && interactive_ && started_world_) {
        // Moving the view while paused would show nothing new; resume instead.
        set_paused(false);
    }
    if (held_) {
        held_ = false;
        renderer_.set_paused(paused_ || yield_);
    }
    renderer_.start(world_at(camera.position), st);
    started_world_ = world_ptr();
    started_camera_ = camera;
    started_w_ = film_w;
    started_h_ = film_h;
    started_block_ = st.coarse_block;
    started_generation_ = renderer_.progress().generation;
    measured_ = false;
    settings_changed_ = false;
    final_uploaded_ = false;
}

bool RenderController::has_new_picture() const {
    return started_world_ && (signature(renderer_.progress()) != uploaded_sig_ || view_.pending() || !dirt_.empty());
}

void RenderController::upload() {
    const auto t0 = std::chrono::steady_clock::now();
    struct Timed {
        const std::chrono::steady_clock::time_point t0;
        double& out;
        ~Timed() { out = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); }
    } timed{t0, upload_seconds_};
    rt::RenderProgress before = renderer_.progress();
    uploaded_sig_ = signature(before);
    std::array<int, 4> changed{};
    // With the default display settings and no region these are the renderer's own
    // tile-incremental bytes (see FilmView).
    if (view_.update(renderer_, display_, region_, ImGui::GetTime(), changed)) {
        const int w = view_.width(), h = view_.height();
        if (!film_.valid() || film_.width() != w || film_.height() != h) {
            // A new size: the texture is made with all of it, once.
            film_.upload(view_.rgba(), w, h, {0, 0, w, h});
            dirt_.reset(w, h);
            dirt_.take(std::int64_t(w) * h);
        } else {
            dirt_.add(changed);
        }
    }
    // What changed goes to the texture a bounded number of pixels a frame (a whole
    // large film at once would hold up the frame that sends it).
    for (const TextureDirt::Box& band : dirt_.take(kUploadBudget))
        film_.upload(view_.rgba(), view_.width(), view_.height(), band);
    if (view_.film_changed()) {
        int w = view_.width(), h = view_.height();
        bool has_picture = before.coarse_level > 0 || before.samples > 0;
        if (has_picture && before.generation == started_generation_) picture_due_ = true;
        if (timing_change_ && has_picture && before.generation == started_generation_ && w == started_w_ &&
            h == started_h_)
            first_image_after_change("renderer", before.first_coarse_time, w, h, started_block_);
    }
    // The render's picture replaces the moving view's preview once the texture has all
    // of it (not half of it over the last picture before the move).
    if (picture_due_ && dirt_.empty()) {
        picture_due_ = false;
        if (before.generation == started_generation_) {
            showing_preview_ = false;
            picture_generation_ = before.generation;
            // An adopted world's links (for its first move) once its picture is up.
            sync_.start_links();
            if (verbose && clock && !first_picture_reported_) {
                std::fprintf(stderr, "raytracer-view: first picture on screen at %.3f s\n", clock());
                first_picture_reported_ = true;
            }
        }
    }
    // RenderProgress::elapsed keeps counting after the render is done; the status bar
    // wants the time the render took, so keep the value seen when it finished.
    if (before.done && done_generation_ != before.generation) {
        done_generation_ = before.generation;
        done_elapsed_ = before.elapsed;
    }
    // The snapshot was taken after `before`: if the render was already done then, the
    // texture now holds the final film.
    if (before.done && started_world_ && before.generation == started_generation_ && dirt_.empty())
        final_uploaded_ = true;
}

void RenderController::draw(const Rect& image, float fb_scale) {
    ImDrawList* dl = ImGui::GetBackgroundDrawList();
    ImVec2 p0(float(image.x), float(image.y)), p1(float(image.x + image.w), float(image.y + image.h));
    if (showing_preview_ && preview_tex_.valid()) {
        // Texel k covers film pixels [k b, (k + 1) b): the last one may overhang the film.
        float u = float(preview_w_) / float(preview_tex_.width() * preview_block_);
        float v = float(preview_h_) / float(preview_tex_.height() * preview_block_);
        dl->AddImage(preview_tex_.id(), p0, p1, ImVec2(0, 0), ImVec2(u, v));
        return;
    }
    if (!film_.valid() || !started_world_) return;
    // 1:1 in framebuffer pixels: nearest filtering shows the film's pixels exactly.
    bool exact = std::fabs(image.w * fb_scale - film_.width()) < 0.5 &&
                 std::fabs(image.h * fb_scale - film_.height()) < 0.5;
    film_.set_nearest(exact);
    dl->AddImage(film_.id(), p0, p1);
}

bool RenderController::settled(int film_w, int film_h) const {
    if (!started_world_ || sync_.building()) return false;
    rt::RenderProgress p = renderer_.progress();
    return p.done && final_uploaded_ && p.width == film_w && p.height == film_h;
}

bool RenderController::picture_current(std::uint64_t version) const {
    return world() && !sync_.building() && sync_.version() == version && started_world_ == world_ptr() &&
           picture_generation_ == started_generation_ && renderer_.progress().generation == started_generation_;
}

bool RenderController::busy() const {
    rt::RenderProgress p = renderer_.progress();
    // A render that yields its processors brings no new pixels: no frames for it.
    const bool rendering = !yield_ && (p.running || (!final_uploaded_ && !paused_ && started_world_));
    return rendering || sync_.building() || showing_preview_;
}

}  // namespace rtview
