// Scheduling: a render is a list of passes, a pass a list of tiles. Workers take
// tiles of the current pass in order (centre first); the pass after it starts only
// when every tile of this one is committed, so each pixel sums its samples in order.
// Stopping: a task's traces poll its job's stop flag and, in the passes after the
// first sample, the time limit, so neither waits for a tile (or a pixel) to finish.
#include "renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <new>
#include <stdexcept>

#include "adaptive.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace rt {

namespace {
// Tiles remembered for snapshot_rgba8's partial updates: a full pass at 4K in 32x32 tiles.
constexpr std::size_t kMaxChanges = 8192;

// to_byte(float(c)) of each of n sums of one sample (the colour is the sum itself),
// four at a time: the same double product, clamps and truncation as to_byte.
void sums_to_bytes(const float* sum, std::size_t n, std::uint8_t* out) {
    std::size_t i = 0;
#if defined(__SSE2__)
    const __m128d k255 = _mm_set1_pd(255.0), zero = _mm_setzero_pd();
    // max(v, 0) gives 0 for NaN as to_byte's v > 0 ? v : 0 does (the second operand).
    auto clamp = [&](__m128d v) { return _mm_min_pd(_mm_max_pd(_mm_mul_pd(v, k255), zero), k255); };
    for (; i + 4 <= n; i += 4) {
        const __m128 f = _mm_loadu_ps(sum + i);
        const __m128i lo = _mm_cvttpd_epi32(clamp(_mm_cvtps_pd(f)));
        const __m128i hi = _mm_cvttpd_epi32(clamp(_mm_cvtps_pd(_mm_movehl_ps(f, f))));
        __m128i v = _mm_unpacklo_epi64(lo, hi);
        v = _mm_packus_epi16(_mm_packs_epi32(v, v), v);
        const std::uint32_t bytes = std::uint32_t(_mm_cvtsi128_si32(v));
        std::memcpy(out + i, &bytes, 4);
    }
#endif
    for (; i < n; ++i) out[i] = to_byte(sum[i]);
}
}  // namespace

using Clock = std::chrono::steady_clock;

enum class PassKind : unsigned char { Coarse, Samples, Decide, Refine, Ids };

// Adaptive anti-aliasing's state, shared by the job and its tasks: a decision task
// writes its own rows of `active` and its own band of `marked` (so a task never waits
// for another), a refine task reads them.
struct AdaptiveJob {
    double threshold = 0;
    int max_samples = 1;
    int tile = 32, cols = 0;  // the sample passes' tiles: side, and how many across
    // Per pixel: marked by the last decision, and by the one before (what the pass in
    // between refined, for the next decision).
    ZeroedArray<std::uint8_t> active, changed;
    std::vector<int> marked;  // per tile of the grid, row by row: pixels the last decision marked
    bool first = true;        // the next decision is the first: it decides every pixel
    std::int64_t refining = 0;
    int refinements = 0;      // refine passes completed
};

struct RenderTask {
    std::uint64_t generation = 0;
    std::shared_ptr<const World> world;
    std::shared_ptr<const std::atomic<bool>> stop;  // the job's: set when it is cancelled or done
    Clock::time_point deadline = Clock::time_point::max();
    CameraBasis camera;
    PassKind kind = PassKind::Samples;
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    int block = 0;               // coarse pass: block size; 0 for a sample pass
    int s0 = 0, s1 = 0;          // sample pass: samples [s0, s1)
    int reuse = 0;               // block size (a power of 2) of the last coarse pass: its
                                 // corner pixels already hold sample 0 in the preview layer
    int step = 1;                // film pixel (x, y) is picture pixel (x step, y step)
    std::shared_ptr<AdaptiveJob> aa;  // decision and refine passes
};

struct Pass {
    PassKind kind = PassKind::Samples;
    int block = 0;
    int s0 = 0, s1 = 0;
};

struct Renderer::Job {
    std::uint64_t generation = 0;
    std::shared_ptr<const World> world;
    std::shared_ptr<std::atomic<bool>> stop = std::make_shared<std::atomic<bool>>(false);
    RenderSettings settings;
    CameraBasis camera;
    int width = 0, height = 0;  // the film's (the picture's / step)
    PixelWindow crop;           // of the film: what is rendered (all of it without a crop)
    Clock::time_point start;
    Clock::time_point deadline = Clock::time_point::max();  // start + time limit
    std::vector<Pass> passes;       // the fixed ones; adaptive passes are appended as needed
    std::size_t pass = 0;           // current pass
    std::vector<std::array<int, 4>> tiles;
    std::size_t next_tile = 0, tiles_done = 0;
    int samples_done = 0;
    int passes_done = 0;
    int coarse_level = 0;
    bool preview_valid = false;  // something of this generation can be shown
    double first_coarse_time = -1;
    double done_time = -1;  // seconds from start to the end of the last pass
    bool done = false;
    bool paused = false;
    std::uint64_t rays = 0;
    std::uint64_t film_samples = 0;
    std::shared_ptr<AdaptiveJob> aa;  // null: a uniform render
    std::string error;                // RenderProgress::error
    int raise_to = 0;                 // raise_samples() of an adaptive render, at the next pass
    bool bytes = false;               // settings.bytes_only in effect: tiles go to film_bytes_
};

namespace {
double radical(unsigned i, unsigned base) {
    double f = 1, r = 0;
    while (i > 0) {
        f /= base;
        r += f * (i % base);
        i /= base;
    }
    return r;
}

// radical(s, 2) and radical(s, 3) of the first samples, worked out once by the same
// operations (so the same values): their divisions would cost more than the rest of
// sample_offset together.
struct Radicals {
    static constexpr unsigned kCount = 256;
    double base2[kCount], base3[kCount];
    Radicals() {
        for (unsigned s = 0; s < kCount; ++s) base2[s] = radical(s, 2), base3[s] = radical(s, 3);
    }
};
}  // namespace

void sample_offset(int x, int y, int s, double& dx, double& dy) {
    if (s == 0) {
        dx = dy = 0;
        return;
    }
    // Halton (2, 3) points, rotated per pixel by a hash so that neighbouring pixels do
    // not share a pattern; centred on the original's sample point.
    static const Radicals table;
    const bool held = unsigned(s) < Radicals::kCount;
    const double r2 = held ? table.base2[s] : radical(unsigned(s), 2);
    const double r3 = held ? table.base3[s] : radical(unsigned(s), 3);
    std::uint32_t h = std::uint32_t(x) * 0x8da6b343u ^ std::uint32_t(y) * 0xd8163841u;
    h ^= h >> 15;
    h *= 0x2c1b3c6du;
    h ^= h >> 12;
    double rx = (h & 0xffff) / 65536.0, ry = (h >> 16) / 65536.0;
    double u = r2 + rx, v = r3 + ry;
    // u and v lie in [0, 2): their floor is 0 or 1, and subtracting it is exact, so this
    // is u - floor(u) without floor's library call (SSE2 has no rounding instruction).
    dx = (u >= 1 ? u - 1 : u) - 0.5;
    dy = (v >= 1 ? v - 1 : v) - 0.5;
}

void accumulate_pixel(const World& world, const CameraBasis& camera, int x, int y, int s0, int s1, float acc[3],
                      RayStats& stats) {
    const bool sampled = world.sampled(camera);
    for (int s = s0; s < s1; ++s) {
        double dx, dy;
        sample_offset(x, y, s, dx, dy);
        Colour c;
        if (sampled) {
            const Vec3 d = normalize(camera.direction(x + dx, y + dy));
            const PixelSample key{x, y, s};
            world.trace_samples(camera, &d, &key, 1, stats, &c);
        } else {
            c = world.trace_camera(camera, x + dx, y + dy, stats);
        }
        acc[0] += float(c.x), acc[1] += float(c.y), acc[2] += float(c.z);
    }
}

std::uint32_t pick_id(const PickResult& r) {
    if (r.object >= 0) return std::uint32_t(r.object + 1) * 4 + 1;
    if (r.plane >= 0) return std::uint32_t(r.plane + 1) * 4 + 2;
    if (r.light >= 0) return std::uint32_t(r.light + 1) * 4 + 3;
    return 0;
}

Renderer::Renderer(ThreadPool& pool) : pool_(&pool), max_runners_(pool.workers()) {
    if (max_runners_ < 1) throw std::invalid_argument("a renderer needs a pool with a worker");
}

Renderer::~Renderer() {
    std::unique_lock<std::mutex> lock(mutex_);
    ++cancel_gen_;
    if (job_) job_->stop->store(true);
    job_.reset();
    // Runners still waiting in the pool hold `this`: each ends at once, finding no job.
    idle_cv_.wait(lock, [&] { return runners_ == 0; });
}

void Renderer::begin_pass_locked(Job& job) {
    job.tiles.clear();
    job.next_tile = job.tiles_done = 0;
    const Pass& p = job.passes[job.pass];
    int ts = std::max(8, job.settings.tile_size / 8 * 8);  // coarse blocks never straddle tiles
    if (p.kind == PassKind::Decide) {
        // Bands of whole rows, one per row of tiles: each counts its tiles' marked pixels.
        for (int y = 0; y < job.height; y += ts) job.tiles.push_back({0, y, job.width, std::min(y + ts, job.height)});
        return;
    }
    // Coarse passes trace one ray per block: their tiles grow with the block so that a
    // task holds as many rays as a sample pass's, in rows as long (a short row's rays
    // cost more each, and a small task more to take from the queue than it holds).
    if (p.kind == PassKind::Coarse) ts *= p.block;
    for (const PixelWindow& t : tile_grid(job.width, job.height, job.crop, ts, job.settings.order)) {
        // A refine pass leaves out the tiles with nothing to refine.
        if (p.kind == PassKind::Refine && job.aa->marked[std::size_t(t.y0 / ts * job.aa->cols + t.x0 / ts)] == 0)
            continue;
        job.tiles.push_back({t.x0, t.y0, t.x1, t.y1});
    }
}

std::vector<PixelWindow> tile_grid(int width, int height, const PixelWindow& window, int side, TileOrder order) {
    std::vector<PixelWindow> tiles;
    const PixelWindow c{std::max(window.x0, 0), std::max(window.y0, 0), std::min(window.x1, width),
                        std::min(window.y1, height)};
    side = std::max(1, side);
    for (int y = c.y0 / side * side; y < c.y1; y += side)
        for (int x = c.x0 / side * side; x < c.x1; x += side)
            tiles.push_back({std::max(x, c.x0), std::max(y, c.y0), std::min(x + side, c.x1), std::min(y + side, c.y1)});
    if (order == TileOrder::CentreOut) {
        const double cx = width / 2.0, cy = height / 2.0;
        std::stable_sort(tiles.begin(), tiles.end(), [&](const PixelWindow& a, const PixelWindow& b) {
            double ax = (a.x0 + a.x1) / 2.0 - cx, ay = (a.y0 + a.y1) / 2.0 - cy;
            double bx = (b.x0 + b.x1) / 2.0 - cx, by = (b.y0 + b.y1) / 2.0 - cy;
            return ax * ax + ay * ay < bx * bx + by * by;
        });
    }
    return tiles;
}

std::vector<std::array<int, 2>> sample_passes(const RenderSettings& settings, int from, int to) {
    std::vector<std::array<int, 2>> passes;
    for (int s = from; s < to;) {
        int n = settings.samples_per_pass > 0 ? settings.samples_per_pass : std::clamp(s, 1, 16);
        if (s == 0 && settings.time_limit > 0) n = 1;
        n = std::min(n, to - s);
        passes.push_back({s, s + n});
        s += n;
    }
    return passes;
}

namespace {
void add_sample_passes(std::vector<Pass>& passes, const RenderSettings& settings, int from, int to) {
    for (const auto& p : sample_passes(settings, from, to)) passes.push_back({PassKind::Samples, 0, p[0], p[1]});
}

// The passes of a render, as start() lists them: the coarse ones, then the sample
// passes (adaptive: only the first sample; the decisions and refinements follow it).
std::vector<Pass> plan_passes(const RenderSettings& settings, int width, int height, int max_samples) {
    std::vector<Pass> passes;
    if (settings.pass == RenderPass::Ids) return {{PassKind::Ids, 0, 0, 1}};
    if (settings.refine_marked) return {{PassKind::Refine, 0, 0, 0}};
    if (settings.first_sample > 0) return {{PassKind::Samples, 0, settings.first_sample, max_samples}};
    int first_block = 2;  // the largest power of 2 <= coarse_block (blocks are masks)
    while (first_block < 256 && first_block * 2 <= settings.coarse_block) first_block *= 2;
    if (settings.coarse)
        for (int b = first_block; b >= 2; b /= 2)
            if (width > b || height > b) passes.push_back({PassKind::Coarse, b, 0, 0});
    if (settings.aa_threshold >= 0) {
        passes.push_back({PassKind::Samples, 0, 0, 1});
        return passes;
    }
    add_sample_passes(passes, settings, 0, max_samples);
    return passes;
}
}  // namespace

namespace {
// RenderSettings::bytes_only in effect: every pixel's one sample is its picture.
bool straight_to_bytes(const RenderSettings& st, bool resume) {
    return st.bytes_only && st.max_samples == 1 && st.aa_threshold < 0 && !st.coarse && !resume && st.step == 1 &&
           st.pass == RenderPass::Colour && !st.hard_time_limit && st.crop.empty();
}
}  // namespace

void Renderer::start(std::shared_ptr<const World> world, const RenderSettings& settings) {
    cancel();
    std::lock_guard<std::mutex> lock(mutex_);
    auto job = std::make_shared<Job>();
    job->generation = cancel_gen_.load();
    job->world = world;
    job->settings = settings;
    RenderSettings& st = job->settings;
    st.max_samples = std::max(1, settings.max_samples);
    st.step = std::max(1, settings.step);
    const int picture_w = settings.width > 0 ? settings.width : world->width;
    const int picture_h = settings.height > 0 ? settings.height : world->height;
    job->width = (picture_w + st.step - 1) / st.step;
    job->height = (picture_h + st.step - 1) / st.step;
    job->camera = CameraBasis::make(settings.camera ? *settings.camera : world->camera, picture_w, picture_h,
                                    settings.mirror);
    // A coarse film or an id pass is one sample of each pixel; a crop renders its
    // pixels uniformly, without previews (their blocks belong to the whole film).
    if (st.step > 1 || st.pass == RenderPass::Ids) st.max_samples = 1, st.aa_threshold = -1, st.coarse = false;
    if (st.pass == RenderPass::Ids) st.time_limit = 0;
    job->crop = {0, 0, job->width, job->height};
    if (!settings.crop.empty()) {
        const PixelWindow& c = settings.crop;
        job->crop = {std::clamp(c.x0, 0, job->width), std::clamp(c.y0, 0, job->height),
                     std::clamp(c.x1, 0, job->width), std::clamp(c.y1, 0, job->height)};
        st.coarse = false;
        st.aa_threshold = -1;
    }
    // A distributed render's tile goes on from what load_window() put in the film.
    const bool resume = !settings.crop.empty() && (st.first_sample > 0 || st.refine_marked);
    if (!resume) st.first_sample = 0, st.refine_marked = false;
    if (resume) st.time_limit = 0, st.max_samples = std::max(st.max_samples, st.first_sample + 1);
    job->start = Clock::now();
    if (st.time_limit > 0)
        job->deadline = job->start + std::chrono::duration_cast<Clock::duration>(
                                         std::chrono::duration<double>(std::min(st.time_limit, 1e9)));
    job->passes = plan_passes(st, job->width, job->height, st.max_samples);
    job->paused = paused_;
    steps_ = 0;
    const std::size_t pixels = std::size_t(job->width) * job->height;
    if (film_.width != job->width || film_.height != job->height) {
        film_.reset(job->width, job->height, st.coarse);
    } else if (!resume) {
        // (A crop clears its own pixels: a distributed render's tiles come one by one.)
        for (int y = job->crop.y0; y < job->crop.y1; ++y)
            std::fill_n(film_.count.data() + std::size_t(y) * std::size_t(job->width) + std::size_t(job->crop.x0),
                        job->crop.width(), 0u);
        if (st.coarse && film_.preview.empty()) film_.preview.reset(Film::preview_size(job->width, job->height));
    }
    film_bytes_.reset((job->bytes = straight_to_bytes(st, resume)) ? 3 * pixels : 0);
    if (st.pass == RenderPass::Ids && film_.ids.size() != pixels) film_.ids.reset(pixels);
    if (st.pass == RenderPass::Ids) std::fill(film_.ids.begin(), film_.ids.end(), 0u);
    if (st.aa_threshold >= 0 || st.refine_marked) {
        auto aa = std::make_shared<AdaptiveJob>();
        aa->threshold = st.aa_threshold;
        aa->max_samples = st.max_samples;
        aa->tile = std::max(8, st.tile_size / 8 * 8);
        aa->cols = (job->width + aa->tile - 1) / aa->tile;
        aa->active.reset(pixels);
        aa->changed.reset(pixels);
        aa->marked.assign(std::size_t(aa->cols) * std::size_t((job->height + aa->tile - 1) / aa->tile), 0);
        aa->refining = std::int64_t(pixels);
        if (film_.squares.size() != pixels) film_.squares.reset(pixels);
        if (st.refine_marked) {
            // The marks load_window() made, every tile of the crop taken.
            if (loaded_marks_.size() == pixels) aa->active.swap(loaded_marks_);
            std::fill(aa->marked.begin(), aa->marked.end(), 1);
            aa->first = false;
        }
        job->aa = std::move(aa);
    }
    film_.preview_level = 0;
    ++film_version_;
    full_version_ = film_version_;
    changes_.clear();
    begin_pass_locked(*job);
    job_ = job;
    if (job->tiles.empty()) finish_locked(*job);  // an empty crop (or film): nothing to do
    kick_locked();
}

bool Renderer::raise_samples(int max_samples) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!job_ || !job_->error.empty() || job_->settings.time_limit > 0 || job_->settings.step > 1 ||
        job_->settings.first_sample > 0 || job_->settings.refine_marked ||
        job_->settings.pass == RenderPass::Ids ||
        max_samples <= std::max(job_->settings.max_samples, job_->raise_to))
        return false;
    Job& job = *job_;
    const std::size_t planned = job.passes.size();
    if (!job.aa) {
        // Uniform: more sample passes after the planned ones (tasks read the list only
        // under the lock, so it may grow while they run).
        add_sample_passes(job.passes, job.settings, job.settings.max_samples, max_samples);
        job.settings.max_samples = max_samples;
    } else {
        // Adaptive: tasks of the running pass read the limit; it changes between passes.
        job.raise_to = max_samples;
        if (!job.done) return true;
        raise_locked(job);
        job.passes.push_back({PassKind::Decide, 0, 0, 0});
        job.passes.push_back({PassKind::Refine, 0, 0, 0});
    }
    if (job.done) {
        // Finished: on from the pass after the last one done, with a stop flag of its own
        // (the old one stays set for whatever still holds it).
        job.pass = job.aa ? job.passes.size() - 2 : planned;
        job.done = false;
        // Its time goes on from where it stopped (the rest in between is not rendering).
        job.start = Clock::now() - std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(job.done_time));
        job.done_time = -1;
        job.stop = std::make_shared<std::atomic<bool>>(false);
        begin_pass_locked(job);
        kick_locked();
    }
    return true;
}

// Called with mutex_ held, between passes of an adaptive render: its new sample limit,
// and a decision of every pixel next (those stopped at the old limit may go on).
void Renderer::raise_locked(Job& job) {
    job.settings.max_samples = job.raise_to;
    job.aa->max_samples = job.raise_to;
    job.aa->first = true;
    job.raise_to = 0;
}

void Renderer::cancel() {
    std::unique_lock<std::mutex> lock(mutex_);
    ++cancel_gen_;
    if (job_) job_->stop->store(true);
    job_.reset();
    done_cv_.notify_all();  // wait() returns: there is no render any more
    idle_cv_.wait(lock, [&] { return busy_ == 0; });
}

void Renderer::set_paused(bool paused) {
    std::lock_guard<std::mutex> lock(mutex_);
    paused_ = paused;
    steps_ = 0;
    if (job_) job_->paused = paused;
    kick_locked();
}

void Renderer::step(int tiles) {
    std::lock_guard<std::mutex> lock(mutex_);
    steps_ += std::max(0, tiles);
    kick_locked();
}

void Renderer::wait() {
    std::unique_lock<std::mutex> lock(mutex_);
    done_cv_.wait(lock, [&] { return !job_ || job_->done; });
}

bool Renderer::wait_for(double seconds) {
    std::unique_lock<std::mutex> lock(mutex_);
    return done_cv_.wait_for(lock, std::chrono::duration<double>(seconds), [&] { return !job_ || job_->done; });
}

// Called with mutex_ held.
bool Renderer::next_task(RenderTask& task) {
    if (!job_ || job_->done) return false;
    Job& job = *job_;
    if (job.next_tile >= job.tiles.size()) return false;  // others are finishing the pass
    if (job.paused) {
        if (steps_ <= 0) return false;
        --steps_;
    }
    const auto& t = job.tiles[job.next_tile++];
    const Pass& p = job.passes[job.pass];
    task.generation = job.generation;
    task.world = job.world;
    task.stop = job.stop;
    // Every pixel gets its first sample whatever the time; what comes after it stops at
    // the limit, even in the middle of a pass. (Coarse passes are too short to matter.)
    const bool first = p.kind == PassKind::Coarse || (p.kind == PassKind::Samples && p.s0 == 0);
    task.deadline = job.settings.hard_time_limit || !first ? job.deadline : Clock::time_point::max();
    task.camera = job.camera;
    task.kind = p.kind;
    task.x0 = t[0], task.y0 = t[1], task.x1 = t[2], task.y1 = t[3];
    task.block = p.block;
    task.s0 = p.s0, task.s1 = p.s1;
    task.reuse = job.coarse_level;
    task.step = job.settings.step;
    task.aa = job.aa;
    return true;
}

void Renderer::kick_locked() {
    if (!job_ || job_->done) return;
    const Job& job = *job_;
    std::size_t left = job.tiles.size() - job.next_tile;
    if (job.paused) left = std::min(left, std::size_t(std::max(0, steps_)));
    // A runner not yet inside a task will take one of those left.
    while (runners_ < max_runners_ && std::size_t(runners_ - busy_) < left) {
        ++runners_;
        pool_->post([this] { run_one(); });
    }
}

void Renderer::run_one() {
    thread_local std::vector<float> buf;
    std::unique_lock<std::mutex> lock(mutex_);
    RenderTask task;
    if (!next_task(task)) {
        if (--runners_ == 0) idle_cv_.notify_all();
        return;
    }
    ++busy_;
    lock.unlock();
    RayStats stats;
    stats.stop.flag = task.stop.get();
    stats.stop.deadline = task.deadline;
    std::string error;
    bool complete = false;
    try {
        if (task_hook) task_hook();
        complete = run_task(task, buf, stats);
    } catch (const std::bad_alloc&) {
        error = "out of memory while rendering";
    } catch (const std::exception& e) {
        error = std::string("a render thread failed: ") + e.what();
    }
    lock.lock();
    finish_task_locked(task, complete, error, buf, stats.rays);
    --busy_;
    --runners_;
    // The next task goes behind whatever else waits for the pool's threads.
    kick_locked();
    if (busy_ == 0 || runners_ == 0) idle_cv_.notify_all();
}

// Called with mutex_ held, after a task ran: its pixels into the film if it is
// complete and still wanted; the render's end if it failed or ran out of time.
void Renderer::finish_task_locked(RenderTask& task, bool complete, std::string& error, const std::vector<float>& buf,
                                  std::uint64_t rays) {
    bool current = job_ && job_->generation == task.generation && !job_->done;
    if (current) job_->rays += rays;
    if (!error.empty()) {
        // The render ends here, with the message; the others stop at once.
        if (current) {
            job_->error = std::move(error);
            finish_locked(*job_);
        }
    } else if (complete && current) {
        commit(task, buf);
    } else if (current && Clock::now() >= task.deadline) {
        // Out of time in the middle of a pass: the tiles committed keep their extra
        // samples, the others the samples of the passes before.
        finish_locked(*job_);
    }
    task.world.reset();
}

namespace {
// Asks for the cache lines of [begin, end) ahead of their use (to write them, if kWrite).
template <bool kWrite, class T>
void prefetch(const T* begin, const T* end) {
    const auto last = reinterpret_cast<std::uintptr_t>(end);
    for (auto a = reinterpret_cast<std::uintptr_t>(begin) & ~std::uintptr_t(63); a < last; a += 64)
        __builtin_prefetch(reinterpret_cast<const void*>(a), kWrite ? 1 : 0);
}

// The number of pixels first_samples() gives for a row of the task at this step.
std::size_t row_count(const RenderTask& task, int step) {
    return std::size_t((task.x1 - task.x0 + step - 1) / step);
}

// Sample 0 of the pixels (x0 + k step, y) of the task's row, k < row_count(), as
// floats into out (3 a pixel: float() of each channel, as the film and the preview
// hold them): traced in one call, except where the last coarse pass traced the same
// ray (its blocks' corners), whose colour the preview holds (the same ray, so the
// same colour, already a float). kSums: as a sum that starts at 0 (0.0f + each, so
// -0 becomes 0), which is what a one-sample pass puts in the film.
template <bool kSums>
void first_samples(const RenderTask& task, const Film& film, int y, int step, RayStats& stats, float* out) {
    // (Grown only: a row's rays are the first of them. Rows of corners trace half as
    // many, and a resize back up would zero what is written next.)
    thread_local std::vector<Vec3> dirs;
    thread_local std::vector<Colour> colours;
    thread_local std::vector<PixelSample> keys;
    const std::size_t n = row_count(task, step);
    if (dirs.size() < n) dirs.resize(n), colours.resize(n);
    const World& world = *task.world;
    // Sample 0 of each pixel traced (its key read only where the world samples).
    const bool sampled = world.sampled(task.camera);
    if (sampled && keys.size() < n) keys.resize(n);
    auto trace = [&](std::size_t m) {
        world.trace_samples(task.camera, dirs.data(), keys.data(), m, stats, colours.data());
    };
    const int mask = task.reuse - 1;
    constexpr float zero = kSums ? 0.0f : -0.0f;  // (-0.0f + v is v, bit for bit)
    auto put = [](const Colour& c, float* o) {
        o[0] = zero + float(c.x), o[1] = zero + float(c.y), o[2] = zero + float(c.z);
    };
    // The row's camera rays are made before any is traced: independent square roots and
    // divisions overlap, where one at a time each would wait for the last.
    if (task.reuse == 0 || (y & mask) != 0) {
        // (A coarse film's pixel is the picture's pixel at `task.step` times its place.)
        const int scale = task.step;
        task.camera.unit_directions(task.x0 * scale, step * scale, int(n), y * scale, dirs.data());
        if (sampled)
            for (std::size_t k = 0; k < n; ++k) keys[k] = {(task.x0 + int(k) * step) * scale, y * scale, 0};
        trace(n);
        for (std::size_t k = 0; k < n; ++k) put(colours[k], out + 3 * k);
        return;
    }
    // A row of corners: only the pixels between them are traced.
    const bool usual = task.reuse == 2 * step && (task.x0 & mask) == 0;
    std::size_t m = 0;  // rays to trace
    if (usual) {
        // (The last coarse pass had twice this step, so the corners are every other
        // pixel from the first; the others are made at a stride of two.)
        m = n / 2;
        task.camera.unit_directions(task.x0 + step, 2 * step, int(m), y, dirs.data());
        if (sampled)
            for (std::size_t k = 0; k < m; ++k) keys[k] = {task.x0 + step + int(k) * 2 * step, y, 0};
    } else {
        for (std::size_t k = 0; k < n; ++k) {
            const int x = task.x0 + int(k) * step;
            if ((x & mask) != 0) {
                if (sampled) keys[m] = {x, y, 0};
                task.camera.unit_directions(x, step, 1, y, &dirs[m++]);
            }
        }
    }
    // The corners' colours were written a pass ago and have left the caches: they are
    // fetched while the others are traced.
    const float* corners = film.preview.data() + film.preview_index(task.x0, y);
    prefetch<false>(corners, film.preview.data() + film.preview_index(task.x0 + int(n - 1) * step, y) + 3);
    trace(m);
    const Colour* c = colours.data();
    if (usual) {
        // Corner, traced, corner, ...: the corners lie 3 step floats apart in the preview
        // (their x are 2 step apart, and a preview row holds every other pixel).
        const std::size_t stride = 3 * std::size_t(step);
        for (std::size_t k = 0; k < n; k += 2, out += 6, corners += stride, ++c) {
            out[0] = zero + corners[0], out[1] = zero + corners[1], out[2] = zero + corners[2];
            if (k + 1 < n) put(*c, out + 3);
        }
        return;
    }
    for (std::size_t k = 0; k < n; ++k, out += 3) {
        const int x = task.x0 + int(k) * step;
        if ((x & mask) != 0) {
            put(*c++, out);
        } else {
            const float* p = &film.preview[film.preview_index(x, y)];
            out[0] = zero + p[0], out[1] = zero + p[1], out[2] = zero + p[2];
        }
    }
}
}  // namespace

namespace {
// A band of a decision pass: its rows' marks, and how many each of its tiles got.
void decide_band(const Film& film, const RenderTask& task) {
    AdaptiveJob& aa = *task.aa;
    const std::uint8_t* changed = aa.first ? nullptr : aa.changed.data();
    decide_rows(film, aa.threshold, aa.max_samples, changed, task.y0, task.y1, aa.active.data());
    int* marked = &aa.marked[std::size_t(task.y0 / aa.tile) * std::size_t(aa.cols)];
    std::fill(marked, marked + aa.cols, 0);
    for (int y = task.y0; y < task.y1; ++y) {
        const std::uint8_t* row = &aa.active[std::size_t(y) * film.width];
        for (int x = 0; x < film.width; ++x) marked[x / aa.tile] += row[x];
    }
}
}  // namespace

bool Renderer::run_task(const RenderTask& task, std::vector<float>& buf, RayStats& stats) {
    auto cancelled = [&] {
        return stats.stopped || cancel_gen_.load(std::memory_order_relaxed) != task.generation;
    };
    switch (task.kind) {
        case PassKind::Samples:
            return run_samples(task, buf, stats);
        case PassKind::Refine:
            return run_refine(task, buf, stats);
        case PassKind::Decide:
            // The film is not written during this pass: every task reads it freely.
            if (cancelled()) return false;
            decide_band(film_, task);
            return !cancelled();
        case PassKind::Ids: {
            // Each pixel's id, its bits in the float buffer (copied, never computed with).
            const int w = task.x1 - task.x0;
            buf.resize(std::size_t(w) * std::size_t(task.y1 - task.y0));
            for (int y = task.y0; y < task.y1; ++y) {
                if (cancelled()) return false;
                for (int x = task.x0; x < task.x1; ++x) {
                    const Ray ray = task.camera.ray(double(x) * task.step, double(y) * task.step);
                    const std::uint32_t id = pick_id(pick(*task.world, ray));
                    std::memcpy(&buf[std::size_t(y - task.y0) * w + std::size_t(x - task.x0)], &id, sizeof id);
                }
            }
            return !cancelled();
        }
        case PassKind::Coarse:
            break;
    }
    // One colour per block, for its corner pixel, blocks in rows.
    int w = task.x1 - task.x0, h = task.y1 - task.y0;
    int b = task.block;
    buf.resize(std::size_t((w + b - 1) / b) * ((h + b - 1) / b) * 3);
    float* out = buf.data();
    const std::size_t n = row_count(task, b);
    for (int by = task.y0; by < task.y1; by += b, out += 3 * n) {
        first_samples<false>(task, film_, by, b, stats, out);
        if (cancelled()) return false;
    }
    return !cancelled();
}

bool Renderer::run_samples(const RenderTask& task, std::vector<float>& buf, RayStats& stats) {
    const World& world = *task.world;
    int w = task.x1 - task.x0, h = task.y1 - task.y0;
    // (The traces poll the stop flag and the deadline themselves and set stats.stopped.)
    auto cancelled = [&] {
        return stats.stopped || cancel_gen_.load(std::memory_order_relaxed) != task.generation;
    };
    buf.resize(std::size_t(w) * h * 3);
    // Sample pass: continue each pixel's running sum. The sums of this tile are only
    // touched by this task until it commits, so reading them unlocked is safe.
    for (int y = task.y0; y < task.y1; ++y) {
        // The commit (under the lock) writes the row's sums and counts, which the last
        // pass left out of the caches: they are fetched while the tile is traced.
        const std::size_t row = std::size_t(y) * film_.width + task.x0;
        prefetch<true>(film_.sum.data() + 3 * row, film_.sum.data() + 3 * (row + w));
        prefetch<true>(film_.count.data() + row, film_.count.data() + row + w);
        float* const row_sums = &buf[3 * std::size_t(y - task.y0) * w];
        if (task.s0 == 0 && task.s1 == 1) {
            // One sample a pixel, all traced: the row's sums as the loop below makes them.
            first_samples<true>(task, film_, y, 1, stats, row_sums);
            if (cancelled()) return false;
            continue;
        }
        if (task.s0 == 0) first_samples<false>(task, film_, y, 1, stats, row_sums);
        for (int x = task.x0; x < task.x1; ++x) {
            if (cancelled()) return false;
            std::size_t idx = std::size_t(y) * film_.width + x;
            float acc[3] = {0, 0, 0};
            if (task.s0 > 0) {
                acc[0] = film_.sum[3 * idx], acc[1] = film_.sum[3 * idx + 1], acc[2] = film_.sum[3 * idx + 2];
            }
            int s = task.s0;
            if (s == 0) {
                // (Sample 0 is the pixel's corner: sample_offset gives 0, 0.)
                const float* c = &row_sums[3 * (x - task.x0)];
                acc[0] += c[0], acc[1] += c[1], acc[2] += c[2];
                ++s;
            }
            accumulate_pixel(world, task.camera, x, y, s, task.s1, acc, stats);
            float* p = &buf[3 * (std::size_t(y - task.y0) * w + (x - task.x0))];
            p[0] = acc[0], p[1] = acc[1], p[2] = acc[2];
        }
    }
    return !cancelled();
}

// A refine task: the marked pixels of its tile into buf (the tile's sums, 3 floats a
// pixel, then its squares); what the others hold there is not used.
bool Renderer::run_refine(const RenderTask& task, std::vector<float>& buf, RayStats& stats) {
    const AdaptiveJob& aa = *task.aa;
    const int w = task.x1 - task.x0, h = task.y1 - task.y0;
    const std::size_t n = std::size_t(w) * std::size_t(h);
    buf.resize(4 * n);
    thread_local std::vector<std::uint32_t> n0, n1;
    n0.resize(n);
    n1.resize(n);
    for (int y = task.y0; y < task.y1; ++y) {
        const std::size_t idx = std::size_t(y) * film_.width + task.x0, k0 = std::size_t(y - task.y0) * w;
        for (int k = 0; k < w; ++k) {
            n0[k0 + k] = film_.count[idx + k];
            n1[k0 + k] = aa.active[idx + k] ? refine_count(n0[k0 + k], std::uint32_t(aa.max_samples)) : n0[k0 + k];
        }
        std::copy_n(&film_.sum[3 * idx], 3 * w, &buf[3 * k0]);
        std::copy_n(&film_.squares[idx], w, &buf[3 * n + k0]);
    }
    refine_rect(*task.world, task.camera, task.x0, task.y0, w, h, n0.data(), n1.data(), buf.data(), &buf[3 * n],
                stats);
    return !stats.stopped && cancel_gen_.load(std::memory_order_relaxed) == task.generation;
}

// Called with mutex_ held: a finished sample or refine task's pixels into the film.
void Renderer::commit_film(const RenderTask& task, const std::vector<float>& buf) {
    Job& job = *job_;
    const int w = task.x1 - task.x0, h = task.y1 - task.y0;
    for (int y = task.y0; y < task.y1; ++y) {
        const std::size_t idx = std::size_t(y) * film_.width + task.x0;
        const float* row = &buf[3 * std::size_t(y - task.y0) * w];
        if (task.kind == PassKind::Samples && job.bytes) {
            // (The bytes row_rgb8 would make of one-sample pixels.)
            sums_to_bytes(row, 3 * std::size_t(w), film_bytes_.data() + 3 * idx);
            job.film_samples += std::uint64_t(w);
            continue;
        }
        if (task.kind == PassKind::Samples) {
            std::copy(row, row + 3 * w, film_.sum.data() + 3 * idx);
            std::fill_n(film_.count.data() + idx, w, std::uint32_t(task.s1));
            job.film_samples += std::uint64_t(w) * std::uint64_t(task.s1 - task.s0);
            continue;
        }
        const AdaptiveJob& aa = *task.aa;
        const float* squares = &buf[3 * std::size_t(w) * h + std::size_t(y - task.y0) * w];
        for (int k = 0; k < w; ++k) {
            if (!aa.active[idx + k]) continue;
            std::uint32_t& n = film_.count[idx + k];
            const std::uint32_t to = refine_count(n, std::uint32_t(aa.max_samples));
            job.film_samples += to - n;
            n = to;
            std::copy_n(row + 3 * k, 3, &film_.sum[3 * (idx + k)]);
            film_.squares[idx + k] = squares[k];
        }
    }
}

// Called with mutex_ held, for a task of the current job.
void Renderer::commit(const RenderTask& task, const std::vector<float>& buf) {
    Job& job = *job_;
    if (task.kind == PassKind::Coarse) {
        // A row's corners lie block / 2 entries apart in the preview: side by side at 2.
        const float* c = buf.data();
        const int b = task.block, n = (task.x1 - task.x0 + b - 1) / b;
        const std::size_t stride = 3 * std::size_t(b / 2);
        for (int y = task.y0; y < task.y1; y += b, c += 3 * n) {
            float* out = film_.preview.data() + film_.preview_index(task.x0, y);
            if (b == 2) {
                std::copy(c, c + 3 * n, out);
                continue;
            }
            for (int k = 0; k < n; ++k, out += stride)
                out[0] = c[3 * k], out[1] = c[3 * k + 1], out[2] = c[3 * k + 2];
        }
    } else if (task.kind == PassKind::Ids) {
        const int w = task.x1 - task.x0;
        for (int y = task.y0; y < task.y1; ++y) {
            const std::size_t idx = std::size_t(y) * film_.width + task.x0;
            std::memcpy(film_.ids.data() + idx, &buf[std::size_t(y - task.y0) * w], sizeof(std::uint32_t) * w);
            std::fill_n(film_.count.data() + idx, w, 1u);
        }
        job.film_samples += std::uint64_t(w) * std::uint64_t(task.y1 - task.y0);
    } else if (task.kind != PassKind::Decide) {
        commit_film(task, buf);
    }
    // A coarse tile changes nothing on screen until its whole pass is done (the screen
    // shows the last complete level, whose corners the pass only traces again); a
    // decision changes nothing at all.
    if (task.kind != PassKind::Decide) ++film_version_;
    if (task.kind == PassKind::Samples || task.kind == PassKind::Refine || task.kind == PassKind::Ids) {
        changes_.push_back({film_version_, {task.x0, task.y0, task.x1, task.y1}});
        if (changes_.size() > kMaxChanges) {
            full_version_ = std::max(full_version_, changes_.front().first);
            changes_.pop_front();
        }
    }
    if (++job.tiles_done < job.tiles.size()) return;
    // The pass is complete.
    const Pass& p = job.passes[job.pass];
    double elapsed = std::chrono::duration<double>(Clock::now() - job.start).count();
    ++job.passes_done;
    job.preview_valid = true;
    if (p.kind == PassKind::Coarse) {
        if (job.first_coarse_time < 0) job.first_coarse_time = elapsed;
        job.coarse_level = p.block;
        film_.preview_level = p.block;
        full_version_ = ++film_version_;
        changes_.clear();
    } else if (p.kind == PassKind::Samples || p.kind == PassKind::Ids) {
        job.samples_done = p.s1;
    }
    bool out_of_time = job.settings.time_limit > 0 && elapsed >= job.settings.time_limit;
    const bool stop = out_of_time && (job.samples_done > 0 || job.settings.hard_time_limit);
    if (stop || !next_pass_locked(job)) {
        finish_locked(job);
        return;
    }
    // Out of time in the previews: straight on to the first sample.
    while (out_of_time && job.passes[job.pass].kind == PassKind::Coarse) ++job.pass;
    begin_pass_locked(job);
    kick_locked();
}

// Called with mutex_ held, when the current pass is complete: moves on to the next
// pass; false if there is none. An adaptive render decides after the first sample and
// after every refinement, and is over once a decision marks no pixel.
bool Renderer::next_pass_locked(Job& job) {
    if (job.settings.refine_marked) return false;  // a tile's one round
    const PassKind kind = job.passes[job.pass].kind;
    if (job.aa && job.raise_to > 0 && kind != PassKind::Coarse) {
        raise_locked(job);
        // After a decision made with the old limit: a decision with the new one next.
        if (kind == PassKind::Decide) {
            job.passes.resize(job.pass + 1);
            job.passes.push_back({PassKind::Decide, 0, 0, 0});
            job.passes.push_back({PassKind::Refine, 0, 0, 0});
            return ++job.pass < job.passes.size();
        }
    }
    if (job.aa && kind == PassKind::Decide) {
        AdaptiveJob& aa = *job.aa;
        aa.first = false;
        aa.refining = 0;
        for (int m : aa.marked) aa.refining += m;
        if (aa.refining == 0) return false;
    }
    // The next decision reads what this refinement changed, and marks afresh.
    if (job.aa && kind == PassKind::Refine) {
        job.aa->active.swap(job.aa->changed);
        ++job.aa->refinements;
    }
    if (job.aa && kind != PassKind::Coarse && kind != PassKind::Decide && job.pass + 1 == job.passes.size()) {
        job.passes.push_back({PassKind::Decide, 0, 0, 0});
        job.passes.push_back({PassKind::Refine, 0, 0, 0});
    }
    return ++job.pass < job.passes.size();
}

// Called with mutex_ held: the job is over; workers still inside it stop at once.
void Renderer::finish_locked(Job& job) {
    job.done = true;
    job.done_time = std::chrono::duration<double>(Clock::now() - job.start).count();
    job.stop->store(true);
    done_cv_.notify_all();
}

RenderProgress Renderer::progress() const {
    std::lock_guard<std::mutex> lock(mutex_);
    RenderProgress r;
    r.paused = paused_;
    if (!job_) return r;
    const Job& j = *job_;
    r.generation = j.generation;
    r.coarse_level = j.coarse_level;
    r.samples = j.samples_done;
    r.passes = j.passes_done;
    r.pass_fraction = j.tiles.empty() ? 1.0 : double(j.tiles_done) / double(j.tiles.size());
    r.rays = j.rays;
    r.elapsed = j.done ? j.done_time : std::chrono::duration<double>(Clock::now() - j.start).count();
    r.first_coarse_time = j.first_coarse_time;
    r.running = !j.done && !j.paused;
    r.done = j.done;
    r.width = j.width;
    r.height = j.height;
    r.refining = j.aa ? j.aa->refining : -1;
    r.refinements = j.aa ? j.aa->refinements : 0;
    r.film_samples = j.film_samples;
    r.error = j.error;
    return r;
}

double progress_fraction(const RenderProgress& p, int max_samples) {
    if (p.done) return 1;
    if (p.refining >= 0) {
        if (p.samples == 0) return 0.5 * p.pass_fraction;
        return 1 - 0.5 * std::pow(0.5, p.refinements) * (1 - 0.5 * p.pass_fraction);
    }
    const double n = std::max(1, max_samples);
    return std::clamp((p.samples + p.pass_fraction * (n - p.samples)) / n, 0.0, 1.0);
}

int Renderer::sample_count(int x, int y) const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (x < 0 || y < 0 || x >= film_.width || y >= film_.height) return 0;
    return int(film_.count[std::size_t(y) * film_.width + x]);
}

bool Renderer::pixel(int x, int y, int width, int height, Colour& c) const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (film_.width != width || film_.height != height || x < 0 || y < 0 || x >= width || y >= height) return false;
    const Colour p = film_.pixel(x, y, std::size_t(y) * film_.width + x);
    c = Colour(float(p.x), float(p.y), float(p.z));  // as the float image of snapshot() holds it
    return true;
}

std::uint64_t Renderer::snapshot_window(const PixelWindow& window, Image& out,
                                       std::vector<std::uint32_t>& counts) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const int x0 = std::clamp(window.x0, 0, film_.width), x1 = std::clamp(window.x1, x0, film_.width);
    const int y0 = std::clamp(window.y0, 0, film_.height), y1 = std::clamp(window.y1, y0, film_.height);
    out.width = x1 - x0;
    out.height = y1 - y0;
    out.rgb.resize(3 * std::size_t(out.width) * std::size_t(out.height));
    counts.resize(std::size_t(out.width) * std::size_t(out.height));
    std::size_t k = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x, ++k) {
            const std::size_t idx = std::size_t(y) * film_.width + x;
            const Colour c = film_.pixel(x, y, idx);
            out.rgb[3 * k] = float(c.x), out.rgb[3 * k + 1] = float(c.y), out.rgb[3 * k + 2] = float(c.z);
            counts[k] = film_.count[idx];
        }
    return film_version_;
}

void Renderer::load_window(int width, int height, const PixelWindow& window, const float* sums,
                           const std::uint32_t* counts, const float* squares, const std::uint8_t* marked) {
    cancel();
    std::lock_guard<std::mutex> lock(mutex_);
    if (film_.width != width || film_.height != height) film_.reset(width, height, false);
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    if (squares && film_.squares.size() != pixels) film_.squares.reset(pixels);
    if (marked) {
        if (loaded_marks_.size() != pixels) loaded_marks_.reset(pixels);
        std::fill(loaded_marks_.begin(), loaded_marks_.end(), std::uint8_t(0));
    }
    const int w = window.width();
    for (int y = window.y0; y < window.y1; ++y) {
        const std::size_t idx = std::size_t(y) * std::size_t(width) + std::size_t(window.x0);
        const std::size_t k = std::size_t(y - window.y0) * std::size_t(w);
        std::copy_n(sums + 3 * k, 3 * w, &film_.sum[3 * idx]);
        std::copy_n(counts + k, w, &film_.count[idx]);
        if (squares) std::copy_n(squares + k, w, &film_.squares[idx]);
        if (marked) std::copy_n(marked + k, w, &loaded_marks_[idx]);
    }
}

void Renderer::read_window(const PixelWindow& window, float* sums, float* squares) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const int w = window.width();
    for (int y = window.y0; y < window.y1; ++y) {
        const std::size_t idx = std::size_t(y) * std::size_t(film_.width) + std::size_t(window.x0);
        const std::size_t k = std::size_t(y - window.y0) * std::size_t(w);
        std::copy_n(&film_.sum[3 * idx], 3 * w, sums + 3 * k);
        if (squares) std::copy_n(&film_.squares[idx], w, squares + k);
    }
}

std::uint64_t Renderer::film_version() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return film_version_;
}

void Renderer::ids(std::vector<std::uint32_t>& out, int& width, int& height) const {
    std::lock_guard<std::mutex> lock(mutex_);
    width = film_.width;
    height = film_.height;
    out.assign(std::size_t(width) * std::size_t(height), 0u);
    if (!film_.ids.empty()) std::copy(film_.ids.begin(), film_.ids.end(), out.begin());
}

void Renderer::sample_counts(std::vector<std::uint32_t>& out, int& width, int& height) const {
    std::lock_guard<std::mutex> lock(mutex_);
    width = film_.width;
    height = film_.height;
    out.assign(film_.count.begin(), film_.count.end());
}

Image Renderer::snapshot(std::uint64_t* generation) const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (generation) *generation = job_ ? job_->generation : 0;
    return film_.resolve();
}

// Row y of the film as 8-bit RGB into out (3 bytes a pixel).
void Renderer::row_rgb8(int y, std::uint8_t* out) const {
    // Runs of one-sample pixels (every pixel of a finished one-sample render, most of
    // an adaptive one) in bulk; the others pixel by pixel.
    const std::size_t w = std::size_t(film_.width), first = std::size_t(y) * w;
    const std::uint32_t* count = film_.count.data() + first;
    for (std::size_t x = 0; x < w;) {
        std::size_t end = x;
        while (end < w && count[end] == 1) ++end;
        sums_to_bytes(film_.sum.data() + 3 * (first + x), 3 * (end - x), out + 3 * x);
        for (x = end; x < w && count[x] != 1; ++x) {
            // Through float, exactly as a snapshot() pixel would be.
            const Colour c = film_.pixel(int(x), y, first + x);
            std::uint8_t* o = out + 3 * x;
            o[0] = to_byte(float(c.x)), o[1] = to_byte(float(c.y)), o[2] = to_byte(float(c.z));
        }
    }
}

// A big picture is converted by as many threads as the renderer has: the command line
// waits for this between the render and the file.
int Renderer::rgb8_parts() const {
    const std::size_t n = std::size_t(film_.width) * std::size_t(film_.height);
    return int(std::min<std::size_t>(std::size_t(max_runners_), n / (1 << 18) + 1));
}

void Renderer::snapshot_rgb8(ZeroedArray<std::uint8_t>& out, int& width, int& height) const {
    std::lock_guard<std::mutex> lock(mutex_);
    width = film_.width;
    height = film_.height;
    out.reset(std::size_t(width) * std::size_t(height) * 3);
    const int parts = rgb8_parts();
    pool_->parallel_for(parts, [&](int k) {
        for (int y = height * k / parts; y < height * (k + 1) / parts; ++y)
            row_rgb8(y, &out[3 * std::size_t(y) * std::size_t(width)]);
    });
}

void Renderer::take_rgb8(ZeroedArray<std::uint8_t>& out, int& width, int& height) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (job_ && !job_->done) {
        // Still rendering: its tiles go on into the film, so a copy.
        lock.unlock();
        snapshot_rgb8(out, width, height);
        return;
    }
    // A task cut short by the end of the render may still be reading the film.
    idle_cv_.wait(lock, [&] { return busy_ == 0; });
    if (job_ && job_->bytes) {
        const bool taken = film_bytes_.empty();  // by an earlier call
        width = taken ? 0 : job_->width;
        height = taken ? 0 : job_->height;
        out.reset(0);
        out.swap(film_bytes_);
        film_.reset(0, 0);
        return;
    }
    width = film_.width;
    height = film_.height;
    const std::size_t w = std::size_t(width), n = w * std::size_t(height);
    if (n == 0 || film_.sum.size() != 3 * n) {
        out.reset(0);
        return;
    }
    // Each part's bytes first go to the start of its own rows' sums: row y's 3w bytes
    // end before row y + 1's floats begin, so a row is read (into `row`) before any of
    // its bytes are written and no later row is overwritten. Then the parts move down
    // to their places, in order: part k's bytes end where part k + 1's begin, far
    // below its floats.
    auto* bytes = reinterpret_cast<std::uint8_t*>(film_.sum.data());
    const int parts = rgb8_parts();
    pool_->parallel_for(parts, [&](int k) {
        thread_local std::vector<std::uint8_t> row;
        row.resize(3 * w);
        const int y0 = height * k / parts, y1 = height * (k + 1) / parts;
        std::uint8_t* to = bytes + 12 * std::size_t(y0) * w;
        for (int y = y0; y < y1; ++y, to += 3 * w) {
            row_rgb8(y, row.data());
            std::memcpy(to, row.data(), 3 * w);
        }
    });
    for (int k = 1; k < parts; ++k) {
        const std::size_t y0 = std::size_t(height * k / parts), y1 = std::size_t(height * (k + 1) / parts);
        std::memmove(bytes + 3 * y0 * w, bytes + 12 * y0 * w, 3 * (y1 - y0) * w);
    }
    out.adopt(film_.sum, 3 * n);
    film_.reset(0, 0);  // the next render starts from a new film
}

bool Renderer::snapshot_rgba8(std::vector<std::uint8_t>& out, int& width, int& height, std::uint64_t& version,
                              std::array<int, 4>* changed) const {
    std::lock_guard<std::mutex> lock(mutex_);
    // Until the new render has something to show, keep showing the old picture.
    if (!job_ || !job_->preview_valid || version == film_version_) return false;
    auto convert = [&](int x0, int y0, int x1, int y1) {
        for (int y = y0; y < y1; ++y) {
            std::size_t idx = std::size_t(y) * film_.width + x0;
            std::uint8_t* p = &out[4 * idx];
            for (int x = x0; x < x1; ++x, ++idx, p += 4) {
                Colour c = film_.pixel(x, y, idx);
                p[0] = to_byte(c.x), p[1] = to_byte(c.y), p[2] = to_byte(c.z), p[3] = 255;
            }
        }
    };
    const std::size_t n = std::size_t(film_.width) * film_.height;
    const bool full = out.size() != n * 4 || width != film_.width || height != film_.height ||
                      version < full_version_ || version > film_version_;
    width = film_.width;
    height = film_.height;
    std::array<int, 4> box{width, height, 0, 0};
    if (full) {
        out.resize(n * 4);
        convert(0, 0, width, height);
        box = {0, 0, width, height};
    } else {
        // The log is in version order: convert the tiles committed after `version`.
        auto it = std::upper_bound(changes_.begin(), changes_.end(), version,
                                   [](std::uint64_t v, const auto& e) { return v < e.first; });
        for (; it != changes_.end(); ++it) {
            const auto& r = it->second;
            convert(r[0], r[1], r[2], r[3]);
            box = {std::min(box[0], r[0]), std::min(box[1], r[1]), std::max(box[2], r[2]), std::max(box[3], r[3])};
        }
        if (box[0] >= box[2]) box = {0, 0, 0, 0};
    }
    if (changed) *changed = box;
    version = film_version_;
    return true;
}

}  // namespace rt
