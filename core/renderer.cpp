// Scheduling: a render is a list of passes, a pass a list of tiles. Workers take
// tiles of the current pass in order (centre first); the pass after it starts only
// when every tile of this one is committed, so each pixel sums its samples in order.
// Stopping: a task's traces poll its job's stop flag and, in the passes after the
// first sample, the time limit, so neither waits for a tile (or a pixel) to finish.
#include "renderer.h"

#include <algorithm>
#include <cmath>
#include <cstring>

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

struct RenderTask {
    std::uint64_t generation = 0;
    std::shared_ptr<const World> world;
    std::shared_ptr<const std::atomic<bool>> stop;  // the job's: set when it is cancelled or done
    Clock::time_point deadline = Clock::time_point::max();
    CameraBasis camera;
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    int block = 0;               // coarse pass: block size; 0 for a sample pass
    int s0 = 0, s1 = 0;          // sample pass: samples [s0, s1)
    int reuse = 0;               // block size (a power of 2) of the last coarse pass: its
                                 // corner pixels already hold sample 0 in the preview layer
};

struct Pass {
    int block = 0;
    int s0 = 0, s1 = 0;
};

struct Renderer::Job {
    std::uint64_t generation = 0;
    std::shared_ptr<const World> world;
    std::shared_ptr<std::atomic<bool>> stop = std::make_shared<std::atomic<bool>>(false);
    RenderSettings settings;
    CameraBasis camera;
    int width = 0, height = 0;
    Clock::time_point start;
    Clock::time_point deadline = Clock::time_point::max();  // start + time limit
    std::vector<Pass> passes;       // the fixed ones; sample passes are appended as needed
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
};

void sample_offset(int x, int y, int s, double& dx, double& dy) {
    if (s == 0) {
        dx = dy = 0;
        return;
    }
    // Halton (2, 3) points, rotated per pixel by a hash so that neighbouring pixels do
    // not share a pattern; centred on the original's sample point.
    auto radical = [](unsigned i, unsigned base) {
        double f = 1, r = 0;
        while (i > 0) {
            f /= base;
            r += f * (i % base);
            i /= base;
        }
        return r;
    };
    std::uint32_t h = std::uint32_t(x) * 0x8da6b343u ^ std::uint32_t(y) * 0xd8163841u;
    h ^= h >> 15;
    h *= 0x2c1b3c6du;
    h ^= h >> 12;
    double rx = (h & 0xffff) / 65536.0, ry = (h >> 16) / 65536.0;
    double u = radical(unsigned(s), 2) + rx, v = radical(unsigned(s), 3) + ry;
    dx = u - std::floor(u) - 0.5;
    dy = v - std::floor(v) - 0.5;
}

void accumulate_pixel(const World& world, const CameraBasis& camera, int x, int y, int s0, int s1, float acc[3],
                      RayStats& stats) {
    for (int s = s0; s < s1; ++s) {
        double dx, dy;
        sample_offset(x, y, s, dx, dy);
        Colour c = world.trace_camera(camera, x + dx, y + dy, stats);
        acc[0] += float(c.x), acc[1] += float(c.y), acc[2] += float(c.z);
    }
}

Renderer::Renderer(int threads) {
    if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
    for (int i = 0; i < threads; ++i) workers_.emplace_back([this] { worker_main(); });
}

Renderer::~Renderer() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        quit_ = true;
        ++cancel_gen_;
        if (job_) job_->stop->store(true);
    }
    work_cv_.notify_all();
    for (auto& t : workers_) t.join();
}

void Renderer::begin_pass_locked(Job& job) {
    job.tiles.clear();
    job.next_tile = job.tiles_done = 0;
    int ts = std::max(8, job.settings.tile_size / 8 * 8);  // coarse blocks never straddle tiles
    // Coarse passes trace one ray per block: their tiles grow with the block so that a
    // task still holds enough rays to outweigh taking it from the queue.
    if (job.passes[job.pass].block > 0) ts = std::max(ts, ts * job.passes[job.pass].block / 2);
    for (int y = 0; y < job.height; y += ts)
        for (int x = 0; x < job.width; x += ts)
            job.tiles.push_back({x, y, std::min(x + ts, job.width), std::min(y + ts, job.height)});
    if (job.settings.order == TileOrder::CentreOut) {
        double cx = job.width / 2.0, cy = job.height / 2.0;
        std::stable_sort(job.tiles.begin(), job.tiles.end(), [&](const auto& a, const auto& b) {
            double ax = (a[0] + a[2]) / 2.0 - cx, ay = (a[1] + a[3]) / 2.0 - cy;
            double bx = (b[0] + b[2]) / 2.0 - cx, by = (b[1] + b[3]) / 2.0 - cy;
            return ax * ax + ay * ay < bx * bx + by * by;
        });
    }
}

void Renderer::start(std::shared_ptr<const World> world, const RenderSettings& settings) {
    cancel();
    std::lock_guard<std::mutex> lock(mutex_);
    auto job = std::make_shared<Job>();
    job->generation = cancel_gen_.load();
    job->world = world;
    job->settings = settings;
    job->settings.max_samples = std::max(1, settings.max_samples);
    job->width = settings.width > 0 ? settings.width : world->width;
    job->height = settings.height > 0 ? settings.height : world->height;
    job->camera = CameraBasis::make(settings.camera ? *settings.camera : world->camera, job->width, job->height,
                                    settings.mirror);
    job->start = Clock::now();
    if (settings.time_limit > 0)
        job->deadline = job->start + std::chrono::duration_cast<Clock::duration>(
                                         std::chrono::duration<double>(std::min(settings.time_limit, 1e9)));
    int first_block = 2;  // the largest power of 2 <= coarse_block (blocks are masks)
    while (first_block < 256 && first_block * 2 <= settings.coarse_block) first_block *= 2;
    if (settings.coarse)
        for (int b = first_block; b >= 2; b /= 2)
            if (job->width > b || job->height > b) job->passes.push_back({b, 0, 0});
    // Sample passes: the given batch, or 1, 1, 2, 4, 8, 16, 16, ... samples. Under a
    // time limit the first pass, which always completes, is one sample.
    int s = 0;
    while (s < job->settings.max_samples) {
        int n = settings.samples_per_pass > 0 ? settings.samples_per_pass : std::clamp(s, 1, 16);
        if (s == 0 && settings.time_limit > 0) n = 1;
        n = std::min(n, job->settings.max_samples - s);
        job->passes.push_back({0, s, s + n});
        s += n;
    }
    job->paused = paused_;
    steps_ = 0;
    if (film_.width != job->width || film_.height != job->height) {
        film_.reset(job->width, job->height, settings.coarse);
    } else {
        std::fill(film_.count.begin(), film_.count.end(), 0u);
        if (settings.coarse && film_.preview.empty()) film_.preview.reset(std::size_t(job->width) * job->height * 3);
    }
    film_.preview_level = 0;
    ++film_version_;
    full_version_ = film_version_;
    changes_.clear();
    begin_pass_locked(*job);
    job_ = job;
    work_cv_.notify_all();
}

void Renderer::cancel() {
    std::unique_lock<std::mutex> lock(mutex_);
    ++cancel_gen_;
    if (job_) job_->stop->store(true);
    job_.reset();
    done_cv_.notify_all();  // wait() returns: there is no render any more
    ++idle_waiters_;
    idle_cv_.wait(lock, [&] { return busy_ == 0; });
    --idle_waiters_;
}

void Renderer::set_paused(bool paused) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        paused_ = paused;
        steps_ = 0;
        if (job_) job_->paused = paused;
    }
    work_cv_.notify_all();
}

void Renderer::step(int tiles) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        steps_ += std::max(0, tiles);
    }
    work_cv_.notify_all();
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
    const bool limited = job.settings.hard_time_limit || (p.block == 0 && p.s0 > 0);
    task.deadline = limited ? job.deadline : Clock::time_point::max();
    task.camera = job.camera;
    task.x0 = t[0], task.y0 = t[1], task.x1 = t[2], task.y1 = t[3];
    task.block = p.block;
    task.s0 = p.s0, task.s1 = p.s1;
    task.reuse = job.coarse_level;
    return true;
}

void Renderer::worker_main() {
    std::vector<float> buf;
    std::unique_lock<std::mutex> lock(mutex_);
    while (!quit_) {
        RenderTask task;
        if (!next_task(task)) {
            work_cv_.wait(lock);
            continue;
        }
        ++busy_;
        lock.unlock();
        RayStats stats;
        stats.stop.flag = task.stop.get();
        stats.stop.deadline = task.deadline;
        bool complete = run_task(task, buf, stats);
        lock.lock();
        bool current = job_ && job_->generation == task.generation && !job_->done;
        if (current) job_->rays += stats.rays;
        if (complete && current) {
            commit(task, buf);
        } else if (current && Clock::now() >= task.deadline) {
            // Out of time in the middle of a pass: the tiles committed keep their extra
            // samples, the others the samples of the passes before.
            finish_locked(*job_);
        }
        task.world.reset();
        // cancel() waits for all idle; waiters for "done" are woken by commit() itself.
        if (--busy_ == 0 && idle_waiters_ > 0) idle_cv_.notify_all();
    }
}

namespace {
// Sample 0 of the pixels (x0 + k step, y) of the task's row, k < n: traced in one call,
// except where the last coarse pass traced the same ray (its blocks' corners), whose
// colour the preview holds (the same ray, so the same colour). The colours stay valid
// until the thread's next call.
const Colour* first_samples(const RenderTask& task, const Film& film, int y, int step, RayStats& stats,
                            std::size_t& n) {
    thread_local std::vector<Vec3> dirs, picked;
    thread_local std::vector<Colour> colours;
    // The row's camera rays, made before any is traced: independent square roots and
    // divisions overlap, where one at a time each would wait for the last.
    n = std::size_t((task.x1 - task.x0 + step - 1) / step);
    dirs.resize(n);
    task.camera.unit_directions(task.x0, step, int(n), y, dirs.data());
    colours.resize(n);
    Colour* c = colours.data();
    const World& world = *task.world;
    const int mask = task.reuse - 1;
    if (task.reuse == 0 || (y & mask) != 0) {
        world.trace_units(task.camera.origin, dirs.data(), n, stats, c);
        return c;
    }
    picked.clear();
    for (std::size_t k = 0; k < n; ++k)
        if (((task.x0 + int(k) * step) & mask) != 0) picked.push_back(dirs[k]);
    world.trace_units(task.camera.origin, picked.data(), picked.size(), stats, c);
    // The traced colours spread out to their places (from the right, in place), the
    // corners' in between.
    std::size_t j = picked.size();
    for (std::size_t k = n; k-- > 0;) {
        const int x = task.x0 + int(k) * step;
        if ((x & mask) != 0) {
            c[k] = c[--j];
        } else {
            const float* p = &film.preview[3 * (std::size_t(y) * film.width + x)];
            c[k] = {p[0], p[1], p[2]};
        }
    }
    return c;
}
}  // namespace

bool Renderer::run_task(const RenderTask& task, std::vector<float>& buf, RayStats& stats) {
    const World& world = *task.world;
    int w = task.x1 - task.x0, h = task.y1 - task.y0;
    // (The traces poll the stop flag and the deadline themselves and set stats.stopped.)
    auto cancelled = [&] {
        return stats.stopped || cancel_gen_.load(std::memory_order_relaxed) != task.generation;
    };
    if (task.block > 0) {
        // One colour per block, for its corner pixel, blocks in rows.
        int b = task.block;
        buf.resize(std::size_t((w + b - 1) / b) * ((h + b - 1) / b) * 3);
        float* out = buf.data();
        for (int by = task.y0; by < task.y1; by += b) {
            std::size_t n = 0;
            const Colour* c = first_samples(task, film_, by, b, stats, n);
            if (cancelled()) return false;
            for (std::size_t k = 0; k < n; ++k)
                *out++ = float(c[k].x), *out++ = float(c[k].y), *out++ = float(c[k].z);
        }
        return !cancelled();
    }
    buf.resize(std::size_t(w) * h * 3);
    // Sample pass: continue each pixel's running sum. The sums of this tile are only
    // touched by this task until it commits, so reading them unlocked is safe.
    for (int y = task.y0; y < task.y1; ++y) {
        std::size_t n = 0;
        const Colour* traced = task.s0 == 0 ? first_samples(task, film_, y, 1, stats, n) : nullptr;
        if (task.s0 == 0 && task.s1 == 1) {
            // One sample a pixel, all traced: the row's sums as the loop below makes
            // them (a sum that starts at 0, so -0 becomes 0 as there).
            if (cancelled()) return false;
            float* p = &buf[3 * std::size_t(y - task.y0) * w];
            for (int k = 0; k < w; ++k, p += 3) {
                p[0] = 0.0f + float(traced[k].x);
                p[1] = 0.0f + float(traced[k].y);
                p[2] = 0.0f + float(traced[k].z);
            }
            continue;
        }
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
                const Colour& c = traced[x - task.x0];
                acc[0] += float(c.x), acc[1] += float(c.y), acc[2] += float(c.z);
                ++s;
            }
            accumulate_pixel(world, task.camera, x, y, s, task.s1, acc, stats);
            float* p = &buf[3 * (std::size_t(y - task.y0) * w + (x - task.x0))];
            p[0] = acc[0], p[1] = acc[1], p[2] = acc[2];
        }
    }
    return !cancelled();
}

// Called with mutex_ held, for a task of the current job.
void Renderer::commit(const RenderTask& task, const std::vector<float>& buf) {
    Job& job = *job_;
    int w = task.x1 - task.x0;
    if (task.block > 0) {
        const float* c = buf.data();
        for (int y = task.y0; y < task.y1; y += task.block)
            for (int x = task.x0; x < task.x1; x += task.block, c += 3)
                std::copy(c, c + 3, &film_.preview[3 * (std::size_t(y) * film_.width + x)]);
    } else {
        for (int y = task.y0; y < task.y1; ++y) {
            std::size_t idx = std::size_t(y) * film_.width + task.x0;
            const float* row = &buf[3 * std::size_t(y - task.y0) * w];
            std::copy(row, row + 3 * w, film_.sum.data() + 3 * idx);
            std::fill_n(film_.count.data() + idx, w, std::uint32_t(task.s1));
        }
    }
    ++film_version_;
    // A coarse tile changes nothing on screen until its whole pass is done (the screen
    // shows the last complete level, whose corners the pass only traces again).
    if (task.block == 0) {
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
    if (p.block > 0) {
        if (job.first_coarse_time < 0) job.first_coarse_time = elapsed;
        job.coarse_level = p.block;
        film_.preview_level = p.block;
        full_version_ = ++film_version_;
        changes_.clear();
    } else {
        job.samples_done = p.s1;
    }
    bool out_of_time = job.settings.time_limit > 0 && elapsed >= job.settings.time_limit;
    const bool stop = out_of_time && (job.samples_done > 0 || job.settings.hard_time_limit);
    if (++job.pass >= job.passes.size() || stop) {
        finish_locked(job);
        return;
    }
    // Out of time in the previews: straight on to the first sample.
    while (out_of_time && job.passes[job.pass].block > 0) ++job.pass;
    begin_pass_locked(job);
    work_cv_.notify_all();
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
    return r;
}

Image Renderer::snapshot(std::uint64_t* generation) const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (generation) *generation = job_ ? job_->generation : 0;
    return film_.resolve();
}

void Renderer::snapshot_rgb8(ZeroedArray<std::uint8_t>& out, int& width, int& height) const {
    std::lock_guard<std::mutex> lock(mutex_);
    width = film_.width;
    height = film_.height;
    std::size_t n = std::size_t(width) * height;
    out.reset(n * 3);
    auto convert = [&](int y0, int y1) {
        // Rows of one sample a pixel (every pixel of a finished one-sample render) in
        // bulk; the others pixel by pixel.
        const std::size_t w = std::size_t(width);
        for (; y0 < y1; ++y0) {
            const std::size_t first = std::size_t(y0) * w;
            const std::uint32_t* count = film_.count.data() + first;
            if (!std::all_of(count, count + w, [](std::uint32_t c) { return c == 1; })) break;
            sums_to_bytes(film_.sum.data() + 3 * first, 3 * w, &out[3 * first]);
        }
        film_.for_each_pixel(y0, y1, [&](std::size_t i, const Colour& c) {
            // Through float, exactly as a snapshot() pixel would be.
            out[3 * i] = to_byte(float(c.x));
            out[3 * i + 1] = to_byte(float(c.y));
            out[3 * i + 2] = to_byte(float(c.z));
        });
    };
    // A big picture is converted by as many threads as the renderer has: the command
    // line waits for this between the render and the file.
    int parts = int(std::min<std::size_t>(workers_.size(), n / (1 << 18) + 1));
    std::vector<std::thread> helpers;
    for (int k = 1; k < parts; ++k) helpers.emplace_back(convert, height * k / parts, height * (k + 1) / parts);
    convert(0, height / parts);
    for (std::thread& t : helpers) t.join();
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
