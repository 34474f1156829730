// TilePool: the threads take chunks of pixels of the oldest unfinished tile from its
// counter; a tile is complete when all its pixels are handed out and the last thread
// inside it has checked out.
#include "tile_pool.h"


#include <algorithm>

#include "adaptive.h"
#include "renderer.h"

namespace rtmpi {

namespace {
// Pixels per chunk: enough to make the atomic counter's cost vanish next to tracing
// (a pixel is hundreds of ns at least), few enough that a 32x32 tile still splits
// into 128 chunks for the threads to balance.
constexpr int kChunk = 8;
}  // namespace

std::vector<Tile> make_tiles(int width, int height, int side) {
    std::vector<Tile> tiles;
    for (int y = 0; y < height; y += side)
        for (int x = 0; x < width; x += side)
            tiles.push_back({x, y, std::min(x + side, width), std::min(y + side, height)});
    // The same comparison as rt::Renderer's centre-out order (stable, so ties stay in
    // scanline order): not needed for the pixels' values, only for what fills first.
    const double cx = width / 2.0, cy = height / 2.0;
    std::stable_sort(tiles.begin(), tiles.end(), [&](const Tile& a, const Tile& b) {
        double ax = (a.x0 + a.x1) / 2.0 - cx, ay = (a.y0 + a.y1) / 2.0 - cy;
        double bx = (b.x0 + b.x1) / 2.0 - cx, by = (b.y0 + b.y1) / 2.0 - cy;
        return ax * ax + ay * ay < bx * bx + by * by;
    });
    return tiles;
}

TilePool::TilePool(const rt::World& world, const rt::CameraBasis& camera, rt::ThreadPool& pool)
    : world_(world), camera_(camera), nthreads_(pool.workers()), pool_(pool) {}

TilePool::~TilePool() {
    std::unique_lock<std::mutex> lock(mutex_);
    quit_ = true;
    stop_ = true;
    // Runners still waiting in the pool hold `this`: each ends at once.
    idle_cv_.wait(lock, [&] { return runners_ == 0; });
}

void TilePool::kick_locked() {
    while (!quit_ && runners_ < nthreads_) {
        ++runners_;
        pool_.post([this] { run(); });
    }
}

void TilePool::submit(int id, const Tile& tile, int s0, int s1, float* sums) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        Job& job = jobs_.emplace_back();
        job.id = id;
        job.tile = tile;
        job.s0 = s0;
        job.s1 = s1;
        job.sums = sums;
        ++outstanding_;
        kick_locked();
    }
}

void TilePool::submit_refine(int id, const Tile& tile, const std::uint32_t* n0, const std::uint32_t* n1, float* sums,
                             float* squares) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        Job& job = jobs_.emplace_back();
        job.id = id;
        job.tile = tile;
        job.n0 = n0;
        job.n1 = n1;
        job.sums = sums;
        job.squares = squares;
        ++outstanding_;
        kick_locked();
    }
}

std::vector<TilePool::Finished> TilePool::take_finished() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<Finished> out;
    out.swap(finished_);
    outstanding_ -= int(out.size());
    return out;
}

void TilePool::wait_finished(std::chrono::microseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    done_cv_.wait_for(lock, timeout, [&] { return !finished_.empty(); });
}

int TilePool::outstanding() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return outstanding_;
}

// Pixels [p0, p1) of the job's tile (counted row by row).
void TilePool::render_pixels(Job& job, int p0, int p1, rt::RayStats& stats) const {
    const Tile& tile = job.tile;
    const int w = tile.x1 - tile.x0;
    if (!job.n0) {
        for (int p = p0; p < p1; ++p) {
            // accumulate_pixel is the one definition of a pixel's value; it continues
            // the running float sum in sample order, exactly as rt::Renderer does.
            rt::accumulate_pixel(world_, camera_, tile.x0 + p % w, tile.y0 + p / w, job.s0, job.s1, &job.sums[3 * p],
                                 stats);
        }
        return;
    }
    // A refine job: the pixels in runs along their rows, as rt::Renderer refines them.
    for (int p = p0; p < p1;) {
        const int run = std::min(p1, (p / w + 1) * w) - p;
        rt::refine_row(world_, camera_, tile.x0 + p % w, tile.y0 + p / w, run, job.n0 + p, job.n1 + p,
                       job.sums + 3 * p, job.squares + p, stats);
        p += run;
    }
}

void TilePool::run() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
        // The oldest job with pixels left; finished jobs leave the list at once.
        Job* job = nullptr;
        for (Job& j : jobs_)
            if (j.next.load(std::memory_order_relaxed) < j.tile.pixels()) {
                job = &j;
                break;
            }
        if (quit_ || !job) {
            // Nothing left to hand out: the next submit() posts runners again.
            if (--runners_ == 0) idle_cv_.notify_all();
            return;
        }
        ++job->workers;  // under the lock: nobody can finish the job under our feet
        lock.unlock();

        const int n = job->tile.pixels();
        rt::RayStats stats;
        stats.stop.flag = &stop_;
        for (int i = job->next.fetch_add(kChunk, std::memory_order_relaxed); i < n;
             i = job->next.fetch_add(kChunk, std::memory_order_relaxed))
            render_pixels(*job, i, std::min(i + kChunk, n), stats);

        lock.lock();
        job->rays += stats.rays;
        // Every pixel is handed out (next only grows) and nobody else is inside: done.
        if (--job->workers == 0) {
            finished_.push_back({job->id, job->rays});
            for (auto it = jobs_.begin(); it != jobs_.end(); ++it)
                if (&*it == job) {
                    jobs_.erase(it);
                    break;
                }
            done_cv_.notify_all();
        }
    }
}

}  // namespace rtmpi
