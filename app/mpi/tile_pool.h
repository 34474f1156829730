// A rank's tiles, and the queue that renders them: each queued tile is a request to
// rt::Renderer (a crop that goes on from the sums rank 0 holds), one after another.
// Every rank, rank 0 included, renders through it, so a pixel's float sums are the
// same whichever rank rendered it, and the same as a render on one machine.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <vector>

#include "camera.h"
#include "parallel.h"
#include "renderer.h"
#include "world.h"

namespace rtmpi {

// Pixels [x0, x1) x [y0, y1).
using Tile = rt::PixelWindow;

// The picture cut into side x side tiles, centre first (rt::tile_grid, the renderer's
// own), so the interesting part fills first. Every rank computes the same list, so a
// tile travels as its index.
std::vector<Tile> make_tiles(int width, int height, int side);

// Renders queued tiles with an rt::Renderer on the workers of a thread pool, oldest
// first. The caller's thread moves the queue on: take_finished() and wait_finished()
// collect a finished tile and start the next at once, so keep a tile or two queued.
class TilePool {
public:
    struct Finished {
        int id = 0;
        std::uint64_t rays = 0;
    };

    // Renders width x height pictures of `world` through `camera` (mirrored if asked)
    // on all of `pool`'s workers (at least one); the pool must outlive it.
    TilePool(std::shared_ptr<const rt::World> world, const rt::Camera& camera, int width, int height, bool mirror,
             int max_samples, rt::ThreadPool& pool);
    ~TilePool();
    TilePool(const TilePool&) = delete;
    TilePool& operator=(const TilePool&) = delete;

    int threads() const { return renderer_.threads(); }

    // Queues samples [s0, s1) of every pixel of `tile`, added to sums (3 floats per
    // pixel, row by row, already holding the sums of samples [0, s0)). sums must stay
    // alive and untouched until the tile comes back from take_finished(). Returns at once.
    void submit(int id, const Tile& tile, int s0, int s1, float* sums);
    // Queues a refine round's work on `tile` (adaptive anti-aliasing): per pixel, row
    // by row, samples [n0, n1) continuing its sums (3 floats) and squares (1), n1 being
    // refine_count(n0, max_samples) where the pixel is marked, n0 where not. The arrays
    // must stay alive and untouched until the tile comes back from take_finished().
    void submit_refine(int id, const Tile& tile, const std::uint32_t* n0, const std::uint32_t* n1, float* sums,
                       float* squares);
    // Tiles completed since the last call, in completion order.
    std::vector<Finished> take_finished();
    // Waits until a tile completes (or one is waiting to be taken), at most `timeout`.
    void wait_finished(std::chrono::microseconds timeout);
    // Tiles submitted and not yet taken back.
    int outstanding() const { return outstanding_; }

private:
    struct Job {
        int id = 0;
        Tile tile;
        int s0 = 0, s1 = 0;
        float* sums = nullptr;
        const std::uint32_t *n0 = nullptr, *n1 = nullptr;  // a refine job's, else null
        float* squares = nullptr;
    };
    // A job (its own fields set) with its id, tile and sums, to the queue's end.
    void queue(Job job, int id, const Tile& tile, float* sums);
    // The running tile's result, if it is done, into its buffers; then the next tile.
    void advance();
    void start_front();

    std::shared_ptr<const rt::World> world_;
    rt::Camera camera_;
    int width_, height_;
    bool mirror_;
    int max_samples_;
    rt::Renderer renderer_;
    std::deque<Job> jobs_;  // queued; the front one renders while running_
    bool running_ = false;
    std::vector<Finished> finished_;
    int outstanding_ = 0;
};

}  // namespace rtmpi
