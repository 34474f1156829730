// Progressive tiled renderer over a thread pool (its own, or one it shares).
//   start()   begins a render (cancelling any previous one) and returns at once;
//   cancel()  stops it and returns when every worker is idle;
//   snapshot  copies the film at any time, never torn between two renders.
// Passes: coarse previews (one ray per 8x8, 4x4, 2x2 block) unless disabled, then
// sample after sample at full resolution. Sample s of pixel (x, y) depends only on
// (x, y, s), and each pixel sums its samples in order, so the film is bit-identical
// whatever the thread count, tile order or pass grouping. With adaptive anti-aliasing
// the passes after the first sample refine only the pixels that a decision between
// passes picks from the film alone (core/adaptive.h): the same film again.
// The one render driver: a final render, the viewer's progressive render, its render
// region (a crop), its previews of a moving view (a coarse step) and its object ids
// (an id pass), and the tiles of a distributed render are all requests to it.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "film.h"
#include "parallel.h"
#include "world.h"

namespace rt {

enum class TileOrder { CentreOut, Scanline };

// What a render puts in the film: colour, or what each pixel's first ray hits.
enum class RenderPass { Colour, Ids };

// Pixels [x0, x1) x [y0, y1) of a film.
struct PixelWindow {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool empty() const { return x1 <= x0 || y1 <= y0; }
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
    int pixels() const { return empty() ? 0 : width() * height(); }
    bool operator==(const PixelWindow& o) const { return x0 == o.x0 && y0 == o.y0 && x1 == o.x1 && y1 == o.y1; }
};

struct RenderSettings {
    int width = 0, height = 0;  // 0: the scene's picture size
    int max_samples = 1;        // samples per pixel to stop at (>= 1)
    double time_limit = 0;      // seconds; 0 = none. Stops at once, even mid-pass, once
                                // every pixel has its first sample
    bool hard_time_limit = false;  // stop at the limit even before that (the previews
                                   // may be all there is: enough for a viewer)
    bool coarse = true;         // coarse preview passes first
    bool mirror = false;        // the original's mirrored picture
    int tile_size = 32;
    int samples_per_pass = 0;   // 0: 1 for the first passes, then growing
    TileOrder order = TileOrder::CentreOut;
    // Renders through this camera instead of world->camera: an interactive view moves
    // without copying the world (whose per-object tables can be large).
    std::optional<Camera> camera;
    // Block size of the first coarse pass (a power of 2, then halved down to 2): a
    // viewer picks a larger one when the scene is expensive, so a preview lands in time.
    int coarse_block = 8;
    // >= 0: adaptive anti-aliasing with this threshold (0..kMaxAaThreshold, see
    // core/render_request.h and core/adaptive.h), max_samples being the most a pixel
    // gets; samples_per_pass is then not used. < 0: every pixel gets max_samples.
    double aa_threshold = -1;
    // Only this window of the film is rendered (pbrt's crop window, Cycles' border
    // render): its pixels are the whole film's, sample for sample; the rest of the film
    // keeps what it held (nothing, in a new renderer). Empty: the whole film. A crop has no coarse passes and renders
    // every pixel to max_samples (aa_threshold is not used).
    PixelWindow crop;
    // > 1: a coarse film of one pixel per step x step block of the width x height
    // picture, ceil(width / step) x ceil(height / step), each the block's corner pixel's
    // sample 0 (the ray of a coarse pass of that block size; any step, not only powers
    // of 2). One sample, no coarse passes; crop is then in the coarse film's pixels.
    int step = 1;
    // Ids: the film holds what each pixel's sample-0 ray hits first (pick_id) instead of
    // a colour. One sample, no coarse passes, no time limit.
    RenderPass pass = RenderPass::Colour;
    // A distributed render's tile (app/mpi): the crop goes on from what load_window()
    // put there instead of starting afresh. first_sample > 0: samples [first_sample,
    // max_samples) of each pixel, in one pass; refine_marked: one round of adaptive
    // refinement, each marked pixel from its n samples to refine_count(n, max_samples).
    int first_sample = 0;
    bool refine_marked = false;
    // A one-shot render for an 8-bit file (take_rgb8): when a pixel's one sample is all
    // there is (max_samples 1, no adaptive anti-aliasing, coarse passes, crop, step, id
    // pass or hard time limit), each tile goes straight into bytes while it is in cache
    // and the film's floats are never written: snapshots of that render show nothing.
    // Otherwise ignored.
    bool bytes_only = false;
};

// The sample passes of samples [from, to), each {s0, s1}: samples_per_pass at a time,
// or 1, 1, 2, 4, 8, 16, 16, ...; under a time limit the first pass, which always
// completes, is one sample. A distributed render hands out the same passes.
std::vector<std::array<int, 2>> sample_passes(const RenderSettings& settings, int from, int to);

// The tiles of a render: the width x height film's grid of side x side tiles, cut to
// `window`, in `order` (centre-out: nearest the film's centre first, ties in scanline
// order). A distributed render hands out the same tiles.
std::vector<PixelWindow> tile_grid(int width, int height, const PixelWindow& window, int side, TileOrder order);

struct RenderProgress {
    std::uint64_t generation = 0;  // increases on every start()
    int coarse_level = 0;          // block size of the last complete coarse pass (8, 4, 2), 0 = none
    int samples = 0;               // samples per pixel completed everywhere
    int passes = 0;                // passes completed (coarse included)
    double pass_fraction = 0;      // fraction of the current pass's tiles done
    std::uint64_t rays = 0;
    double elapsed = 0;            // seconds since start(), or start to finish once done
    double first_coarse_time = -1; // seconds from start() to the first complete coarse pass
    bool running = false;
    bool done = false;             // reached max_samples or the time limit (adaptive: or
                                   // every pixel settled)
    bool paused = false;
    int width = 0, height = 0;
    // Adaptive anti-aliasing: the pixels not yet settled (all of them until the first
    // decision after the first sample; 0 once every one is); -1 for a uniform render.
    std::int64_t refining = -1;
    int refinements = 0;             // adaptive passes completed after the first sample
    std::uint64_t film_samples = 0;  // samples in the film, all pixels together
    // Why the render stopped unfinished, or empty: a worker ran out of memory (a
    // bad_alloc on a render thread ends the render, not the program). done is set too.
    std::string error;
};

// How far a render with this max_samples has got, 0..1, for progress bars: samples per
// pixel against max_samples; adaptive (p.refining >= 0), the first sample as the first
// half, then each refinement as half of what is left (their number is not known).
double progress_fraction(const RenderProgress& p, int max_samples);

// Sample position for sample s of pixel (x, y): s = 0 is the original's exact pixel
// corner; later samples are a per-pixel rotated low-discrepancy set around it.
void sample_offset(int x, int y, int s, double& dx, double& dy);

// Adds samples [s0, s1) of pixel (x, y) to acc, in sample order: the one definition of
// a pixel's value (the renderer's sample passes; distributed rendering and the viewer's
// region are requests to the renderer). The resolved colour is acc / count (see
// Film::pixel).
void accumulate_pixel(const World& world, const CameraBasis& camera, int x, int y, int s0, int s1, float acc[3],
                      RayStats& stats);

// What an id pass holds for a pick: 0 nothing, else (index + 1) * 4 + kind (1 object,
// 2 plane, 3 lamp glow).
std::uint32_t pick_id(const PickResult& r);

struct RenderTask;

class Renderer {
public:
    // Renders on `pool`'s workers, shared with whatever else runs there (the process
    // pool in the programs; a pool of a chosen size in tests that compare thread
    // counts). The pool must have a worker (a render runs in the background) and
    // outlive the renderer; std::invalid_argument if it has none.
    explicit Renderer(ThreadPool& pool);
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    void start(std::shared_ptr<const World> world, const RenderSettings& settings);
    // Raises the running (or finished) render's max_samples to `max_samples`: it goes on
    // from the samples it has, instead of starting again. The film is the one a render
    // started with that many would give for a uniform render; an adaptive one decides
    // every pixel again at its next decision, with the new limit. False (nothing done)
    // if there is no render, it ended with an error, has a time limit, or already has
    // that many.
    bool raise_samples(int max_samples);
    void cancel();
    void set_paused(bool paused);
    // While paused: let the workers take `tiles` more tiles. A render one tile at a
    // time, whatever the thread count or the machine's load (tests use it).
    void step(int tiles = 1);
    // Block until the render is done or cancelled.
    void wait();
    // Block until done or the timeout passes; true if done.
    bool wait_for(double seconds);

    RenderProgress progress() const;
    // Copy of the current film (resolved colours); generation tells which render.
    Image snapshot(std::uint64_t* generation = nullptr) const;
    // The film as 8-bit RGB with the original's rounding, as image files hold it
    // (the same bytes as to_rgb8(snapshot()), without the float copy).
    void snapshot_rgb8(ZeroedArray<std::uint8_t>& out, int& width, int& height) const;
    // The same bytes, made in place of the film's sums (no fresh memory for a picture
    // written once) and handed over: the film is left empty (0 x 0), for the end of a
    // one-shot render (after bytes_only, the bytes its tiles went into). While a render runs,
    // a copy as snapshot_rgb8 makes.
    void take_rgb8(ZeroedArray<std::uint8_t>& out, int& width, int& height);
    // RGBA8 for display, kept up to date in `out` between calls: returns false if
    // nothing changed since `version`; else brings `out` (as the last call with this
    // `version` left it) up to the film's state, converting only the tiles finished in
    // between when it can, and sets `version`. `changed`, if given, receives the
    // rectangle {x0, y0, x1, y1} that may differ from before.
    bool snapshot_rgba8(std::vector<std::uint8_t>& out, int& width, int& height, std::uint64_t& version,
                        std::array<int, 4>* changed = nullptr) const;
    // The film's per-pixel sample counts, top row first; one pixel's (0 outside the film).
    void sample_counts(std::vector<std::uint32_t>& out, int& width, int& height) const;
    int sample_count(int x, int y) const;
    // A window of the film (cut to it): its pixels resolved as snapshot() has them, and
    // their sample counts, row by row; returns the film's version (as snapshot_rgba8
    // counts them: it changes with every tile committed).
    std::uint64_t snapshot_window(const PixelWindow& window, Image& out, std::vector<std::uint32_t>& counts) const;
    // The film's version: snapshot_window() would give something new when it changed.
    std::uint64_t film_version() const;
    // What a distributed render's tile continues (RenderSettings::first_sample,
    // refine_marked): the window of a width x height film (made that size) gets, per
    // pixel row by row, its sums (3 floats) and sample count, and for a refinement its
    // sum of squares and whether it is marked (nonzero). Call before start().
    void load_window(int width, int height, const PixelWindow& window, const float* sums, const std::uint32_t* counts,
                     const float* squares = nullptr, const std::uint8_t* marked = nullptr);
    // The window's sums (3 floats a pixel, row by row) and, if asked for, sums of squares.
    void read_window(const PixelWindow& window, float* sums, float* squares = nullptr) const;
    // An id pass's film (RenderPass::Ids): per pixel, top row first, its pick_id(), 0
    // where nothing was traced.
    void ids(std::vector<std::uint32_t>& out, int& width, int& height) const;
    // One pixel of the film (its resolved colour, as snapshot() has it) while the film
    // is width x height: no copy of the whole film. False outside it or at another size.
    bool pixel(int x, int y, int width, int height, Colour& c) const;
    int threads() const { return max_runners_; }
    // The pool it renders on (for other work alongside, such as a preview's loops).
    ThreadPool& pool() const { return *pool_; }

    // Called by a worker before each task it takes, outside the lock (null: nothing).
    // Tests throw from it to see a failing worker end the render with a message.
    std::function<void()> task_hook;

private:
    struct Job;
    // Posts runners while there are tasks to take and fewer runners than threads().
    void kick_locked();
    // One pool task: takes one render task, runs and commits it, and posts the next.
    void run_one();
    void finish_task_locked(RenderTask& task, bool complete, std::string& error, const std::vector<float>& buf,
                            std::uint64_t rays);
    bool next_task(RenderTask& task);
    bool run_task(const RenderTask& task, std::vector<float>& buf, RayStats& stats);
    void commit(const RenderTask& task, const std::vector<float>& buf);
    void begin_pass_locked(Job& job);
    bool next_pass_locked(Job& job);
    void raise_locked(Job& job);
    void finish_locked(Job& job);
    bool run_samples(const RenderTask& task, std::vector<float>& buf, RayStats& stats);
    bool run_refine(const RenderTask& task, std::vector<float>& buf, RayStats& stats);
    void commit_film(const RenderTask& task, const std::vector<float>& buf);
    void row_rgb8(int y, std::uint8_t* out) const;
    int rgb8_parts() const;

    ThreadPool* pool_ = nullptr;
    int max_runners_ = 1;
    mutable std::mutex mutex_;
    std::condition_variable idle_cv_, done_cv_;
    int runners_ = 0;  // run_one tasks posted and not yet ended (under mutex_)
    std::atomic<std::uint64_t> cancel_gen_{0};  // workers stop a task when it differs from theirs

    std::shared_ptr<Job> job_;
    Film film_;
    std::uint64_t film_version_ = 0;
    // What changed on screen since which version, for snapshot_rgba8: the tiles of
    // sample passes in commit order; before full_version_ (a new render, a new coarse
    // level) or before the oldest entry kept, everything.
    std::deque<std::pair<std::uint64_t, std::array<int, 4>>> changes_;
    std::uint64_t full_version_ = 0;
    ZeroedArray<std::uint8_t> loaded_marks_;  // load_window()'s, for the next start()
    ZeroedArray<std::uint8_t> film_bytes_;    // a bytes_only render's picture, 3 bytes a pixel
    int busy_ = 0;  // runners inside a task
    bool paused_ = false;
    int steps_ = 0;  // tiles that may still be taken while paused
};

}  // namespace rt
