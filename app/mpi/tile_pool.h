// Tiles and the per-rank thread pool that renders them with all cores.
// Every rank, rank 0 included, renders through TilePool, so a pixel's float sums are
// the same whichever rank rendered it, and the same as rt::Renderer's.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <list>
#include <mutex>
#include <vector>

#include "camera.h"
#include "parallel.h"
#include "world.h"

namespace rtmpi {

// Pixels [x0, x1) x [y0, y1).
struct Tile {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    int pixels() const { return (x1 - x0) * (y1 - y0); }
};

// The picture cut into side x side tiles, centre first (the order rt::Renderer uses),
// so the interesting part fills first. Every rank computes the same list, so a tile
// travels as its index.
std::vector<Tile> make_tiles(int width, int height, int side);

// Renders queued tiles on the workers of a thread pool (rt::ThreadPool). All of them
// work on the oldest tile that still has pixels to hand out, then go straight on to
// the next queued one: a thread never waits for the caller between tiles (on a busy
// machine every such wait costs a trip through the scheduler queue), so keep a tile
// or two queued.
class TilePool {
public:
    struct Finished {
        int id = 0;
        std::uint64_t rays = 0;
    };

    // Renders on all of `pool`'s workers (at least one); the pool must outlive it.
    TilePool(const rt::World& world, const rt::CameraBasis& camera, rt::ThreadPool& pool);
    ~TilePool();
    TilePool(const TilePool&) = delete;
    TilePool& operator=(const TilePool&) = delete;

    int threads() const { return nthreads_; }

    // Queues samples [s0, s1) of every pixel of `tile`, added to sums (3 floats per
    // pixel, row by row, already holding the sums of samples [0, s0)). sums must stay
    // alive and untouched until the tile comes back from take_finished(). Returns at once.
    void submit(int id, const Tile& tile, int s0, int s1, float* sums);
    // Queues a refine round's work on `tile` (adaptive anti-aliasing): per pixel, row
    // by row, samples [n0, n1) continuing its sums (3 floats) and squares (1), as
    // rt::refine_row takes them. The arrays must stay alive and untouched until the
    // tile comes back from take_finished().
    void submit_refine(int id, const Tile& tile, const std::uint32_t* n0, const std::uint32_t* n1, float* sums,
                       float* squares);
    // Tiles completed since the last call, in completion order.
    std::vector<Finished> take_finished();
    // Waits until a tile completes (or one is waiting to be taken), at most `timeout`.
    void wait_finished(std::chrono::microseconds timeout);
    // Tiles submitted and not yet taken back.
    int outstanding() const;

private:
    struct Job {
        int id = 0;
        Tile tile;
        int s0 = 0, s1 = 0;
        float* sums = nullptr;
        const std::uint32_t *n0 = nullptr, *n1 = nullptr;  // a refine job's, else null
        float* squares = nullptr;
        std::atomic<int> next{0};  // next pixel to hand out
        int workers = 0;           // threads inside this job
        std::uint64_t rays = 0;
    };
    // Posts runners, up to threads(), while tiles wait.
    void kick_locked();
    // One pool task: renders the queued tiles, oldest first, until none is left.
    void run();
    void render_pixels(Job& job, int p0, int p1, rt::RayStats& stats) const;

    const rt::World& world_;
    const rt::CameraBasis& camera_;
    int nthreads_ = 0;
    rt::ThreadPool& pool_;  // nthreads_ workers
    mutable std::mutex mutex_;
    std::condition_variable idle_cv_, done_cv_;
    int runners_ = 0;  // posted and not yet ended (under mutex_)
    std::atomic<bool> stop_{false};  // set when the pool ends: the traces in progress stop
    std::list<Job> jobs_;  // queued or running, oldest first; list: addresses stay put
    std::vector<Finished> finished_;
    int outstanding_ = 0;
    bool quit_ = false;
};

}  // namespace rtmpi
